//! What an experiment's check found: the report's lines and the expected behaviours it tested.
//!
//! Each expectation states its tolerance and why that tolerance; `cargo xtask experiments` fails and
//! lists every expectation that a full run did not meet.

/// The outcome of an experiment's check.
#[derive(Debug, Clone, Default)]
pub struct Check {
    lines: Vec<String>,
    failures: Vec<String>,
}

impl Check {
    /// An empty check.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a report line (markdown).
    pub fn say(&mut self, line: impl Into<String>) {
        self.lines.push(line.into());
    }

    /// Adds report lines.
    pub fn extend(&mut self, lines: impl IntoIterator<Item = String>) {
        self.lines.extend(lines);
    }

    /// Tests an expected behaviour: `claim` says what is expected, with its tolerance and the reason
    /// for it; `measured` what the outputs show. A missing measurement (`None`) counts as not met.
    pub fn expect(&mut self, claim: impl Into<String>, measured: Option<(bool, String)>) {
        let claim = claim.into();
        let (passed, measured) = measured.unwrap_or((false, "not measured (output missing)".into()));
        if passed {
            self.lines.push(format!("- ✓ {claim}: {measured}."));
        } else {
            self.lines.push(format!("- ✗ **not met**: {claim}: {measured}."));
            self.failures.push(format!("{claim}: {measured}"));
        }
    }

    /// The report's lines.
    pub fn lines(&self) -> &[String] {
        &self.lines
    }

    /// The expectations that were not met.
    pub fn failures(&self) -> &[String] {
        &self.failures
    }
}

/// `Some((value within [lo, hi], text))`: a measured value against its bounds.
pub fn within(value: f64, lo: f64, hi: f64, text: String) -> Option<(bool, String)> {
    Some((value.is_finite() && value >= lo && value <= hi, text))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unmet_and_missing_expectations_are_failures() {
        let mut c = Check::new();
        c.expect("a", within(1.0, 0.0, 2.0, "1".into()));
        c.expect("b", within(3.0, 0.0, 2.0, "3".into()));
        c.expect("c", None);
        c.expect("d", within(f64::NAN, 0.0, 2.0, "NaN".into()));
        assert_eq!(c.failures().len(), 3);
        assert!(c.lines()[0].starts_with("- ✓ a"));
        assert!(c.lines()[1].contains("not met"));
    }
}
