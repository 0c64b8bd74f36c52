//! A failing differential case leaves a waveform behind, and the failure names its path.
//!
//! The suite runs on models built without tracing: Verilator's `--trace` doubles the C++
//! the crate compiles (about two more minutes on two cores), which every run would pay
//! for a failure that rarely comes. So when a case fails, its test runs again, alone, in a
//! child `cargo test` of this crate with the `trace` feature (built then, once; a second
//! failure reuses it). Every case is seeded, so the child repeats the run exactly up to
//! the failing case, where the model starts a VCD of every signal, and stops at that
//! case's end: the waveform holds only that case (an operand set's or a pair's clocks
//! from entry to result, one scene's frame, one access sequence), with the state the run
//! had brought the model to.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use rt_core_rtl_sim::{Cast, Device, Intersect, MathUnits, RtlError};

/// The case the child replays with a waveform.
const CASE: &str = "FPGFX_RT_WAVE_CASE";
/// Where the child writes it.
const VCD: &str = "FPGFX_RT_WAVE_VCD";
/// How the child says the case failed again (the parent reads it in the child's log).
const AGAIN: &str = "waveform replay: failed again:";
/// How the child says the case passed this time.
const PASSED: &str = "waveform replay: passed:";

/// A model that can write a waveform.
pub trait Waveform {
    /// Starts a VCD of every signal at `path` from the next clock edge on.
    fn trace_to(&mut self, path: &Path) -> Result<(), RtlError>;
}

impl Waveform for MathUnits {
    fn trace_to(&mut self, path: &Path) -> Result<(), RtlError> {
        MathUnits::trace_to(self, path)
    }
}

impl Waveform for Intersect {
    fn trace_to(&mut self, path: &Path) -> Result<(), RtlError> {
        Intersect::trace_to(self, path)
    }
}

impl Waveform for Cast {
    fn trace_to(&mut self, path: &Path) -> Result<(), RtlError> {
        Cast::trace_to(self, path)
    }
}

impl Waveform for Device {
    fn trace_to(&mut self, path: &Path) -> Result<(), RtlError> {
        Device::trace_to(self, path)
    }
}

/// The mismatches of a stream of cycles (operand sets, pairs) against the model: their
/// lines, and the earliest cycle whose inputs failed, the case a failure replays.
#[derive(Default)]
pub struct Mismatches {
    lines: Vec<String>,
    first: Option<u64>,
}

impl Mismatches {
    /// A mismatch of the inputs that went in at `cycle`.
    pub fn push(&mut self, cycle: u64, why: String) {
        self.lines.push(why);
        self.first.get_or_insert(cycle);
    }

    /// After a cycle's checks: in the child replaying cycle `replay`, ends the replay
    /// once that cycle failed; whether the suite has enough (ten) to stop streaming.
    pub fn enough(&self, waves: &Waves, replay: Option<u64>) -> bool {
        if let Some(at) = self.first.filter(|at| Some(*at) == replay) {
            waves.fail(&format!("cycle {at}"), &self.lines.join("\n"));
        }
        self.lines.len() >= 10
    }

    /// After the stream: if anything failed, fails naming the first failing cycle.
    pub fn finish(self, waves: &Waves) {
        if let Some(at) = self.first {
            waves.fail(
                &format!("cycle {at}"),
                &format!(
                    "{} mismatches, first ones:\n{}",
                    self.lines.len(),
                    self.lines.join("\n")
                ),
            );
        }
    }
}

/// One test's cases: run by the suite, or replayed by the child.
pub struct Waves {
    /// The test's path in the binary (`module::name`), which the child runs alone.
    test: &'static str,
    /// In the child: the case to replay and where its waveform goes.
    replay: Option<(String, PathBuf)>,
}

impl Waves {
    /// The cases of `test` (its path, as `cargo test -- --exact` takes it).
    pub fn new(test: &'static str) -> Self {
        let replay = match (std::env::var(CASE), std::env::var_os(VCD)) {
            (Ok(case), Some(vcd)) => Some((case, PathBuf::from(vcd))),
            _ => None,
        };
        Self { test, replay }
    }

    /// In the child, the case it replays.
    pub fn replaying(&self) -> Option<&str> {
        self.replay.as_ref().map(|(c, _)| c.as_str())
    }

    /// Before `case` runs on `model`: in the child replaying it, starts its waveform.
    pub fn before(&self, case: &str, model: &mut impl Waveform) {
        if let Some((c, vcd)) = &self.replay {
            if c == case {
                model
                    .trace_to(vcd)
                    .unwrap_or_else(|e| panic!("{}: {e}", vcd.display()));
            }
        }
    }

    /// Runs `case`'s checks; if one fails (panics), the test fails with the case's
    /// waveform.
    pub fn case<T>(&self, case: &str, checks: impl FnOnce() -> T) -> T {
        self.case_or(case, checks, || None)
    }

    /// As [`Self::case`], but a failure is first offered to `shrink`, which may name a
    /// smaller case that fails too, and how; that one is replayed instead.
    pub fn case_or<T>(
        &self,
        case: &str,
        checks: impl FnOnce() -> T,
        shrink: impl FnOnce() -> Option<(String, String)>,
    ) -> T {
        match catch_unwind(AssertUnwindSafe(checks)) {
            Ok(v) => {
                self.passed(case);
                v
            }
            Err(p) => {
                let why = message(p.as_ref());
                if self.replay.is_some() {
                    self.fail(case, &why)
                }
                match catch_unwind(AssertUnwindSafe(shrink)).ok().flatten() {
                    Some((smaller, how)) => {
                        self.fail(&smaller, &format!("{why}\n  shrunk to {smaller}: {how}"))
                    }
                    None => self.fail(case, &why),
                }
            }
        }
    }

    /// `case` passed: in the child replaying it, the replay ends here (it did not fail
    /// again).
    pub fn passed(&self, case: &str) {
        if self.replaying() == Some(case) {
            panic!("{PASSED} {case}");
        }
    }

    /// `case` failed with `why`: in the suite, replays it with a waveform and fails naming
    /// it; in the child, ends the replay.
    pub fn fail(&self, case: &str, why: &str) -> ! {
        if self.replay.is_some() {
            panic!("{AGAIN} {case}: {why}");
        }
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rt-core-waves");
        let _ = std::fs::create_dir_all(&dir);
        let stem: String = format!("{}-{case}", self.test)
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
            .collect();
        let vcd = dir.join(format!("{stem}.vcd"));
        let log = dir.join(format!("{stem}.log"));
        let _ = std::fs::remove_file(&vcd);
        let outcome = self.child(case, &vcd, &log);
        match outcome {
            Ok(()) => panic!(
                "{why}\n  waveform of the failing case ({case}): {}",
                vcd.display()
            ),
            Err(e) => panic!("{why}\n  no waveform: {e} (log: {})", log.display()),
        }
    }

    /// Runs the test alone in a child `cargo test` with the `trace` feature, replaying
    /// `case` into `vcd`, its output into `log`; whether it failed again with a waveform.
    fn child(&self, case: &str, vcd: &Path, log: &Path) -> Result<(), String> {
        let out = std::fs::File::create(log).map_err(|e| format!("{}: {e}", log.display()))?;
        let err = out.try_clone().map_err(|e| e.to_string())?;
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let mut cmd = Command::new(cargo);
        cmd.current_dir(env!("CARGO_MANIFEST_DIR")).args([
            "test",
            "-p",
            "rt-core-rtl-sim",
            "--features",
            "trace",
        ]);
        if !cfg!(debug_assertions) {
            cmd.arg("--release");
        }
        cmd.args(["--test", "integration", "--", self.test, "--exact"])
            .env(CASE, case)
            .env(VCD, vcd)
            .stdin(Stdio::null())
            .stdout(out)
            .stderr(err);
        eprintln!(
            "{}: {case} failed; building the traced model and replaying it (log: {})",
            self.test,
            log.display()
        );
        let status = cmd.status().map_err(|e| format!("cannot run cargo: {e}"))?;
        let text = std::fs::read_to_string(log).unwrap_or_default();
        let again = text.contains(&format!("{AGAIN} {case}:"));
        let header = std::fs::File::open(vcd).is_ok_and(|f| {
            std::io::BufRead::lines(std::io::BufReader::new(f))
                .map_while(Result::ok)
                .any(|l| l.contains("$enddefinitions"))
        });
        match (again, header) {
            (true, true) => Ok(()),
            (true, false) => Err("the replay failed again but wrote no waveform".into()),
            _ if text.contains(&format!("{PASSED} {case}")) => {
                Err("the case passed when replayed, so it is not deterministic".into())
            }
            _ => Err(format!(
                "the traced replay did not reach the case ({status})"
            )),
        }
    }
}

/// The text of a panic's payload.
fn message(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "(a panic without a message)".into())
}
