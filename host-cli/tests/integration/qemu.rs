//! The real board binaries in QEMU. Here the STM32F405 (`netduinoplus2`): USART1 is the
//! host link, USART2 the FPGA link served by `fpgfx-sim --fpga-link`. `fpgfx raster` and
//! `fpgfx render` against USART1 must give images identical to built-in mode, and the
//! board's defmt log (semihosting, decoded with the ELF's format table) is printed into
//! the test log. What every board shares ([`Board`], [`draws_and_renders_like_built_in`])
//! lives here too; `qemu_riscv.rs` runs the MicroBlaze V through it. `cargo test qemu`
//! runs both. QEMU comes from Debian (`cargo xtask setup`).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::common::{
    collect, every_primitive, example, ok, rgb, sim_command, tmp, workspace, KillOnDrop,
};

/// A board binary and the QEMU machine that runs it.
pub struct Board {
    /// The Rust target the binary is built for.
    pub target: &'static str,
    /// The firmware feature that selects the binary.
    pub feature: &'static str,
    /// The binary's name.
    pub bin: &'static str,
    /// The QEMU program.
    pub qemu: &'static str,
    /// The Debian package that installs it (`cargo xtask setup` does).
    pub package: &'static str,
    /// The `-M` machine: it must have two UARTs, the host link first.
    pub machine: &'static str,
    /// How the machine takes the ELF.
    pub load: Load,
}

/// How QEMU is handed the board's ELF.
pub enum Load {
    /// `-kernel ELF`: the Arm boards boot it like a firmware image.
    Kernel,
    /// `-device loader,file=ELF,cpu-num=0`: loads the segments and starts CPU 0 at the
    /// entry point, for machines that have no firmware loader of their own.
    Loader,
}

/// The STM32F405 board binary on QEMU's Netduino Plus 2.
const STM32: Board = Board {
    target: "thumbv7em-none-eabihf",
    feature: "board-stm32",
    bin: "fpgfx-firmware",
    qemu: "qemu-system-arm",
    package: "qemu-system-arm",
    machine: "netduinoplus2",
    load: Load::Kernel,
};

impl Board {
    /// Builds the board binary (a no-op when `cargo xtask test` already did) and returns
    /// it. A missing Rust target fails here with the command that installs it, rather than
    /// with cargo's "can't find crate for `core`".
    pub(crate) fn elf(&self) -> PathBuf {
        let libdir = Command::new("rustc")
            .current_dir(workspace())
            .args(["--print", "target-libdir", "--target", self.target])
            .output();
        let installed = libdir.is_ok_and(|o| {
            o.status.success() && Path::new(String::from_utf8_lossy(&o.stdout).trim()).is_dir()
        });
        assert!(
            installed,
            "the Rust target {} is not installed: run `cargo xtask setup`",
            self.target
        );
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let status = Command::new(cargo)
            .current_dir(workspace())
            .args(["build", "-q", "-p", "firmware", "--features", self.feature])
            .args(["--target", self.target, "--profile", "firmware"])
            .status()
            .expect("cargo runs");
        assert!(
            status.success(),
            "building the board binary {} failed",
            self.bin
        );
        let target_dir = std::env::var_os("CARGO_TARGET_DIR")
            .map(PathBuf::from)
            .unwrap_or_else(|| workspace().join("target"));
        target_dir.join(self.target).join("firmware").join(self.bin)
    }

    /// The arguments that hand QEMU `elf`.
    fn load_args(&self, elf: &Path) -> Vec<OsString> {
        match self.load {
            Load::Kernel => vec!["-kernel".into(), elf.into()],
            Load::Loader => {
                let mut device = OsString::from("loader,file=");
                device.push(elf);
                device.push(",cpu-num=0");
                vec!["-device".into(), device]
            }
        }
    }
}

/// QEMU's stdout: first its "char device redirected to /dev/pts/N (label serialK)"
/// lines, then the semihosting bytes (defmt frames).
pub(crate) struct Qemu {
    _child: KillOnDrop,
    out: Arc<Mutex<Vec<u8>>>,
}

impl Qemu {
    fn start(board: &Board, elf: &Path) -> (Self, String, String) {
        let machines = Command::new(board.qemu).args(["-M", "help"]).output();
        assert!(
            machines.is_ok_and(|o| o.status.success()
                && String::from_utf8_lossy(&o.stdout)
                    .lines()
                    .any(|l| l.split_whitespace().next() == Some(board.machine))),
            "{} is not installed or has no `{}` machine: run `cargo xtask setup` (Debian \
             package {})",
            board.qemu,
            board.machine,
            board.package
        );
        let mut child = Command::new(board.qemu)
            .args(["-M", board.machine, "-display", "none", "-monitor", "none"])
            .args(["-semihosting-config", "enable=on,target=native"])
            .args(["-serial", "pty", "-serial", "pty"])
            .args(board.load_args(elf))
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap_or_else(|e| panic!("{} starts: {e}", board.qemu));
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

/// `board` in QEMU with `fpgfx-sim --fpga-link` and `fpga_args` on its second UART:
/// QEMU, the host link's pty, and the FPGA's process (both killed on drop).
pub(crate) fn start(board: &Board, elf: &Path, fpga_args: &[&str]) -> (Qemu, String, KillOnDrop) {
    let (qemu, host_pty, fpga_pty) = Qemu::start(board, elf);
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
pub(crate) fn assert_board_log(qemu: &Qemu, elf: &Path) {
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

/// The end-to-end check every board passes: `fpgfx raster` (every primitive, 4× AA) and
/// `fpgfx render` (the reference scene, 48 × 27, Q16.16) over its host link give images
/// identical to built-in mode's, and its log shows boot, FPGA and host session.
pub fn draws_and_renders_like_built_in(board: &Board) {
    let elf = board.elf();
    let (qemu, host_pty, _fpga) = start(board, &elf, &[]);

    // A raster job with every primitive, small enough that its read-back (QEMU delivers
    // UART bytes one per main-loop turn, ~6 KB/s) takes a few seconds.
    let file = tmp(&format!("raster-{}.toml", board.bin));
    let aa = "[aa]\npattern = \"rotated\"\nsamples = 4";
    std::fs::write(&file, every_primitive(96, 64, aa)).expect("temp file");
    let (on_board, built_in) = (
        tmp(&format!("{}.png", board.bin)),
        tmp(&format!("built-in-{}.png", board.bin)),
    );
    let started = Instant::now();
    let stats = ok(&[
        "--port", &host_pty, "raster", &file, "-o", &on_board, "--stats",
    ])
    .stdout;
    let raster_time = started.elapsed();
    ok(&["--port", "builtin", "raster", &file, "-o", &built_in]);
    assert_eq!(
        rgb(&on_board),
        rgb(&built_in),
        "raster image differs from built-in"
    );
    println!(
        "raster over QEMU ({}) in {raster_time:?}:\n{stats}",
        board.machine
    );

    let (on_board, built_in) = (
        tmp(&format!("{}-rt.png", board.bin)),
        tmp(&format!("built-in-rt-{}.png", board.bin)),
    );
    let started = Instant::now();
    let stats = render(Some(&host_pty), &on_board);
    let render_time = started.elapsed();
    render(None, &built_in);
    assert_eq!(
        rgb(&on_board),
        rgb(&built_in),
        "render differs from built-in"
    );
    println!(
        "render over QEMU ({}) in {render_time:?}:\n{stats}",
        board.machine
    );
    assert_board_log(&qemu, &elf);
}

#[test]
fn qemu_board_draws_and_renders_like_built_in() {
    draws_and_renders_like_built_in(&STM32);
}

/// The QEMU board with the FITkit block's RTL on its FPGA link: `fpgfx-sim --fpga-link
/// --fpga rtl` answers the link through the same SPI driver a FITkit MCU runs, so the
/// board identifies a FITkit-layout FPGA, packs FITkit records, and its frame must equal
/// the RTL's in process (`--port rtl`) and the golden model's (`--port builtin`).
#[test]
fn qemu_board_draws_on_the_rtl() {
    let elf = STM32.elf();
    let (qemu, host_pty, _fpga) = start(&STM32, &elf, &["--fpga", "rtl"]);
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
