//! Where the test command's time goes: each step of `cargo xtask test` is timed, and the
//! table is printed when the command ends (passed or not) and kept in
//! `target/xtask-test-times.md`, so that a slow run says which step made it slow without
//! a second run under a profiler.
//!
//! Beside the wall time, the CPU time each step's processes used (on Linux, from
//! `/proc/self/stat`): wall time alone cannot tell a step that is slow because it does
//! much work from one that leaves a core idle, and on a 2-core machine only the second
//! can be made faster by running something beside it.

use std::time::{Duration, Instant};

use anyhow::{Context, Result};

/// The steps run so far, in order, with their wall time and CPU seconds.
pub struct Steps {
    started: Instant,
    cpu_at_start: Option<f64>,
    done: Vec<(&'static str, Duration, Option<f64>)>,
}

impl Steps {
    /// Starts the clock for the whole command.
    pub fn new() -> Self {
        Self {
            started: Instant::now(),
            cpu_at_start: cpu_seconds(),
            done: Vec::new(),
        }
    }

    /// Runs one step and records its wall time and CPU seconds, whether it passes or
    /// fails. A failure comes back with the step's name in front of its cause, so the
    /// command's last line says which step stopped it.
    pub fn run<T>(&mut self, name: &'static str, step: impl FnOnce() -> Result<T>) -> Result<T> {
        self.run_measured(name, || {
            let t = Instant::now();
            let out = step();
            (t.elapsed(), out)
        })
    }

    /// Records a step whose wall time `step` measures itself (a check that ran beside
    /// others and is only collected here: its own start to its exit), with the CPU
    /// seconds of the processes collected during the call.
    pub fn run_measured<T>(
        &mut self,
        name: &'static str,
        step: impl FnOnce() -> (Duration, Result<T>),
    ) -> Result<T> {
        let cpu = cpu_seconds();
        let (wall, out) = step();
        let cpu = cpu.zip(cpu_seconds()).map(|(a, b)| b - a);
        self.done.push((name, wall, cpu));
        out.with_context(|| format!("step \"{name}\" failed"))
    }

    /// The table: one row per step, its seconds, CPU seconds, how many cores it kept
    /// busy on average and its share of the whole, then the total.
    pub fn table(&self) -> String {
        let total = self.started.elapsed();
        let share = |d: Duration| 100.0 * d.as_secs_f64() / total.as_secs_f64().max(1e-9);
        let cpu = |c: Option<f64>, d: Duration| match c {
            Some(c) => format!("{c:.0} | {:.2}", c / d.as_secs_f64().max(1e-9)),
            None => "— | —".into(),
        };
        let mut s = String::from(
            "| step | seconds | CPU seconds | cores busy | share |\n|---|---:|---:|---:|---:|\n",
        );
        for (name, d, c) in &self.done {
            s += &format!(
                "| {name} | {:.1} | {} | {:.0} % |\n",
                d.as_secs_f64(),
                cpu(*c, *d),
                share(*d)
            );
        }
        let steps: Duration = self.done.iter().map(|(_, d, _)| *d).sum();
        let other = total.saturating_sub(steps);
        if other > Duration::from_millis(500) {
            s += &format!(
                "| (between steps) | {:.1} | | | {:.0} % |\n",
                other.as_secs_f64(),
                share(other)
            );
        }
        let all = self.cpu_at_start.zip(cpu_seconds()).map(|(a, b)| b - a);
        s += &format!(
            "| **total** | **{:.1}** | {} | 100 % |\n",
            total.as_secs_f64(),
            cpu(all, total)
        );
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

/// CPU seconds used so far by this process and by every child it has waited for (their
/// children included, when they waited for them: cargo's rustc, Yosys under a thread),
/// or `None` where `/proc` does not say.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    ticks(&stat).map(|t| t as f64 / clock_ticks_per_second())
}

/// The fields of a `/proc/<pid>/stat` line from the third (the state) on: the command
/// name, field 2, is in parentheses and may hold spaces, so they are counted from its
/// closing one. `None` for a line without it.
pub fn stat_fields(stat: &str) -> Option<Vec<&str>> {
    Some(stat[stat.rfind(')')? + 1..].split_whitespace().collect())
}

/// utime + stime + cutime + cstime of a `/proc/<pid>/stat` line (fields 14 to 17).
fn ticks(stat: &str) -> Option<u64> {
    // the state is field 3, so utime (14) is the 12th of these
    stat_fields(stat)?
        .get(11..15)?
        .iter()
        .map(|v| v.parse::<u64>().ok())
        .sum::<Option<u64>>()
}

/// The kernel's clock ticks per second (`getconf CLK_TCK`; 100 on every Linux this runs
/// on, the fallback).
fn clock_ticks_per_second() -> f64 {
    static TCK: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *TCK.get_or_init(|| {
        std::process::Command::new("getconf")
            .arg("CLK_TCK")
            .output()
            .ok()
            .and_then(|o| String::from_utf8_lossy(&o.stdout).trim().parse().ok())
            .filter(|t: &f64| *t > 0.0)
            .unwrap_or(100.0)
    })
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

    #[test]
    fn cpu_ticks_are_the_four_time_fields_after_the_name() {
        // a name with spaces and a parenthesis, then state, ppid .. cstime
        let stat = "1234 (a (b) c) S 1 2 3 4 5 6 7 8 9 10 100 20 3000 400 20 0 1 0";
        assert_eq!(ticks(stat), Some(100 + 20 + 3000 + 400));
        assert_eq!(ticks("1 (x) S 1 2"), None);
    }

    #[test]
    fn a_step_that_spins_uses_cpu_time() {
        let mut steps = Steps::new();
        steps
            .run("spin", || {
                let t = Instant::now();
                let mut x = 0u64;
                while t.elapsed() < Duration::from_millis(300) {
                    x = std::hint::black_box(x.wrapping_add(1));
                }
                Ok(())
            })
            .unwrap();
        if let Some(cpu) = steps.done[0].2 {
            assert!(cpu >= 0.1, "{cpu} CPU seconds for a 0.3 s spin");
        }
    }
}
