//! Serial ports on this machine, with what is behind them (USB VID:PID, maker, product).
//!
//! Read from sysfs (`/sys/class/tty/*/device`, walking up to the USB device that carries
//! `idVendor`) rather than through libudev, so that the tool builds without a system
//! library and the listing is testable against a fixture tree.

use std::path::{Path, PathBuf};

/// One serial port.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortInfo {
    /// Device node, e.g. `/dev/ttyUSB0`.
    pub path: String,
    /// USB identity, if the port is a USB device.
    pub usb: Option<UsbInfo>,
}

/// What a USB serial adapter says about itself.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UsbInfo {
    /// USB vendor id (`idVendor`), matched against [`KNOWN_ADAPTERS`].
    pub vid: u16,
    /// USB product id (`idProduct`), matched against [`KNOWN_ADAPTERS`].
    pub pid: u16,
    /// `manufacturer` string, if any.
    pub manufacturer: Option<String>,
    /// `product` string, if any.
    pub product: Option<String>,
    /// `serial` string, if any.
    pub serial: Option<String>,
}

/// USB-serial bridges found on the seeds' boards and on common Cortex-M boards: with no
/// `--port`, exactly one of these present is taken as the board.
pub const KNOWN_ADAPTERS: &[(u16, u16, &str)] = &[
    (0x0403, 0x6001, "FTDI FT232R"),
    (0x0403, 0x6010, "FTDI FT2232 (FITkit, Digilent boards)"),
    (0x0403, 0x6014, "FTDI FT232H"),
    (0x0403, 0x6015, "FTDI FT-X"),
    (0x10c4, 0xea60, "Silicon Labs CP210x"),
    (0x10c4, 0xea71, "Silicon Labs CP2108 (KCU116)"),
    (0x1a86, 0x7523, "WCH CH340"),
    (0x1a86, 0x55d4, "WCH CH9102"),
    (0x067b, 0x2303, "Prolific PL2303"),
    (0x0483, 0x374b, "ST-LINK/V2-1 virtual COM port"),
    (0x0483, 0x374e, "STLINK-V3 virtual COM port"),
    (0x0483, 0x3752, "ST-LINK/V2-1 virtual COM port"),
    (0x0483, 0x3753, "STLINK-V3 virtual COM port"),
    (0x2e8a, 0x000c, "Raspberry Pi Debug Probe"),
];

impl PortInfo {
    /// The known adapter this port is, if any.
    pub fn known_adapter(&self) -> Option<&'static str> {
        let usb = self.usb.as_ref()?;
        KNOWN_ADAPTERS
            .iter()
            .find(|(v, p, _)| *v == usb.vid && *p == usb.pid)
            .map(|(_, _, name)| *name)
    }
}

/// The serial ports of this machine: USB serial devices and hardware UARTs (those whose
/// sysfs entry has a device behind it; virtual consoles and ptys have none).
pub fn list() -> std::io::Result<Vec<PortInfo>> {
    list_in(Path::new("/sys/class/tty"), Path::new("/dev"))
}

/// [`list`] over another sysfs `class/tty` directory and device directory (for tests).
pub fn list_in(class_tty: &Path, dev: &Path) -> std::io::Result<Vec<PortInfo>> {
    let mut ports = Vec::new();
    let entries = match std::fs::read_dir(class_tty) {
        Ok(e) => e,
        // No sysfs (a container, another OS): no ports, not an error.
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(ports),
        Err(e) => return Err(e),
    };
    for entry in entries {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let Ok(device) = std::fs::canonicalize(entry.path().join("device")) else {
            continue;
        };
        // Legacy 8250 UARTs are registered whether or not a chip exists; only the
        // ones a driver bound to real hardware (ttyS with a serial8250 parent and no
        // port type are the phantom ones) would be useful, and we cannot tell here
        // without opening them: list ttyS only when they are not the platform stubs.
        if name.starts_with("ttyS") && device.ends_with("serial8250") {
            continue;
        }
        ports.push(PortInfo {
            path: dev.join(&name).display().to_string(),
            usb: usb_info(&device),
        });
    }
    ports.sort_by(|a, b| a.path.cmp(&b.path));
    Ok(ports)
}

/// Walks up from the tty's device to the USB device that has `idVendor`.
fn usb_info(device: &Path) -> Option<UsbInfo> {
    let mut dir: Option<PathBuf> = Some(device.to_path_buf());
    while let Some(d) = dir {
        if let Some(vid) = read_hex(&d.join("idVendor")) {
            let text = |f: &str| {
                std::fs::read_to_string(d.join(f))
                    .ok()
                    .map(|s| s.trim().to_string())
                    .filter(|s| !s.is_empty())
            };
            return Some(UsbInfo {
                vid,
                pid: read_hex(&d.join("idProduct"))?,
                manufacturer: text("manufacturer"),
                product: text("product"),
                serial: text("serial"),
            });
        }
        dir = d.parent().map(Path::to_path_buf);
    }
    None
}

fn read_hex(path: &Path) -> Option<u16> {
    let s = std::fs::read_to_string(path).ok()?;
    u16::from_str_radix(s.trim(), 16).ok()
}

/// The one known adapter among `ports`, if there is exactly one.
pub fn the_one_adapter(ports: &[PortInfo]) -> Option<&PortInfo> {
    let mut known = ports.iter().filter(|p| p.known_adapter().is_some());
    match (known.next(), known.next()) {
        (Some(p), None) => Some(p),
        _ => None,
    }
}

/// One line per port, as `fpgfx ports` prints them.
pub fn describe(p: &PortInfo) -> String {
    match &p.usb {
        None => format!("{}  (no USB device)", p.path),
        Some(u) => {
            let mut s = format!("{}  USB {:04x}:{:04x}", p.path, u.vid, u.pid);
            for part in [&u.manufacturer, &u.product].into_iter().flatten() {
                s.push_str("  ");
                s.push_str(part);
            }
            if let Some(serial) = &u.serial {
                s.push_str(&format!("  serial {serial}"));
            }
            if let Some(known) = p.known_adapter() {
                s.push_str(&format!("  [{known}]"));
            }
            s
        }
    }
}
