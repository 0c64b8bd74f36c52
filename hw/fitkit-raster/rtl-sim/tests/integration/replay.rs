//! A failing differential case leaves a waveform behind: the case is replayed (every case
//! is seeded, so it fails the same way again) with the block writing a VCD of every
//! signal, and the failure names its path. A case that is a list of commands is first
//! shrunk to the fewest commands that still fail, so the waveform is as short as the
//! failure allows.

use std::cell::RefCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

use fitkit_rtl_sim::SharedRtl;

thread_local! {
    /// Where the next RTL made on this thread writes its waveform, while a case replays.
    static TRACE: RefCell<Option<PathBuf>> = const { RefCell::new(None) };
}

/// Where waveforms go: the workspace's `target/tmp/fitkit-waves/`.
pub fn waves_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fitkit-waves")
}

/// `rtl`, writing the replayed case's waveform if one is asked for on this thread (the
/// first RTL the case makes: a case with several writes the first one's).
pub fn traced(rtl: SharedRtl) -> SharedRtl {
    if let Some(path) = TRACE.with(|t| t.borrow_mut().take()) {
        rtl.borrow_mut()
            .trace_to(&path)
            .unwrap_or_else(|e| panic!("{e}"));
    }
    rtl
}

/// The text of a panic's payload.
fn message(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "(a panic without a message)".into())
}

/// Runs `case`; whether and how it failed.
fn quietly<T>(case: impl FnOnce() -> T) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(case)).map_err(|p| message(p.as_ref()))
}

/// Runs `case` once more writing the waveform to `waves/<name>.vcd`, then fails with
/// `why` and the waveform's path.
fn fail_with_waveform(name: &str, why: &str, case: impl FnOnce()) -> ! {
    let dir = waves_dir();
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(format!("{name}.vcd"));
    TRACE.with(|t| *t.borrow_mut() = Some(path.clone()));
    let again = quietly(case);
    TRACE.with(|t| t.borrow_mut().take());
    match again {
        Err(_) => panic!("{why}\n  waveform of the failing case: {}", path.display()),
        Ok(()) => panic!(
            "{why}\n  (the case passed when replayed, so it is not deterministic: no waveform)"
        ),
    }
}

/// Runs `case` (a seeded, self-contained check); if it fails, replays it with a waveform
/// and fails naming it.
pub fn with_waveform(name: &str, case: impl Fn()) {
    if let Err(why) = quietly(&case) {
        fail_with_waveform(name, &why, &case);
    }
}

/// Runs `job` on `cmds`; if it fails, shrinks `cmds` to a list that still fails and no
/// command of which can be left out (each tried once, from the last), replays that with
/// a waveform and fails naming the commands kept and the waveform.
pub fn shrinking<C: Clone + std::fmt::Debug>(name: &str, cmds: &[C], job: impl Fn(&[C])) {
    let Err(first) = quietly(|| job(cmds)) else {
        return;
    };
    let mut kept = cmds.to_vec();
    let mut why = first;
    let mut i = kept.len();
    while i > 0 {
        i -= 1;
        let mut fewer = kept.clone();
        fewer.remove(i);
        if let Err(w) = quietly(|| job(&fewer)) {
            kept = fewer;
            why = w;
        }
    }
    let summary = format!(
        "{name}: fails; shrunk from {} to {} commands {kept:?}:\n  {why}",
        cmds.len(),
        kept.len()
    );
    fail_with_waveform(name, &summary, || job(&kept));
}
