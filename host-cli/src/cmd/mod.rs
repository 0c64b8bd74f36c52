//! One file per `fpgfx` command: its arguments (`Args`) and its `run`, which calls the
//! library and prints. What every command shares is here: the target options, opening
//! the target, and the pieces of output two commands print alike.

pub mod animate;
pub mod bench;
pub mod compare;
pub mod flash;
pub mod ports;
pub mod raster;
pub mod render;
pub mod stress;
pub mod vectors;

use std::fs::OpenOptions;
use std::path::Path;

use anyhow::{bail, Context, Result};
use host_cli::connect::{self, Config, Settings};
use host_cli::session::{Phase, Session, Transport};

/// Options every command shares; each falls back to `fpgfx.toml` (see `fpgfx ports
/// --help`), then to its default.
#[derive(clap::Args)]
pub struct TargetArgs {
    /// Target: a serial port (a board, `fpgfx-sim --pty`, QEMU), `tcp:HOST:PORT`
    /// (`fpgfx-sim --tcp`), `builtin` (the golden model in process), `builtin:mmio` (the
    /// same with the controller on the model's AXI4-Lite registers, as a soft core beside
    /// ViRAY-style IP), `rtl` (the FITkit raster block's RTL, Verilated, driven over its
    /// SPI pins) or `rtl:rt` (the ray-casting core's RTL, Verilated, driven over its
    /// AXI4-Lite pins by the same register driver). Default: the one known USB-serial
    /// adapter if exactly one is plugged in, else the built-in target.
    #[arg(long, global = true, env = "FPGFX_PORT")]
    pub port: Option<String>,
    /// Line rate of a serial --port [default: 115200].
    #[arg(long, global = true)]
    pub baud: Option<u32>,
    /// Seconds to wait for the target to answer the handshake [default: 10].
    #[arg(long, global = true)]
    pub timeout: Option<f64>,
}

impl TargetArgs {
    /// The flags merged with the config file and the defaults.
    pub fn settings(&self) -> Result<Settings, connect::ConfigError> {
        connect::resolve(Config {
            port: self.port.clone(),
            baud: self.baud,
            timeout: self.timeout,
        })
    }

    /// Opens the target the options, the environment and the config file name.
    pub fn connect(&self) -> Result<Session<Box<dyn Transport>>> {
        use host_cli::connect::{choose, open, Target};
        let Settings {
            port,
            baud,
            timeout,
        } = self.settings()?;
        anyhow::ensure!(
            timeout.is_finite() && timeout > 0.0,
            "--timeout {timeout}: must be a positive number of seconds"
        );
        // Listing ports only matters when none was named.
        let ports = if port.is_none() {
            host_cli::serial_ports::list().unwrap_or_default()
        } else {
            Vec::new()
        };
        let (target, why) = choose(port.as_deref(), baud, &ports);
        if target != Target::BuiltIn && port.is_none() {
            eprintln!("using {why}");
        }
        let mut session = Session::new(open(&target)?);
        session.timeout = std::time::Duration::from_secs_f64(timeout);
        Ok(session)
    }
}

/// `--size WxH`, each side in 1..=[`MAX_FRAME_SIDE`](protocol::MAX_FRAME_SIDE).
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    use protocol::MAX_FRAME_SIDE as MAX;
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s:?} is not WxH"))?;
    let w: u32 = w
        .parse()
        .map_err(|_| format!("width {w:?} is not a number"))?;
    let h: u32 = h
        .parse()
        .map_err(|_| format!("height {h:?} is not a number"))?;
    if w == 0 || h == 0 || w > MAX || h > MAX {
        return Err(format!("{w}x{h} is outside 1..={MAX} per side"));
    }
    Ok((w, h))
}

/// One direction of a run's traffic for `--stats`: payload, time, rate and, on a serial
/// port, how much of the line it used.
pub fn phase_line(what: &str, phase: Phase, line_rate: Option<u32>) -> String {
    let mut line = format!(
        "{what:<13} {} B payload in {:.1} ms = {:.1} KB/s",
        phase.payload_bytes,
        phase.time.as_secs_f64() * 1e3,
        phase.rate() / 1e3
    );
    if let Some(baud) = line_rate {
        // 8N1: ten bit times per byte on the wire.
        line.push_str(&format!(
            " = {:.1} % of {baud} baud",
            phase.rate() / (f64::from(baud) / 10.0) * 100.0
        ));
    }
    line
}

/// `FLAG PATH`, how an output is named in the messages of [`check_output_file`] and
/// [`check_output_dir`].
pub fn flag_path(flag: &str, path: &Path) -> String {
    format!("{flag} {}", path.display())
}

/// The directory a file path lives in (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Refuses, before any work, an output file the command could not write at the end:
/// one whose extension is not one of `exts` (lower case, without the dot; `what` says
/// what is written, e.g. "the frame"), whose directory is missing or no directory, that
/// is a directory, or that cannot be opened for writing. The probe leaves the file system
/// as it found it: an existing file is opened without truncating it, a new one is created
/// and removed again. `label` names the flag and the path as the user gave them.
pub fn check_output_file(label: &str, path: &Path, what: &str, exts: &[&str]) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !ext.as_deref().is_some_and(|e| exts.contains(&e)) {
        let kinds: Vec<String> = exts.iter().map(|e| e.to_ascii_uppercase()).collect();
        let names: Vec<String> = exts.iter().map(|e| format!(".{e}")).collect();
        bail!(
            "{label}: {what} is written as {}: give a name ending in {}",
            kinds.join(" or "),
            names.join(" or ")
        );
    }
    check_writable_file(label, path)
}

/// The directory and writability half of [`check_output_file`], for outputs of any name
/// (e.g. `animate --save-frames`, whose files are scene or command text).
pub fn check_writable_file(label: &str, path: &Path) -> Result<()> {
    let dir = parent_dir(path);
    match std::fs::metadata(dir) {
        Err(_) => bail!("{label}: directory {} does not exist", dir.display()),
        Ok(m) if !m.is_dir() => bail!("{label}: {} is not a directory", dir.display()),
        Ok(_) => {}
    }
    if path.is_dir() {
        bail!("{label}: is a directory; name a file");
    }
    let probe = if path.exists() {
        OpenOptions::new().write(true).open(path).map(drop)
    } else {
        OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(path)
            .map(|f| {
                drop(f);
                let _ = std::fs::remove_file(path);
            })
    };
    probe.with_context(|| format!("{label}: cannot be written"))
}

/// Refuses, before any work, an output directory the command could not create or write
/// in: the directory, or its nearest existing ancestor when it is to be created, must be
/// a directory in which a file can be created (a probe file is created and removed).
pub fn check_output_dir(label: &str, dir: &Path) -> Result<()> {
    let mut existing = dir;
    while !existing.exists() {
        match existing.parent() {
            Some(p) if !p.as_os_str().is_empty() => existing = p,
            _ => {
                existing = Path::new(".");
                break;
            }
        }
    }
    if !existing.is_dir() {
        if existing == dir {
            bail!("{label}: is a file, not a directory");
        }
        bail!("{label}: {} is a file, not a directory", existing.display());
    }
    let probe = existing.join(format!(".fpgfx-write-probe-{}", std::process::id()));
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map(|f| {
            drop(f);
            let _ = std::fs::remove_file(&probe);
        })
        .with_context(|| format!("{label}: cannot write in {}", existing.display()))
}
