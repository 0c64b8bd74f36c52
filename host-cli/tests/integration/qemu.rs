//! The real board binary in QEMU (`netduinoplus2`, STM32F405): USART1 is the host link,
//! USART2 the FPGA link served by `fpgfx-sim --fpga-link`. `fpgfx raster` and `fpgfx
//! render` against USART1 must give images identical to built-in mode, and the board's
//! defmt log (semihosting, decoded with the ELF's format table) is printed into the test
//! log. `cargo test qemu` runs just this. QEMU comes from Debian (`cargo xtask setup`).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::common::{
    collect, every_primitive, example, ok, rgb, sim_command, tmp, workspace, KillOnDrop,
};

const TARGET: &str = "thumbv7em-none-eabihf";

/// Builds the board binary (a no-op when `cargo xtask test` already did) and returns it.
fn firmware_elf() -> PathBuf {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(workspace())
        .args(["build", "-q", "-p", "firmware", "--features", "board-stm32"])
        .args(["--target", TARGET, "--profile", "firmware"])
        .status()
        .expect("cargo runs");
    assert!(status.success(), "building the board binary failed");
    let target_dir = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace().join("target"));
    target_dir
        .join(TARGET)
        .join("firmware")
        .join("fpgfx-firmware")
}

/// QEMU's stdout: first its "char device redirected to /dev/pts/N (label serialK)"
/// lines, then the semihosting bytes (defmt frames).
struct Qemu {
    _child: KillOnDrop,
    out: Arc<Mutex<Vec<u8>>>,
}

impl Qemu {
    fn start(elf: &Path) -> (Self, String, String) {
        let found = Command::new("qemu-system-arm").arg("--version").output();
        assert!(
            found.is_ok_and(|o| o.status.success()),
            "qemu-system-arm is not installed: run `cargo xtask setup` (Debian package \
             qemu-system-arm)"
        );
        let mut child = Command::new("qemu-system-arm")
            .args([
                "-M",
                "netduinoplus2",
                "-display",
                "none",
                "-monitor",
                "none",
            ])
            .args(["-semihosting-config", "enable=on,target=native"])
            .args(["-serial", "pty", "-serial", "pty", "-kernel"])
            .arg(elf)
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("qemu-system-arm starts");
        let stdout = child.stdout.take().expect("piped");
        let (out, _reader) = collect(stdout);
        let qemu = Qemu {
            _child: KillOnDrop(child),
            out,
        };
        let started = Instant::now();
        loop {
            let ptys = qemu.ptys();
            if ptys.len() == 2 {
                return (qemu, ptys[0].clone(), ptys[1].clone());
            }
            assert!(
                started.elapsed() < Duration::from_secs(20),
                "QEMU did not report two ptys: {:?}",
                String::from_utf8_lossy(&qemu.out.lock().expect("lock"))
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    fn ptys(&self) -> Vec<String> {
        let out = self.out.lock().expect("lock");
        String::from_utf8_lossy(&out)
            .lines()
            .filter_map(|l| l.strip_prefix("char device redirected to "))
            .filter_map(|l| l.split_whitespace().next())
            .map(str::to_string)
            .collect()
    }

    /// The board's log so far, decoded.
    fn log(&self, elf: &Path) -> Vec<String> {
        let out = self.out.lock().expect("lock").clone();
        // Skip QEMU's own text lines; everything after them is defmt.
        let mut start = 0;
        while out[start..].starts_with(b"char device redirected") {
            match out[start..].iter().position(|&b| b == b'\n') {
                Some(nl) => start += nl + 1,
                None => break,
            }
        }
        let bytes = std::fs::read(elf).expect("ELF readable");
        let table = defmt_decoder::Table::parse(&bytes)
            .expect("defmt table parses")
            .expect("the ELF has defmt data");
        let mut decoder = table.new_stream_decoder();
        decoder.received(&out[start..]);
        let mut lines = Vec::new();
        loop {
            match decoder.decode() {
                Ok(frame) => lines.push(format!(
                    "{} {}",
                    frame
                        .level()
                        .map(|l| l.as_str().to_uppercase())
                        .unwrap_or_default(),
                    frame.display_message()
                )),
                Err(defmt_decoder::DecodeError::UnexpectedEof) => break,
                Err(defmt_decoder::DecodeError::Malformed) => {
                    lines.push("(malformed defmt frame)".into());
                    break;
                }
            }
        }
        lines
    }
}

/// `fpgfx render` of the reference scene, small and in Q16.16 (the board's format), on
/// the board at `port` (with `--stats`, whose stdout it returns) or built-in.
fn render(port: Option<&str>, out: &str) -> String {
    let scene = example("reference.toml");
    let mut args = vec![
        "--port",
        "builtin",
        "render",
        &scene,
        "--size",
        "48x27",
        "--numeric",
        "q16.16",
        "-o",
        out,
    ];
    if let Some(port) = port {
        args[1] = port;
        args.push("--stats");
    }
    ok(&args).stdout
}

/// The board in QEMU with `fpgfx-sim --fpga-link` and `fpga_args` on its USART2: QEMU,
/// the host link's pty, and the FPGA's process (both killed on drop).
fn board(elf: &Path, fpga_args: &[&str]) -> (Qemu, String, KillOnDrop) {
    let (qemu, host_pty, fpga_pty) = Qemu::start(elf);
    let fpga = KillOnDrop(
        sim_command()
            .args(["--fpga-link", &fpga_pty])
            .args(fpga_args)
            .stderr(Stdio::inherit())
            .spawn()
            .expect("fpgfx-sim starts"),
    );
    (qemu, host_pty, fpga)
}

/// Asserts that the board booted, reached its FPGA and a host, and did not panic.
fn assert_board_log(qemu: &Qemu, elf: &Path) {
    let log = qemu.log(elf);
    println!("--- board log (defmt over semihosting) ---");
    for line in &log {
        println!("{line}");
    }
    let has = |s: &str| log.iter().any(|l| l.contains(s));
    assert!(has("fpgfx-firmware"), "no boot line in the board log");
    assert!(has("FPGA up"), "the board never reached the FPGA");
    assert!(has("host session"), "the board never saw a host session");
    assert!(!has("panic"), "the board panicked");
}

#[test]
fn qemu_board_draws_and_renders_like_built_in() {
    let elf = firmware_elf();
    let (qemu, host_pty, _fpga) = board(&elf, &[]);

    // A raster job with every primitive, small enough that its read-back (QEMU delivers
    // UART bytes one per main-loop turn, ~6 KB/s) takes a few seconds.
    let file = tmp("raster.toml");
    let aa = "[aa]\npattern = \"rotated\"\nsamples = 4";
    std::fs::write(&file, every_primitive(96, 64, aa)).expect("temp file");
    let (board, built_in) = (tmp("board.png"), tmp("built-in.png"));
    let started = Instant::now();
    let stats = ok(&[
        "--port", &host_pty, "raster", &file, "-o", &board, "--stats",
    ])
    .stdout;
    let raster_time = started.elapsed();
    ok(&["--port", "builtin", "raster", &file, "-o", &built_in]);
    assert_eq!(
        rgb(&board),
        rgb(&built_in),
        "raster image differs from built-in"
    );
    println!("raster over QEMU in {raster_time:?}:\n{stats}");

    let (board, built_in) = (tmp("board-rt.png"), tmp("built-in-rt.png"));
    let started = Instant::now();
    let stats = render(Some(&host_pty), &board);
    let render_time = started.elapsed();
    render(None, &built_in);
    assert_eq!(rgb(&board), rgb(&built_in), "render differs from built-in");
    println!("render over QEMU in {render_time:?}:\n{stats}");
    assert_board_log(&qemu, &elf);
}

/// The QEMU board with the FITkit block's RTL on its FPGA link: `fpgfx-sim --fpga-link
/// --fpga rtl` answers the link through the same SPI driver a FITkit MCU runs, so the
/// board identifies a FITkit-layout FPGA, packs FITkit records, and its frame must equal
/// the RTL's in process (`--port rtl`) and the golden model's (`--port builtin`).
#[test]
fn qemu_board_draws_on_the_rtl() {
    let elf = firmware_elf();
    let (qemu, host_pty, _fpga) = board(&elf, &["--fpga", "rtl"]);
    // Small (QEMU moves ~6 KB/s of read-back) and within what the FITkit draws: whole
    // pixels, flat colours in RGB332, a clear, lines in every direction.
    let file = tmp("fitkit-small.toml");
    let job = r##"size = [64, 48]
background = "#000000"
subpixel_bits = 0
[[cmd]]
op = "clear"
color = "#2449aa"
[[cmd]]
op = "triangle"
v = [[2.0, 3.0], [60.0, 10.0], [14.0, 45.0]]
color = "#dbb655"
[[cmd]]
op = "line"
from = [0.0, 47.0]
to = [63.0, 0.0]
color = "#ffffff"
[[cmd]]
op = "line"
from = [63.0, 47.0]
to = [5.0, 1.0]
color = "#00ff00"
"##;
    std::fs::write(&file, job).expect("temp file");
    let (board, in_process, built_in) = (tmp("rtl-board.png"), tmp("rtl.png"), tmp("model.png"));
    let started = Instant::now();
    let stats = ok(&[
        "--port", &host_pty, "raster", &file, "-o", &board, "--stats",
    ])
    .stdout;
    println!(
        "raster over QEMU onto the RTL in {:?}:\n{stats}",
        started.elapsed()
    );
    ok(&["--port", "rtl", "raster", &file, "-o", &in_process]);
    ok(&["--port", "builtin", "raster", &file, "-o", &built_in]);
    assert_eq!(
        rgb(&board),
        rgb(&in_process),
        "board frame differs from --port rtl"
    );
    assert_eq!(
        rgb(&board),
        rgb(&built_in),
        "board frame differs from the model"
    );
    // The board learnt the FITkit layout from the FPGA's identity: what it cannot carry
    // is refused by name before anything is sent.
    let err = crate::common::fails(&[
        "--port",
        &host_pty,
        "raster",
        &example("raster/gallery.toml"),
        "-o",
        &tmp("never.png"),
    ]);
    assert!(
        err.contains("gallery.toml: cmd[0] (clear)") && err.contains("fitkit layout"),
        "{err}"
    );
    assert_board_log(&qemu, &elf);
}
