//! Scaffolding shared by host-cli's end-to-end tests: one way to start the emulator, run
//! `fpgfx`, name temporary files and load images, so that a fix (say, hermetic
//! environment variables or the no-panic rule) reaches every test module at once.

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::JoinHandle;
use std::time::SystemTime;

/// The workspace root (where `examples/` and the firmware crate live).
pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("host-cli sits in the workspace")
        .to_path_buf()
}

/// A file under `examples/`, as the string `fpgfx` takes on its command line.
pub fn example(rel: &str) -> String {
    workspace().join("examples").join(rel).display().to_string()
}

/// A path for a scratch file in the calling test module's own directory: one directory
/// per process (so concurrent runs and earlier ones never collide) and in it one per
/// module, named after the caller's source file (the modules share the process and run
/// on parallel threads, and several use the same file names). The directory is left in
/// place: after a failure the files are what one wants to look at.
#[track_caller]
pub fn tmp(name: &str) -> String {
    let module = Path::new(std::panic::Location::caller().file())
        .file_stem()
        .and_then(|s| s.to_str())
        .expect("a test module's file has a name");
    let dir = std::env::temp_dir()
        .join(format!(
            "fpgfx-{}-{}",
            env!("CARGO_CRATE_NAME"),
            std::process::id()
        ))
        .join(module);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name).display().to_string()
}

/// The raster gallery, `examples/raster/*.toml`, sorted: the one list of the files that
/// the tests draw, compare, send over the FPGA link and damage, so that a new example
/// joins all of them.
pub fn raster_gallery() -> Vec<PathBuf> {
    let dir = workspace().join("examples/raster");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 3, "gallery files missing: {files:?}");
    files
}

/// An image file as RGB8, named in the panic when it is missing or unreadable (the usual
/// cause: the command that should have written it did not).
pub fn rgb(path: &str) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{path}: {e}"))
        .to_rgb8()
}

/// Kills its child when the test ends, passed or failed: a panicking test must not leave
/// an emulator holding a pty or QEMU spinning.
pub struct KillOnDrop(pub Child);

impl Drop for KillOnDrop {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Everything `from` yields until its end, collected by a thread (a child's pipe that
/// nobody reads fills up and blocks the child). Join the handle to have all of it.
pub fn collect<R: Read + Send + 'static>(mut from: R) -> (Arc<Mutex<Vec<u8>>>, JoinHandle<()>) {
    let log = Arc::new(Mutex::new(Vec::new()));
    let sink = log.clone();
    let reader = std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = from.read(&mut buf) {
            if n == 0 {
                break;
            }
            sink.lock().expect("log lock").extend_from_slice(&buf[..n]);
        }
    });
    (log, reader)
}

/// A running `fpgfx-sim`, killed on drop.
pub struct Sim {
    child: KillOnDrop,
    /// What the sim printed first, i.e. what `fpgfx --port` takes: its pty path
    /// ([`start_sim`]) or `tcp:ADDR` ([`start_tcp_sim`]).
    pub pty: String,
    /// Its stderr, collected in the background: a sim that logs a lot must never block
    /// on a full pipe while the test waits for it.
    stderr: Arc<Mutex<Vec<u8>>>,
    reader: Option<JoinHandle<()>>,
}

impl Sim {
    /// Waits (up to `limit`) until the sim's stderr holds `needle`: a request the host
    /// sent last (the bootloader's Go) may still be in the sim when the host exits, and
    /// killing it then would cut its log line short.
    pub fn wait_for_log(&self, needle: &str, limit: std::time::Duration) -> bool {
        let end = std::time::Instant::now() + limit;
        loop {
            let seen = {
                let log = self.stderr.lock().expect("log lock");
                String::from_utf8_lossy(&log).contains(needle)
            };
            if seen || std::time::Instant::now() >= end {
                return seen;
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
    }
}

/// A `Command` for the emulator binary, for the tests that do not want [`start_sim`]'s
/// handshake (e.g. `--fpga-link`, which prints no port).
pub fn sim_command() -> Command {
    Command::new(sim_binary())
}

/// The `fpgfx-sim` binary. It is sim-board's, and cargo names only a crate's own binaries
/// to its tests (`CARGO_BIN_EXE_*`), so it is looked for next to `fpgfx`, in the same
/// target profile directory. `cargo test --workspace` has built it there; `cargo test -p
/// host-cli` has not, so when it is missing, or older than its sources (a stale one would
/// test old code without a word), it is built there, once per test run.
pub fn sim_binary() -> PathBuf {
    static SIM: OnceLock<PathBuf> = OnceLock::new();
    SIM.get_or_init(|| {
        let fpgfx = Path::new(env!("CARGO_BIN_EXE_fpgfx"));
        let profile_dir = fpgfx
            .parent()
            .expect("fpgfx lives in a target profile directory");
        let sim = profile_dir.join(format!("fpgfx-sim{}", std::env::consts::EXE_SUFFIX));
        if !newer_than_sources(&sim) {
            build_sim(profile_dir);
        }
        assert!(
            sim.is_file(),
            "fpgfx-sim is not at {} (it must sit next to fpgfx)",
            sim.display()
        );
        sim
    })
    .clone()
}

/// Whether `binary` exists and was built after every file of sim-board and the workspace
/// crates it is built from last changed (cargo judges freshness by modification times too).
fn newer_than_sources(binary: &Path) -> bool {
    fn newest(path: &Path) -> SystemTime {
        let Ok(meta) = path.metadata() else {
            return SystemTime::UNIX_EPOCH;
        };
        let own = meta.modified().unwrap_or(SystemTime::UNIX_EPOCH);
        if !meta.is_dir() {
            return own;
        }
        std::fs::read_dir(path)
            .into_iter()
            .flatten()
            .flatten()
            .map(|entry| newest(&entry.path()))
            .fold(own, SystemTime::max)
    }
    let Ok(built) = binary.metadata().and_then(|m| m.modified()) else {
        return false;
    };
    let root = workspace();
    ["sim-board", "firmware", "sim-target", "protocol"]
        .iter()
        .all(|krate| newest(&root.join(krate)) <= built)
}

/// `$CARGO build -p sim-board --bin fpgfx-sim` into `profile_dir` (`<target-dir>/debug` is
/// the dev profile's; other profiles' directories carry their names).
fn build_sim(profile_dir: &Path) {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| {
        panic!(
            "fpgfx-sim is missing from {} or older than its sources, and CARGO is not set \
             to build it: run the tests through cargo, or `cargo build -p sim-board --bin \
             fpgfx-sim` first",
            profile_dir.display()
        )
    });
    let name = profile_dir
        .file_name()
        .and_then(|n| n.to_str())
        .expect("the profile directory has a name");
    let profile = if name == "debug" { "dev" } else { name };
    let target_dir = profile_dir
        .parent()
        .expect("the profile directory sits in a target directory");
    let args = [
        "build",
        "-p",
        "sim-board",
        "--bin",
        "fpgfx-sim",
        "--profile",
        profile,
        "--target-dir",
    ];
    let status = Command::new(&cargo)
        .args(args)
        .arg(target_dir)
        .current_dir(workspace())
        .status()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", Path::new(&cargo).display()));
    assert!(
        status.success(),
        "`cargo {} {}` failed ({status}): the tests need fpgfx-sim",
        args.join(" "),
        target_dir.display()
    );
}

fn spawn_sim(args: &[&str]) -> Sim {
    let mut child = sim_command()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("fpgfx-sim starts");
    let stdout = child.stdout.take().expect("piped stdout");
    let (log, reader) = collect(child.stderr.take().expect("piped stderr"));
    let child = KillOnDrop(child);
    let mut line = String::new();
    BufReader::new(stdout)
        .read_line(&mut line)
        .expect("fpgfx-sim prints where it listens");
    Sim {
        child,
        pty: line.trim().to_string(),
        stderr: log,
        reader: Some(reader),
    }
}

/// `fpgfx-sim --pty EXTRA…`, once it has printed its pty.
pub fn start_sim(extra: &[&str]) -> Sim {
    let sim = spawn_sim(&[&["--pty"], extra].concat());
    assert!(
        sim.pty.starts_with("/dev/"),
        "unexpected pty path {:?}",
        sim.pty
    );
    sim
}

/// `fpgfx-sim --tcp 127.0.0.1:0`, once it has printed its address; `pty` is `tcp:ADDR`.
pub fn start_tcp_sim() -> Sim {
    let mut sim = spawn_sim(&["--tcp", "127.0.0.1:0"]);
    assert!(!sim.pty.is_empty(), "fpgfx-sim printed no address");
    sim.pty = format!("tcp:{}", sim.pty);
    sim
}

/// The sim's whole stderr after it ended (killed first if it would not end by itself).
pub fn sim_stderr(sim: Sim) -> String {
    sim_stderr_after(sim, std::time::Duration::ZERO)
}

/// The whole stderr of a sim that ends by itself (`--exit-after-writes`), given up to
/// `limit` to do so and killed after that. Killing it at once raced its last line: the
/// host sees the line go quiet before the sim has written "exiting after N writes", and a
/// kill between two of that line's writes left "exiting after 10" in the log.
pub fn sim_stderr_after(mut sim: Sim, limit: std::time::Duration) -> String {
    let end = std::time::Instant::now() + limit;
    while std::time::Instant::now() < end && matches!(sim.child.0.try_wait(), Ok(None)) {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let _ = sim.child.0.kill();
    let _ = sim.child.0.wait();
    if let Some(reader) = sim.reader.take() {
        let _ = reader.join();
    }
    let log = sim.stderr.lock().expect("log lock");
    String::from_utf8_lossy(&log).into_owned()
}

/// `fpgfx ARGS…`, hermetic: no `FPGFX_PORT` from the caller's shell, no config file
/// (`FPGFX_CONFIG=/dev/null`; a test sets its own with `.env` afterwards), and
/// `RUST_BACKTRACE=1` so that a panic could not hide behind a short message.
pub fn fpgfx_command(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_fpgfx"));
    c.args(args)
        .env_remove("FPGFX_PORT")
        .env("FPGFX_CONFIG", "/dev/null")
        .env("RUST_BACKTRACE", "1");
    c
}

/// What a finished `fpgfx` run left behind.
pub struct Run {
    /// The exit status; `None` when a signal ended it.
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

/// Nothing the user can type makes `fpgfx` panic (the brief's rule): checked on every run.
pub fn assert_no_panic(stderr: &str) {
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!stderr.contains("Stack backtrace"), "{stderr}");
}

/// Runs a command built by [`fpgfx_command`] to the end.
pub fn run(cmd: &mut Command) -> Run {
    let out = cmd.output().expect("fpgfx runs");
    let run = Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    };
    assert_no_panic(&run.stderr);
    run
}

/// `fpgfx ARGS…` (hermetic) to the end.
pub fn fpgfx(args: &[&str]) -> Run {
    run(&mut fpgfx_command(args))
}

/// Asserts that a run succeeded; `args` only name it in the failure message.
pub fn assert_ok(run: Run, args: &[&str]) -> Run {
    assert!(
        run.code == Some(0),
        "fpgfx {args:?} failed ({:?}):\nstdout: {}\nstderr: {}",
        run.code,
        run.stdout,
        run.stderr
    );
    run
}

/// Asserts that a run failed the way user errors do (status 1); returns its stderr.
pub fn assert_fails(run: Run, args: &[&str]) -> String {
    assert_eq!(
        run.code,
        Some(1),
        "fpgfx {args:?} should fail with status 1:\nstdout: {}\nstderr: {}",
        run.stdout,
        run.stderr
    );
    run.stderr
}

/// `fpgfx ARGS…` must succeed.
pub fn ok(args: &[&str]) -> Run {
    assert_ok(fpgfx(args), args)
}

/// `fpgfx ARGS…` must fail with status 1; returns its stderr.
pub fn fails(args: &[&str]) -> String {
    assert_fails(fpgfx(args), args)
}

/// `fpgfx ARGS…` must be refused by the argument parser (clap: status 2, before anything
/// runs); returns its stderr.
pub fn refused(args: &[&str]) -> String {
    let run = fpgfx(args);
    assert_eq!(
        run.code,
        Some(2),
        "fpgfx {args:?} should be refused with status 2:\nstdout: {}\nstderr: {}",
        run.stdout,
        run.stderr
    );
    run.stderr
}

/// A raster job with every primitive (Gouraud triangle, line, filled circle, 8-connected
/// seed fill, Bézier) at sub-pixel positions, spread over a `width`×`height` frame; `aa`
/// is extra TOML (e.g. an `[aa]` table) or empty. At 96×64 the numbers are the ones the
/// QEMU test always used; other sizes scale them.
pub fn every_primitive(width: u32, height: u32, aa: &str) -> String {
    let (sx, sy) = (f64::from(width) / 96.0, f64::from(height) / 64.0);
    let p = |x: f64, y: f64| format!("[{:?}, {:?}]", x * sx, y * sy);
    format!(
        r##"
size = [{width}, {height}]
background = "#102030"
{aa}
[[cmd]]
op = "triangle"
v = [{}, {}, {}]
colors = ["#ff0000", "#00ff00", "#0000ff"]
[[cmd]]
op = "line"
from = {}
to = {}
color = "#ffffff"
[[cmd]]
op = "circle"
center = {}
radius = {:?}
color = "#00ff00"
fill = true
[[cmd]]
op = "fill"
seed = [1, {}]
color = "#808000"
connectivity = 8
[[cmd]]
op = "bezier"
points = [{}, {}, {}, {}]
color = "#ffff00"
"##,
        p(4.5, 6.25),
        p(90.0, 10.0),
        p(30.0, 60.75),
        p(2.0, 3.0),
        p(94.0, 60.0),
        p(64.0, 32.0),
        18.5 * sx.min(sy),
        height - 2,
        p(5.0, 60.0),
        p(30.0, 5.0),
        p(60.0, 62.0),
        p(94.0, 8.0),
    )
}

/// The frame after a first one, in the other packing (KCU116) and without AOVs: returns
/// how many register words crossed the link, which must be only the ones that changed
/// (the renderer keeps the device's register image; the packing is no register).
pub fn words_for_next_frame<T: host_cli::session::Transport>(
    renderer: &mut host_cli::run::render::Renderer,
    session: &mut host_cli::session::Session<T>,
    regs: &sim_target::scene_regs::Regs,
    numeric: protocol::frame::Numeric,
) -> usize {
    use host_cli::run::render::{Aovs, Packing};
    let (_, words) = renderer
        .frame(session, regs, numeric, Packing::Kcu116, Aovs::default())
        .expect("the next frame renders");
    words
}

/// A fresh pty pair with its slave end closed again: the path is a port on which only
/// the test, through the master end, answers (or nobody, if it keeps quiet).
pub fn pty_pair() -> (serialport::TTYPort, String) {
    let (master, slave) = serialport::TTYPort::pair().expect("pty pair");
    let path = serialport::SerialPort::name(&slave).expect("pty path");
    drop(slave);
    (master, path)
}

/// Asserts that `--stats` on an RTL target printed the model's clock count equal to the
/// RTL's (its `model cycles … = +0)` line).
pub fn assert_model_cycles_equal(stdout: &str) {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("model cycles"))
        .unwrap_or_else(|| panic!("no model cycles line:\n{stdout}"));
    assert!(
        line.ends_with("= +0)"),
        "RTL and model cycles differ: {line}"
    );
}
