//! A check run beside the test command's other steps: a `cargo xtask …` of its own, niced,
//! its output in a log file that is printed when it is collected.
//!
//! Why: after the test build, the test run (1.5 cores busy on average), the Python
//! package (1.6) and cocotb (1.0) leave cores idle that the fuzz smoke, a build of its own
//! into `fuzz/target` on the nightly, can use; run one after another they took 607 s of a
//! fresh clone's test command. Niced, it takes only what the steps in front leave, so
//! their timing-sensitive tests (pseudo-terminals, simulators) see the machine as before.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

/// A running check; killed with its process group if dropped before [`Beside::finish`].
pub struct Beside {
    what: String,
    child: Option<Child>,
    log: PathBuf,
    started: Instant,
    /// When the child was seen to exit (before it is collected, so its CPU time lands in
    /// the step that collects it).
    ended: Arc<Mutex<Option<Instant>>>,
}

impl Beside {
    /// Starts `cargo xtask ARGS` (this very program with `args`) beside the caller
    /// ([`Beside::start_program`]).
    pub fn start(args: &[&str], log: &Path) -> Result<Self> {
        let exe = std::env::current_exe().context("cannot find the xtask binary")?;
        Self::start_program(&exe, args, &format!("cargo xtask {}", args.join(" ")), log)
    }

    /// Starts `program args` (called `what` in the log) under `nice -n 10` in a process
    /// group of its own, stdout and stderr into `log`.
    pub fn start_program(program: &Path, args: &[&str], what: &str, log: &Path) -> Result<Self> {
        use std::os::unix::process::CommandExt;
        let out = File::create(log).with_context(|| format!("cannot create {}", log.display()))?;
        let err = out.try_clone()?;
        let what = what.to_string();
        eprintln!(
            "+ nice -n 10 {what} (beside the steps that follow; its output goes to {} and is printed when it ends)",
            log.display()
        );
        let child = Command::new("nice")
            .args(["-n", "10"])
            .arg(program)
            .args(args)
            .stdout(out)
            .stderr(err)
            .process_group(0)
            .spawn()
            .context("could not start `nice`")?;
        let ended = Arc::new(Mutex::new(None));
        let watch = Arc::clone(&ended);
        let stat = format!("/proc/{}/stat", child.id());
        std::thread::spawn(move || loop {
            // A zombie keeps its /proc entry until it is collected.
            let gone = std::fs::read_to_string(&stat)
                .map(|s| exited(&s))
                .unwrap_or(true);
            if gone {
                *watch.lock().unwrap_or_else(|p| p.into_inner()) = Some(Instant::now());
                return;
            }
            std::thread::sleep(Duration::from_millis(200));
        });
        Ok(Self {
            what,
            child: Some(child),
            log: log.to_path_buf(),
            started: Instant::now(),
            ended,
        })
    }

    /// Waits for the check, prints its log, and says how long it ran (start to exit, not
    /// to this call) and whether it passed.
    pub fn finish(mut self) -> (Duration, Result<()>) {
        let status = match self.child.take() {
            Some(mut c) => c.wait(),
            None => unreachable!("a Beside is finished once"),
        };
        let now = Instant::now();
        let ended = self
            .ended
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .unwrap_or(now);
        let wall = ended.duration_since(self.started);
        let text = std::fs::read_to_string(&self.log).unwrap_or_default();
        eprintln!(
            "+ {} ran beside the steps above for {:.1} s; its output:",
            self.what,
            wall.as_secs_f64()
        );
        eprint!("{text}");
        let result = match status {
            Ok(s) if s.success() => Ok(()),
            Ok(s) => Err(anyhow::anyhow!(
                "`{}` failed with {s} (its output is just above and in {})",
                self.what,
                self.log.display()
            )),
            Err(e) => Err(anyhow::anyhow!("could not wait for `{}`: {e}", self.what)),
        };
        (wall, result)
    }
}

impl Drop for Beside {
    /// A step in front failed: the check is stopped, with everything it started.
    fn drop(&mut self) {
        if let Some(mut c) = self.child.take() {
            let _ = Command::new("kill")
                .args(["-TERM", "--", &format!("-{}", c.id())])
                .status();
            let _ = c.wait();
        }
    }
}

/// Whether a `/proc/<pid>/stat` line is a process that has exited (a zombie, `Z`, or
/// dead, `X`); a line that cannot be read counts as gone.
fn exited(stat: &str) -> bool {
    crate::steps::stat_fields(stat).is_none_or(|f| matches!(f.first().copied(), Some("Z" | "X")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_zombie_and_a_dead_process_have_exited() {
        assert!(exited("42 (cargo (x)) Z 1 2"));
        assert!(exited("42 (x) X 1"));
        assert!(!exited("42 (a b) S 1 2"));
        assert!(!exited("42 (x) R 1"));
        assert!(exited("garbage"));
    }

    fn log(name: &str) -> PathBuf {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/tmp");
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn a_check_beside_is_timed_to_its_exit_and_its_failure_is_reported() {
        let sh = Path::new("/bin/sh");
        let ok = Beside::start_program(sh, &["-c", "sleep 0.5"], "sleep", &log("beside-ok.log"))
            .unwrap();
        std::thread::sleep(Duration::from_millis(1500));
        let (wall, result) = ok.finish();
        assert!(result.is_ok());
        assert!(
            wall >= Duration::from_millis(400) && wall < Duration::from_millis(1300),
            "{wall:?}: the time to its exit, not to its collection"
        );
        let bad = Beside::start_program(
            sh,
            &["-c", "echo half-way; exit 3"],
            "the failing check",
            &log("beside-bad.log"),
        )
        .unwrap();
        let (_, result) = bad.finish();
        let e = format!("{:#}", result.expect_err("exit 3 fails"));
        assert!(
            e.contains("the failing check") && e.contains("exit status: 3"),
            "{e}"
        );
        let text = std::fs::read_to_string(log("beside-bad.log")).unwrap();
        assert_eq!(text, "half-way\n");
    }

    #[test]
    fn a_check_dropped_unfinished_is_stopped_with_its_children() {
        let sh = Path::new("/bin/sh");
        let t = Instant::now();
        let long = Beside::start_program(
            sh,
            &["-c", "sleep 30 & sleep 30; wait"],
            "a long check",
            &log("beside-long.log"),
        )
        .unwrap();
        std::thread::sleep(Duration::from_millis(200));
        drop(long);
        assert!(t.elapsed() < Duration::from_secs(10), "{:?}", t.elapsed());
    }
}
