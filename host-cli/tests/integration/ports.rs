//! `fpgfx ports` and target selection: ports listed from a sysfs fixture with their USB
//! identity, the one known adapter chosen when no port is named, the config file's
//! defaults and its errors.

use std::os::unix::fs::symlink;
use std::path::Path;

use crate::common::{assert_fails, assert_ok, example, fpgfx_command, run, Run};

use host_cli::connect::{choose, Target};
use host_cli::serial_ports::{describe, list_in, the_one_adapter};

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().expect("parent")).expect("mkdir");
    std::fs::write(path, text).expect("write");
}

/// A sysfs tree: an FTDI FT2232 (known), an unknown USB device, a real 16550 on PNP, a
/// phantom 8250 and a virtual console.
fn fixture() -> tempdir::TempDir {
    let dir = tempdir::TempDir::new();
    let root = dir.path();
    let ftdi = root.join("devices/pci0/usb1/1-1");
    write(&ftdi.join("idVendor"), "0403\n");
    write(&ftdi.join("idProduct"), "6010\n");
    write(&ftdi.join("manufacturer"), "FTDI\n");
    write(&ftdi.join("product"), "Dual RS232-HS\n");
    write(&ftdi.join("serial"), "FITKIT42\n");
    std::fs::create_dir_all(ftdi.join("1-1:1.0/ttyUSB0")).expect("mkdir");
    let other = root.join("devices/pci0/usb1/1-2");
    write(&other.join("idVendor"), "1234\n");
    write(&other.join("idProduct"), "5678\n");
    std::fs::create_dir_all(other.join("1-2:1.0/ttyACM0")).expect("mkdir");
    std::fs::create_dir_all(root.join("devices/pnp0/00:05")).expect("mkdir");
    std::fs::create_dir_all(root.join("devices/platform/serial8250")).expect("mkdir");
    let tty = root.join("class/tty");
    for (name, target) in [
        ("ttyUSB0", "devices/pci0/usb1/1-1/1-1:1.0/ttyUSB0"),
        ("ttyACM0", "devices/pci0/usb1/1-2/1-2:1.0/ttyACM0"),
        ("ttyS0", "devices/pnp0/00:05"),
        ("ttyS1", "devices/platform/serial8250"),
    ] {
        std::fs::create_dir_all(tty.join(name)).expect("mkdir");
        symlink(root.join(target), tty.join(name).join("device")).expect("symlink");
    }
    std::fs::create_dir_all(tty.join("tty0")).expect("mkdir");
    dir
}

#[test]
fn ports_are_listed_with_their_usb_identity() {
    let dir = fixture();
    let ports = list_in(&dir.path().join("class/tty"), Path::new("/dev")).expect("lists");
    let lines: Vec<String> = ports.iter().map(describe).collect();
    assert_eq!(
        lines,
        vec![
            "/dev/ttyACM0  USB 1234:5678".to_string(),
            "/dev/ttyS0  (no USB device)".to_string(),
            "/dev/ttyUSB0  USB 0403:6010  FTDI  Dual RS232-HS  serial FITKIT42  \
             [FTDI FT2232 (FITkit, Digilent boards)]"
                .to_string(),
        ]
    );
    let one = the_one_adapter(&ports).expect("one known adapter");
    assert_eq!(one.path, "/dev/ttyUSB0");
}

#[test]
fn target_choice_prefers_the_named_port_then_the_one_adapter() {
    let dir = fixture();
    let ports = list_in(&dir.path().join("class/tty"), Path::new("/dev")).expect("lists");
    assert_eq!(
        choose(Some("tcp:127.0.0.1:9"), 115_200, &ports).0,
        Target::Tcp("127.0.0.1:9".into())
    );
    assert_eq!(choose(Some("builtin"), 115_200, &ports).0, Target::BuiltIn);
    assert_eq!(
        choose(None, 921_600, &ports).0,
        Target::Serial {
            path: "/dev/ttyUSB0".into(),
            baud: 921_600
        }
    );
    // Two known adapters: ambiguous, so the built-in target.
    let mut two = ports.clone();
    two.push(two[2].clone());
    two[3].path = "/dev/ttyUSB1".into();
    assert_eq!(choose(None, 115_200, &two).0, Target::BuiltIn);
    assert_eq!(choose(None, 115_200, &[]).0, Target::BuiltIn);
}

/// `fpgfx ARGS…` with this config file instead of none.
fn fpgfx_with_config(config: &Path, args: &[&str]) -> Run {
    run(fpgfx_command(args).env("FPGFX_CONFIG", config))
}

#[test]
fn the_config_file_supplies_the_port_and_its_errors_name_it() {
    let dir = tempdir::TempDir::new();
    let gallery = example("raster/gallery.toml");
    let cfg = dir.path().join("fpgfx.toml");
    std::fs::write(&cfg, "port = \"/dev/fpgfx-from-config\"\n").expect("write");
    // Every run writes into the test's own directory: the default `raster.png` in the
    // shared working directory would race the other tests' output checks.
    let png = dir.path().join("g.png").display().to_string();
    let args = ["raster", &gallery, "-o", &png];
    let err = assert_fails(fpgfx_with_config(&cfg, &args), &args);
    assert!(
        err.contains("serial port /dev/fpgfx-from-config does not exist"),
        "{err}"
    );

    // The flag wins over the file.
    let args = ["--port", "builtin", "raster", &gallery, "-o", &png];
    assert_ok(fpgfx_with_config(&cfg, &args), &args);

    std::fs::write(&cfg, "port = \"builtin\"\nbaud_rate = 9600\n").expect("write");
    let args = ["raster", &gallery, "-o", &png];
    let err = assert_fails(fpgfx_with_config(&cfg, &args), &args);
    assert!(err.contains(&cfg.display().to_string()), "{err}");
    assert!(err.contains("baud_rate"), "{err}");
}

/// A temporary directory removed at the end of the test (no extra dependency).
mod tempdir {
    pub struct TempDir(std::path::PathBuf);

    impl TempDir {
        pub fn new() -> Self {
            static N: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
            let n = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let p = std::env::temp_dir().join(format!("fpgfx-ports-{}-{n}", std::process::id()));
            std::fs::create_dir_all(&p).expect("temp dir");
            TempDir(p)
        }

        pub fn path(&self) -> &std::path::Path {
            &self.0
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}
