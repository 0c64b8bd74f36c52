//! Where the test command's time goes: each step of `cargo xtask test` is timed, and the
//! table is printed when the command ends (passed or not) and kept in
//! `target/xtask-test-times.md`, so that a slow run says which step made it slow without
//! a second run under a profiler.

use std::time::{Duration, Instant};

use anyhow::{Context, Result};

/// The steps run so far, in order, with their wall time.
pub struct Steps {
    started: Instant,
    done: Vec<(&'static str, Duration)>,
}

impl Steps {
    /// Starts the clock for the whole command.
    pub fn new() -> Self {
        Self {
            started: Instant::now(),
            done: Vec::new(),
        }
    }

    /// Runs one step and records its wall time, whether it passes or fails.
    /// A failure comes back with the step's name in front of its cause, so the command's
    /// last line says which step stopped it.
    pub fn run<T>(&mut self, name: &'static str, step: impl FnOnce() -> Result<T>) -> Result<T> {
        let t = Instant::now();
        let out = step();
        self.done.push((name, t.elapsed()));
        out.with_context(|| format!("step \"{name}\" failed"))
    }

    /// The table: one row per step, its seconds and share of the whole, then the total.
    pub fn table(&self) -> String {
        let total = self.started.elapsed();
        let share = |d: Duration| 100.0 * d.as_secs_f64() / total.as_secs_f64().max(1e-9);
        let mut s = String::from("| step | seconds | share |\n|---|---:|---:|\n");
        for (name, d) in &self.done {
            s += &format!("| {name} | {:.1} | {:.0} % |\n", d.as_secs_f64(), share(*d));
        }
        let steps: Duration = self.done.iter().map(|(_, d)| *d).sum();
        let other = total.saturating_sub(steps);
        if other > Duration::from_millis(500) {
            s += &format!(
                "| (between steps) | {:.1} | {:.0} % |\n",
                other.as_secs_f64(),
                share(other)
            );
        }
        s += &format!("| **total** | **{:.1}** | 100 % |\n", total.as_secs_f64());
        s
    }

    /// Prints the table and writes it to `path` (a failure to write is reported, not
    /// fatal: the table was printed).
    pub fn report(&self, path: &std::path::Path) {
        let table = self.table();
        eprintln!("xtask test: where the time went\n{table}");
        if let Err(e) = std::fs::write(path, &table) {
            eprintln!("xtask test: could not write {}: {e}", path.display());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_step_is_timed_and_the_table_lists_every_step() {
        let mut steps = Steps::new();
        assert_eq!(steps.run("first", || Ok(3)).ok(), Some(3));
        assert!(steps
            .run("second", || -> Result<()> { anyhow::bail!("broken") })
            .is_err());
        let err = steps
            .run("third", || -> Result<()> { anyhow::bail!("the cause") })
            .err()
            .map(|e| format!("{e:#}"));
        assert_eq!(
            err.as_deref(),
            Some("step \"third\" failed: the cause"),
            "a failure names its step and keeps its cause"
        );
        let table = steps.table();
        let rows: Vec<&str> = table.lines().collect();
        assert!(rows[2].starts_with("| first | "), "{table}");
        assert!(rows[3].starts_with("| second | "), "{table}");
        assert!(
            rows.last().is_some_and(|r| r.starts_with("| **total** |")),
            "{table}"
        );
    }
}
