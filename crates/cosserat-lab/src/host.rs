//! The machine and revision a report was generated on, for its provenance line.

use std::process::Command;

/// When, from which revision and on what a report was generated.
#[derive(Debug, Clone)]
pub struct Host {
    /// The UTC date and time, `YYYY-MM-DD HH:MM UTC` (empty if `date` is missing).
    pub date_time: String,
    /// The UTC date, `YYYY-MM-DD`.
    pub date: String,
    /// The short git revision of the checkout (empty outside a git checkout).
    pub rev: String,
    /// The CPU's model name (`unknown CPU` if the system does not say).
    pub cpu: String,
    /// The cores available to the process.
    pub cores: usize,
    /// The one-minute load average when the report was written (`None` where the system does not
    /// say): timings taken on a shared machine are upper bounds, and this says how shared it was.
    pub load: Option<f64>,
}

impl Host {
    /// The current machine, time and revision.
    pub fn current() -> Self {
        let date_time = command_output("date", &["-u", "+%Y-%m-%d %H:%M UTC"]);
        let date = date_time.split(' ').next().unwrap_or_default().to_string();
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("model name"))
                    .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
            })
            .unwrap_or_else(|| "unknown CPU".into());
        Self {
            date_time,
            date,
            rev: command_output("git", &["rev-parse", "--short", "HEAD"]),
            cpu,
            cores: std::thread::available_parallelism().map_or(0, |n| n.get()),
            load: std::fs::read_to_string("/proc/loadavg")
                .ok()
                .and_then(|s| s.split_whitespace().next().and_then(|l| l.parse().ok())),
        }
    }

    /// `CPU, N cores` and, where known, the load average when the report was written.
    pub fn machine(&self) -> String {
        match self.load {
            Some(load) => format!(
                "{}, {} cores (load average {load:.1} when written)",
                self.cpu, self.cores
            ),
            None => format!("{}, {} cores", self.cpu, self.cores),
        }
    }
}

/// A command's trimmed standard output, empty if it cannot run.
fn command_output(program: &str, args: &[&str]) -> String {
    Command::new(program)
        .args(args)
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default()
}
