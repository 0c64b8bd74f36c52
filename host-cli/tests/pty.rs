//! End to end over a real pseudo-terminal: `fpgfx-sim --pty` serves the controller and the
//! FPGA model, `fpgfx --port` drives it. The images must equal built-in mode's, and a
//! second host session on the same running board must work (the link resynchronises).

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

struct Sim(Child);

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn start_sim() -> (Sim, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_fpgfx-sim"))
        .arg("--pty")
        .stdout(Stdio::piped())
        .spawn()
        .expect("fpgfx-sim starts");
    let stdout = child.stdout.take().expect("piped stdout");
    let mut line = String::new();
    BufReader::new(stdout)
        .read_line(&mut line)
        .expect("fpgfx-sim prints its pty");
    let path = line.trim().to_string();
    assert!(path.starts_with("/dev/"), "unexpected pty path {path:?}");
    (Sim(child), path)
}

fn fpgfx(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_fpgfx"))
        .args(args)
        .output()
        .expect("fpgfx runs");
    assert!(
        out.status.success(),
        "fpgfx {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn tmp(name: &str) -> String {
    std::env::temp_dir()
        .join(format!("fpgfx-pty-{}-{name}", std::process::id()))
        .display()
        .to_string()
}

fn rgb(path: &str) -> image::RgbImage {
    image::open(path).expect("PNG written").to_rgb8()
}

#[test]
fn pty_board_draws_what_built_in_draws() {
    let (_sim, pty) = start_sim();
    let root = env!("CARGO_MANIFEST_DIR");
    let gallery = format!("{root}/../examples/raster/gallery.toml");
    let golden = rgb(&format!("{root}/../examples/raster/golden/gallery.png"));

    // Two host sessions against the same running board.
    for run in 0..2 {
        let out = tmp(&format!("gallery{run}.png"));
        fpgfx(&["--port", &pty, "raster", &gallery, "-o", &out]);
        assert!(
            rgb(&out) == golden,
            "raster over the pty (run {run}) differs from the golden"
        );
    }

    let scene = format!("{root}/../examples/rt/shapes.toml");
    let (over_pty, built_in) = (tmp("shapes-pty.png"), tmp("shapes-builtin.png"));
    fpgfx(&[
        "--port", &pty, "render", &scene, "--size", "96x54", "-o", &over_pty,
    ]);
    fpgfx(&["render", &scene, "--size", "96x54", "-o", &built_in]);
    assert!(
        rgb(&over_pty) == rgb(&built_in),
        "render over the pty differs from built-in"
    );
}

#[test]
fn a_port_that_does_not_exist_is_a_clear_error() {
    let gallery = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/raster/gallery.toml"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_fpgfx"))
        .args(["--port", "/dev/fpgfx-no-such-port", "raster", gallery])
        .output()
        .expect("fpgfx runs");
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("cannot open serial port /dev/fpgfx-no-such-port at 115200 baud"),
        "{err}"
    );
}
