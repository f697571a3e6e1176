//! Memory: what a scene will need, what the machine (or the user) allows, and the refusal of a run
//! that cannot fit, before anything large is allocated.
//!
//! A run that runs out of memory is ended by the operating system without a summary, so the simulator
//! checks first. The estimate is a lower bound from the number of unknowns: a run's peak grows about
//! linearly with them (a little faster, with the fill of the factor), and [`BYTES_PER_UNKNOWN`] is the
//! low end of that rate on the plate ladders of the bench table, so a run refused here could not have
//! finished, while one accepted may still need up to about twice the estimate.

use cosserat_scene::mesh_source::ElementBudget;
use cosserat_scene::spec::SceneSpec;
use std::fmt;

/// The lower bound of the peak memory per unknown (bytes): the system's Hessian with its assembly
/// maps, the factor, the state and the quadrature-point data.
pub const BYTES_PER_UNKNOWN: u64 = 4_000;

/// Memory that every run needs beside its unknowns (the program, thread pools, buffers).
const BASE_BYTES: u64 = 16 << 20;

/// A limit on the memory a run may use, with where it comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MemoryLimit {
    /// Bytes.
    pub bytes: u64,
    /// Where the limit comes from, for messages (`--max-memory`, `MemAvailable`, ...).
    pub source: String,
}

impl MemoryLimit {
    /// The smallest of `requested` (e.g. `--max-memory`) and what the machine allows: the memory the
    /// kernel reports as available, the process's address-space limit and its control group's limit.
    /// `None` when nothing is known (not Linux, no limit given).
    pub fn of_machine(requested: Option<u64>) -> Option<Self> {
        let mut limits: Vec<MemoryLimit> = Vec::new();
        if let Some(bytes) = requested {
            limits.push(MemoryLimit {
                bytes,
                source: "--max-memory".into(),
            });
        }
        if let Some(bytes) = meminfo_available() {
            limits.push(MemoryLimit {
                bytes,
                source: "the machine's available memory (MemAvailable)".into(),
            });
        }
        if let Some(bytes) = address_space_limit() {
            limits.push(MemoryLimit {
                bytes,
                source: "the process's address-space limit (ulimit -v)".into(),
            });
        }
        if let Some(bytes) = cgroup_limit() {
            limits.push(MemoryLimit {
                bytes,
                source: "the control group's memory limit (memory.max)".into(),
            });
        }
        limits.into_iter().min_by_key(|l| l.bytes)
    }

    /// The most mesh elements whose run could fit: every element brings at least three unknowns
    /// (a Tri3 mesh has about half as many vertices as triangles, with a position and a rotation each).
    /// Scene loading checks this before it builds a mesh, so that a mesh too large to simulate is not
    /// even built.
    pub fn element_budget(&self) -> ElementBudget {
        let per_element = 3 * BYTES_PER_UNKNOWN;
        let fits = self.bytes.saturating_sub(BASE_BYTES) / per_element;
        let default = ElementBudget::default();
        if fits >= default.max as u64 {
            return default;
        }
        ElementBudget {
            max: fits as usize,
            source: format!(
                "what fits into the {} allowed by {}",
                format_bytes(self.bytes),
                self.source
            ),
        }
    }
}

/// What a scene needs at least.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Unknowns of the system (three per displacement node and per rotation node).
    pub unknowns: u64,
    /// The lower bound of the peak resident memory \[bytes\].
    pub bytes: u64,
}

impl MemoryEstimate {
    /// The estimate for a validated scene, from its meshes (before the system is built).
    pub fn of_scene(spec: &SceneSpec) -> Self {
        let unknowns: u64 = spec
            .shells
            .iter()
            .map(|s| {
                let corners = s.mesh.corners.n_nodes() as u64;
                let disp = s.mesh.tri6.as_ref().map_or(corners, |t| t.n_nodes() as u64);
                let rot = if s.pair.rotation() == s.pair.displacement() {
                    disp
                } else {
                    corners
                };
                3 * (disp + rot)
            })
            .sum();
        Self {
            unknowns,
            bytes: BASE_BYTES.saturating_add(unknowns.saturating_mul(BYTES_PER_UNKNOWN)),
        }
    }

    /// An error if the estimate exceeds the limit.
    ///
    /// # Errors
    /// [`TooLarge`] naming the estimate, the limit and where the limit comes from.
    pub fn check(&self, limit: &MemoryLimit) -> Result<(), TooLarge> {
        if self.bytes > limit.bytes {
            Err(TooLarge {
                estimate: *self,
                limit: limit.clone(),
            })
        } else {
            Ok(())
        }
    }
}

/// A scene that needs more memory than allowed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TooLarge {
    /// What the scene needs at least.
    pub estimate: MemoryEstimate,
    /// What is allowed.
    pub limit: MemoryLimit,
}

impl fmt::Display for TooLarge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the scene has {} unknowns and needs at least {} of memory, more than the {} allowed by {}; \
             use a coarser mesh (or raise the limit)",
            self.estimate.unknowns,
            format_bytes(self.estimate.bytes),
            format_bytes(self.limit.bytes),
            self.limit.source
        )
    }
}

impl std::error::Error for TooLarge {}

/// `bytes` in the largest binary unit that keeps a number of at least 1 (`3.2 GiB`).
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

/// Parses a size such as `3G`, `512M`, `1.5GiB` or `2000000000` (binary units: K = 1024).
///
/// # Errors
/// A message saying what is wrong.
pub fn parse_size(text: &str) -> Result<u64, String> {
    let text = text.trim();
    let split = text.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(text.len());
    let (number, unit) = text.split_at(split);
    let number: f64 = number
        .parse()
        .map_err(|_| format!("`{text}` is not a size: give a number with an optional unit, e.g. 3G or 512M"))?;
    let scale: u64 = match unit.trim().to_ascii_uppercase().as_str() {
        "" | "B" => 1,
        "K" | "KB" | "KIB" => 1 << 10,
        "M" | "MB" | "MIB" => 1 << 20,
        "G" | "GB" | "GIB" => 1 << 30,
        "T" | "TB" | "TIB" => 1 << 40,
        other => return Err(format!("`{other}` is not a size unit (use K, M, G or T)")),
    };
    let bytes = number * scale as f64;
    if bytes.is_finite() && bytes >= 1.0 && bytes < u64::MAX as f64 {
        Ok(bytes as u64)
    } else {
        Err(format!("`{text}` is not a usable size"))
    }
}

/// `MemAvailable` of `/proc/meminfo` in bytes.
fn meminfo_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// The soft limit of the process's address space (`ulimit -v`) from `/proc/self/limits`.
fn address_space_limit() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = text.lines().find(|l| l.starts_with("Max address space"))?;
    line.split_whitespace().nth(3)?.parse().ok()
}

/// The control group's limit minus its current use (cgroup v2), if a limit is set.
fn cgroup_limit() -> Option<u64> {
    let read = |name: &str| std::fs::read_to_string(format!("/sys/fs/cgroup/{name}")).ok();
    let max: u64 = read("memory.max")?.trim().parse().ok()?;
    let current: u64 = read("memory.current").and_then(|s| s.trim().parse().ok()).unwrap_or(0);
    Some(max.saturating_sub(current))
}
