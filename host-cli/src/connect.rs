//! Which target a command talks to, decided once: `--port` (or `FPGFX_PORT`, or the
//! config file), else the one known USB-serial adapter plugged in, else the built-in
//! target. Everything after [`open`] is transport-agnostic.

use std::io::{self, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::Deserialize;

use crate::serial_ports::PortInfo;
use crate::session::Transport;

/// `fpgfx.toml`: defaults for the options every command shares.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// Same as `--port`.
    pub port: Option<String>,
    /// Same as `--baud`.
    pub baud: Option<u32>,
    /// Same as `--timeout`, in seconds.
    pub timeout: Option<f64>,
}

/// Problems with the config file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ConfigError {
    /// It exists but cannot be read.
    #[error("cannot read {path}")]
    Read {
        /// The config file that failed to read.
        path: PathBuf,
        /// The underlying error, reported as this one's `source()`.
        source: io::Error,
    },
    /// It is not valid TOML or has unknown keys; the parser's message has line and column.
    #[error("{path}: {message}")]
    Parse {
        /// The config file, named in the message.
        path: PathBuf,
        /// The parser's message.
        message: String,
    },
}

/// Where the config file is looked for, first match wins: `$FPGFX_CONFIG`, `./fpgfx.toml`,
/// `$XDG_CONFIG_HOME/fpgfx/config.toml`, `~/.config/fpgfx/config.toml`.
pub fn config_candidates() -> Vec<PathBuf> {
    let mut c = Vec::new();
    if let Some(p) = std::env::var_os("FPGFX_CONFIG") {
        c.push(PathBuf::from(p));
        return c;
    }
    c.push(PathBuf::from("fpgfx.toml"));
    if let Some(x) = std::env::var_os("XDG_CONFIG_HOME") {
        c.push(Path::new(&x).join("fpgfx/config.toml"));
    }
    if let Some(h) = std::env::var_os("HOME") {
        c.push(Path::new(&h).join(".config/fpgfx/config.toml"));
    }
    c
}

/// Loads the first config file that exists (an explicit `$FPGFX_CONFIG` must exist).
pub fn load_config() -> Result<Option<(PathBuf, Config)>, ConfigError> {
    let explicit = std::env::var_os("FPGFX_CONFIG").is_some();
    for path in config_candidates() {
        match std::fs::read_to_string(&path) {
            Ok(text) => {
                let cfg = toml::from_str(&text).map_err(|e| ConfigError::Parse {
                    path: path.clone(),
                    message: e.to_string(),
                })?;
                return Ok(Some((path, cfg)));
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound && !explicit => {}
            Err(source) => return Err(ConfigError::Read { path, source }),
        }
    }
    Ok(None)
}

/// Line rate of a serial target when neither `--baud` nor the config file sets one.
pub const DEFAULT_BAUD: u32 = 115_200;
/// Seconds to wait for the handshake when neither `--timeout` nor the config file says.
pub const DEFAULT_TIMEOUT_S: f64 = 10.0;

/// The options every command shares once the config file and the defaults have filled in
/// what the flags left out.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// The target, if anything named one ([`choose`] decides otherwise).
    pub port: Option<String>,
    /// Line rate of a serial target.
    pub baud: u32,
    /// Handshake timeout in seconds, as given (the caller checks it is usable).
    pub timeout: f64,
}

impl Settings {
    /// Each option from its flag (`flags`, shaped like the file), else from `file`, else
    /// its default.
    pub fn merge(flags: Config, file: Config) -> Settings {
        Settings {
            port: flags.port.or(file.port),
            baud: flags.baud.or(file.baud).unwrap_or(DEFAULT_BAUD),
            timeout: flags.timeout.or(file.timeout).unwrap_or(DEFAULT_TIMEOUT_S),
        }
    }
}

/// [`Settings::merge`] of the flags with the config file [`load_config`] finds (with
/// none, the defaults).
pub fn resolve(flags: Config) -> Result<Settings, ConfigError> {
    let file = load_config()?.map(|(_, c)| c).unwrap_or_default();
    Ok(Settings::merge(flags, file))
}

/// A target to talk to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// The controller and FPGA model in this process.
    BuiltIn,
    /// The same with the controller's register-bus driver (`firmware::MmioBus`) on the
    /// model's AXI4-Lite registers (written `builtin:mmio`).
    BuiltInMmio,
    /// The controller in this process driving the FITkit block's RTL (Verilated) over its
    /// SPI pins.
    Rtl,
    /// The controller in this process driving the ray-casting core's RTL (Verilated) over
    /// its AXI4-Lite pins with its register driver (written `rtl:rt`).
    RtlRt,
    /// A serial port (a board's USB-UART, `fpgfx-sim --pty`, QEMU's pty).
    Serial {
        /// Device path (`/dev/ttyUSB0`, a pty's `/dev/pts/N`).
        path: String,
        /// Line rate in baud.
        baud: u32,
    },
    /// `fpgfx-sim --tcp` (written `tcp:HOST:PORT`).
    Tcp(String),
}

impl Target {
    /// Parses a `--port` value: `builtin`, `builtin:mmio`, `rtl`, `rtl:rt`, `tcp:HOST:PORT`
    /// (or `tcp://HOST:PORT`), or a serial device path.
    pub fn parse(port: &str, baud: u32) -> Target {
        if port == "builtin" {
            Target::BuiltIn
        } else if port == "builtin:mmio" {
            Target::BuiltInMmio
        } else if port == "rtl" {
            Target::Rtl
        } else if port == "rtl:rt" {
            Target::RtlRt
        } else if let Some(addr) = port
            .strip_prefix("tcp://")
            .or_else(|| port.strip_prefix("tcp:"))
        {
            Target::Tcp(addr.to_string())
        } else {
            Target::Serial {
                path: port.to_string(),
                baud,
            }
        }
    }
}

/// Decides the target: an explicit port (flag, environment or config, already merged by
/// the caller) wins; otherwise exactly one known USB-serial adapter among `ports` is used;
/// otherwise the built-in target. The string says why, for the user.
pub fn choose(port: Option<&str>, baud: u32, ports: &[PortInfo]) -> (Target, String) {
    if let Some(p) = port {
        return (Target::parse(p, baud), format!("--port {p}"));
    }
    match crate::serial_ports::the_one_adapter(ports) {
        Some(p) => (
            Target::Serial {
                path: p.path.clone(),
                baud,
            },
            format!(
                "the only known adapter: {} (use --port builtin for the built-in target)",
                crate::serial_ports::describe(p)
            ),
        ),
        None => (Target::BuiltIn, "no --port: the built-in target".into()),
    }
}

/// Why a target could not be opened.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ConnectError {
    /// No such device.
    #[error("serial port {0} does not exist (`fpgfx ports` lists the ports of this machine)")]
    Missing(String),
    /// Another program has it open.
    #[error("serial port {0} is busy: another program has it open (a terminal, another fpgfx, ModemManager?)")]
    Busy(String),
    /// The user may not open the device (not in its group).
    #[error("no permission to open serial port {0} (on Debian, join the `dialout` group)")]
    Permission(String),
    /// Anything else the port said.
    #[error("cannot open serial port {path} at {baud} baud: {message}")]
    Serial {
        /// Device path as given.
        path: String,
        /// Line rate in baud it was opened at.
        baud: u32,
        /// The driver's message.
        message: String,
    },
    /// The RTL target is not in this build (no verilator when it was built).
    #[error("--port rtl")]
    Rtl(#[from] sim_board::rtl::RtlTargetError),
    /// The ray-casting core's RTL target is not in this build, or its probe failed.
    #[error("--port rtl:rt")]
    RtlRt(#[from] sim_board::rt_rtl::RtRtlTargetError),
    /// The register-bus driver did not find the model's device (a broken build).
    #[error("--port builtin:mmio: {0}")]
    Mmio(firmware::MmioError<sim_target::mmio::RegisterError>),
    /// TCP connection failed.
    #[error("cannot connect to {addr}")]
    Tcp {
        /// `HOST:PORT` as given after `tcp:`.
        addr: String,
        /// The underlying error, reported as this one's `source()`.
        source: io::Error,
    },
}

impl ConnectError {
    /// What opening serial port `path` at `baud` failed with, in the user's terms: the
    /// one reading of serialport's errors, for the link and for `flash` alike.
    ///
    /// serialport 4 on Linux opens with `O_NOCTTY`, then takes `TIOCEXCL` and an exclusive
    /// `flock`. Another process holding the port makes `open` fail with EBUSY (its
    /// `TIOCEXCL`; root passes that check) or the `flock` fail with EWOULDBLOCK, and it
    /// reports both as [`serialport::ErrorKind::NoDevice`]: "busy", not "missing". A
    /// missing node is ENOENT, i.e. `Io(NotFound)`, and EACCES is `Io(PermissionDenied)`.
    pub fn serial_open(path: &str, baud: u32, e: serialport::Error) -> ConnectError {
        use serialport::ErrorKind as K;
        let path = path.to_string();
        match e.kind {
            K::NoDevice | K::Io(io::ErrorKind::ResourceBusy) => ConnectError::Busy(path),
            K::Io(io::ErrorKind::NotFound) => ConnectError::Missing(path),
            K::Io(io::ErrorKind::PermissionDenied) => ConnectError::Permission(path),
            _ => ConnectError::Serial {
                path,
                baud,
                message: e.description,
            },
        }
    }
}

/// Opens a serial or TCP target (the built-in one is made by the caller, which chooses
/// its bus layout).
pub fn open(target: &Target) -> Result<Box<dyn Transport>, ConnectError> {
    match target {
        Target::BuiltIn => Ok(Box::new(sim_board::in_process::sim_target())),
        Target::BuiltInMmio => sim_board::in_process::sim_target_mmio()
            .map(|t| Box::new(t) as Box<dyn Transport>)
            .map_err(ConnectError::Mmio),
        Target::Rtl => Ok(Box::new(sim_board::rtl::rtl_target()?)),
        Target::RtlRt => Ok(Box::new(sim_board::rt_rtl::rt_rtl_target()?)),
        Target::Serial { path, baud } => crate::serial::SerialTransport::open(path, *baud)
            .map(|t| Box::new(t) as Box<dyn Transport>)
            .map_err(|e| ConnectError::serial_open(path, *baud, e)),
        Target::Tcp(addr) => TcpStream::connect(addr)
            .and_then(TcpTransport::new)
            .map(|t| Box::new(t) as Box<dyn Transport>)
            .map_err(|source| ConnectError::Tcp {
                addr: addr.clone(),
                source,
            }),
    }
}

/// A TCP connection as a [`Transport`].
pub struct TcpTransport(TcpStream);

impl TcpTransport {
    /// Wraps a connected stream (Nagle off: link frames and ACKs are small and latency-bound).
    pub fn new(stream: TcpStream) -> io::Result<Self> {
        stream.set_nodelay(true)?;
        Ok(Self(stream))
    }
}

impl Transport for TcpTransport {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.0.write_all(bytes)
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        self.0
            .set_read_timeout(Some(timeout.max(Duration::from_millis(1))))?;
        match self.0.read(buf) {
            Ok(0) => Err(io::Error::new(
                io::ErrorKind::ConnectionAborted,
                "the target closed the connection",
            )),
            Ok(n) => Ok(n),
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                ) =>
            {
                Ok(0)
            }
            Err(e) => Err(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flag_beats_the_file_and_the_file_beats_the_default() {
        let file = Config {
            port: Some("/dev/ttyUSB1".into()),
            baud: Some(921_600),
            timeout: None,
        };
        let flags = Config {
            port: Some("builtin".into()),
            ..Config::default()
        };
        assert_eq!(
            Settings::merge(flags, file),
            Settings {
                port: Some("builtin".into()),
                baud: 921_600,
                timeout: DEFAULT_TIMEOUT_S,
            }
        );
        let none = Settings::merge(Config::default(), Config::default());
        assert_eq!((none.port, none.baud), (None, DEFAULT_BAUD));
    }

    #[test]
    fn builtin_mmio_is_a_target_of_its_own() {
        assert_eq!(Target::parse("builtin:mmio", 9600), Target::BuiltInMmio);
        assert_eq!(Target::parse("builtin", 9600), Target::BuiltIn);
        assert!(matches!(
            Target::parse("builtin:mmi", 9600),
            Target::Serial { .. }
        ));
    }

    #[test]
    fn each_rtl_block_is_a_target_of_its_own() {
        assert_eq!(Target::parse("rtl", 9600), Target::Rtl);
        assert_eq!(Target::parse("rtl:rt", 9600), Target::RtlRt);
        assert!(matches!(
            Target::parse("rtl:r", 9600),
            Target::Serial { .. }
        ));
    }

    /// The errors serialport 4 gives on Linux for the ways an open fails, as its posix
    /// back end words them.
    #[test]
    fn serial_open_errors_read_as_the_user_would_say_them() {
        use serialport::{Error, ErrorKind as K};
        let read =
            |kind, text: &str| ConnectError::serial_open("/dev/x", 9600, Error::new(kind, text));
        // Another process's TIOCEXCL (EBUSY), or its flock as root.
        for text in [
            "Device or resource busy",
            "Unable to acquire exclusive lock on serial port",
        ] {
            let e = read(K::NoDevice, text);
            assert!(matches!(&e, ConnectError::Busy(p) if p == "/dev/x"), "{e}");
            assert!(e.to_string().contains("/dev/x is busy"), "{e}");
        }
        let e = read(K::Io(io::ErrorKind::NotFound), "No such file or directory");
        assert!(matches!(e, ConnectError::Missing(_)), "{e}");
        let e = read(K::Io(io::ErrorKind::PermissionDenied), "Permission denied");
        assert!(matches!(e, ConnectError::Permission(_)), "{e}");
        // ENXIO: a node whose device is gone.
        let e = read(K::Unknown, "No such device or address");
        assert_eq!(
            e.to_string(),
            "cannot open serial port /dev/x at 9600 baud: No such device or address"
        );
    }
}
