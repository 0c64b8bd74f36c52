//! `cargo xtask test` — the README's test command and the only thing `.ci/run` calls.
//!
//! It installs what the checks need (the Cortex-M and RISC-V targets and the pinned
//! nightly the MSP430 binary builds with; from Debian, QEMU for the board binaries'
//! end-to-end tests, mspdebug for the MSP430's simulator run, the third-party `stm32flash` the bootloader
//! test drives, and Verilator, Icarus, Yosys and nextpnr for the RTL; from PyPI into
//! `target/pyenv`, the third-party MSP430 BSL client python-msp430-tools, maturin, numpy,
//! pytest, Pillow, abi3audit and mypy's stubtest for the Python package, whose wheel is
//! built and tested last, then cocotb and cocotbext-spi for the FITkit block's cocotb
//! testbench, which runs after it)
//! idempotently, so a fresh machine needs nothing done by hand, then runs every
//! check in the order that fails fastest: formatting, lints, the no_std builds, tests.

use std::path::Path;
use std::process::Command;

use anyhow::{bail, Context, Result};

mod baseline;
mod beside;
mod cocotb;
mod cores;
mod fuzz;
mod layers;
mod mitsuba;
mod steps;
mod synth;

/// The MCU target the protocol crate must build for on its own (the board binaries below
/// build it for theirs too).
const MCU_TARGET: &str = "thumbv7em-none-eabihf";

/// A board binary: the Rust target it is built for and the firmware feature that selects
/// it. Each is linted and built before the tests, which then find it up to date.
struct BoardBinary {
    target: &'static str,
    feature: &'static str,
}

/// The board binaries (docs/firmware.md): the STM32F405 and the MicroBlaze V (RV32IMAC).
const BOARDS: &[BoardBinary] = &[
    BoardBinary {
        target: MCU_TARGET,
        feature: "board-stm32",
    },
    BoardBinary {
        target: "riscv32imac-unknown-none-elf",
        feature: "board-riscv",
    },
];

/// Reports a failure as its cause chain on the last line, never as a backtrace: CI
/// environments that set `RUST_BACKTRACE` would otherwise end the log with thirty frames
/// of `std::rt` and push the step and the reason out of the excerpt a reader sees first.
fn main() -> std::process::ExitCode {
    match command() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// The command named on the command line.
fn command() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("test") => test(),
        Some("setup") => setup(),
        Some("synth") => {
            synth::synth(&workspace_root(), &synth::Options::parse(&args[1..])?).map(|_| ())
        }
        Some("fuzz") => {
            // cargo-fuzz needs the pinned nightly; on a machine the test command has not
            // set up yet, `fuzz` installs it rather than failing inside rustup.
            let opts = fuzz::Options::parse(&args[1..])?;
            install_msp430_toolchain()?;
            fuzz::run(&workspace_root(), &msp430_toolchain()?, &opts)
        }
        Some("mitsuba") => mitsuba::run(&workspace_root(), &mitsuba::Options::parse(&args[1..])?),
        Some("layers") => layers::check(&std::env::var("CARGO").unwrap_or_else(|_| "cargo".into())),
        Some("python") => {
            // The test command's last step alone, for work on python/: its PyPI tools,
            // then wheel, install and pytest (the fpgfx binary must be built).
            for tool in PYPI.iter().filter(|t| t.program != "msp430-bsl") {
                tool.ensure(&workspace_root())?;
            }
            python_package()
        }
        Some("cocotb") => {
            // The cocotb testbench alone, on the fpgfx wheel `python` last installed.
            for tool in PYPI.iter().filter(|t| t.program != "msp430-bsl") {
                tool.ensure(&workspace_root())?;
            }
            cocotb::run(&workspace_root())
        }
        _ => {
            eprintln!("usage: cargo xtask <test|setup|synth|fuzz|mitsuba|layers|python|cocotb>\n  setup  install the Rust targets and packages the tests need\n  test   setup, then fmt, clippy, no_std builds, RTL lint and testbenches, every test\n  synth  Yosys + nextpnr on the RTL blocks: LUT/FF/BRAM/DSP per module and Fmax [--json] [--block NAME] [--variant NAME] [--family NAME] [--check | --gate | --update-baseline]
         --check: every design placed and held to hw/synth-baseline.json; --gate: what the test command runs (docs/synthesis.md)\n  fuzz   build the cargo-fuzz targets (pinned nightly, ASan) and run each: [--target NAME]... [--runs N | --time SECONDS | --smoke]; prints executions, exec/s, coverage, corpus and crashes per target (fuzz/README.md)\n  mitsuba  time `fpgfx render` against Mitsuba 3 (llvm_ad_rgb, scalar_rgb, from PyPI) on one scene and check both drew it alike: [--scene FILE] [--runs N] (docs/bench.md)\n  layers check that every dependency between the workspace's crates points down\n  python build the Python package's wheel, install it into target/pyenv and run its pytest suite (needs target/debug/fpgfx)\n  cocotb run the FITkit block's cocotb testbench on Icarus (docs/cocotb.md; needs the wheel `python` installs)");
            bail!("unknown or missing xtask command: {args:?}")
        }
    }
}

/// The workspace's root, whatever directory `cargo xtask` was started from.
fn workspace_root() -> std::path::PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    here.parent().unwrap_or(here).to_path_buf()
}

/// Runs a command, echoing it, and fails with the command line if it does not succeed.
fn run(program: &str, args: &[&str]) -> Result<()> {
    eprintln!("+ {program} {}", args.join(" "));
    let status = Command::new(program)
        .args(args)
        .status()
        .with_context(|| format!("could not start `{program}`"))?;
    if !status.success() {
        bail!("`{program} {}` failed with {status}", args.join(" "));
    }
    Ok(())
}

/// Whether a command succeeds and prints `needle` on stdout (used for idempotent checks).
fn prints(program: &str, args: &[&str], needle: &str) -> bool {
    Command::new(program)
        .args(args)
        .output()
        .map(|o| o.status.success() && String::from_utf8_lossy(&o.stdout).contains(needle))
        .unwrap_or(false)
}

/// A Debian package a check needs: the program the check runs, the package that provides
/// it, and why, which `setup` prints before it installs anything.
struct Package {
    program: &'static str,
    package: &'static str,
    why: &'static str,
    /// Arguments to `program` whose output must contain the given text, for a check that
    /// needs more than the program existing (a release too old fails it, and `setup`
    /// installs a newer one from backports); `None` when being on the PATH is enough.
    needs: Option<(&'static [&'static str], &'static str)>,
}

impl Package {
    /// Whether the program is on the PATH and, if it has one, passes its `needs` probe.
    fn present(&self) -> bool {
        on_path(self.program)
            && self
                .needs
                .is_none_or(|(args, text)| prints(self.program, args, text))
    }
}

/// The Debian packages the tests drive.
const PACKAGES: &[Package] = &[
    Package {
        program: "cc",
        package: "gcc",
        why: "compiles the C library's C test against libfpgfx.a (capi/tests/c_test.rs)",
        needs: None,
    },
    Package {
        program: "c++",
        package: "g++",
        why: "compiles the C library's Vitis HLS testbench around its stand-in DUT (capi/tests/c_test.rs)",
        needs: None,
    },
    Package {
        program: "qemu-system-arm",
        package: "qemu-system-arm",
        why: "runs the STM32F405 board binary end to end (host-cli/tests/integration/qemu.rs)",
        needs: None,
    },
    Package {
        program: "qemu-system-riscv32",
        package: "qemu-system-misc",
        why: "runs the MicroBlaze V (RISC-V) board binary end to end (host-cli/tests/integration/qemu_riscv.rs)",
        // The machine arrived in QEMU in 2024: bookworm's own 7.2 lacks it.
        needs: Some((&["-M", "help"], "amd-microblaze-v-generic")),
    },
    Package {
        program: "stm32flash",
        package: "stm32flash",
        why: "the third-party AN3155 client `fpgfx-sim --bootloader` is checked against (host-cli/tests/integration/flash.rs)",
        needs: None,
    },
    Package {
        program: "mspdebug",
        package: "mspdebug",
        why: "runs the MSP430F2617 board binary in its simulator (firmware/tests/msp430.rs)",
        needs: None,
    },
    Package {
        program: "verilator",
        package: "verilator",
        why: "lints hw/fitkit-raster/rtl/ and builds the cycle-accurate model of the FITkit block that fitkit-rtl-sim and `--port rtl` drive",
        needs: None,
    },
    Package {
        program: "iverilog",
        package: "iverilog",
        why: "runs hw/fitkit-raster/'s self-checking testbenches (a second simulator beside Verilator)",
        needs: None,
    },
    Package {
        program: "yosys",
        package: "yosys",
        why: "synthesises hw/fitkit-raster/rtl/ for iCE40 (`cargo xtask synth`; the test command checks it still maps)",
        needs: None,
    },
    Package {
        program: "nextpnr-ice40",
        package: "nextpnr-ice40",
        why: "places and routes hw/fitkit-raster/rtl/ on an iCE40 HX8K for the Fmax that `cargo xtask synth` reports",
        needs: None,
    },
];

/// A PyPI package a test drives, installed into the workspace's Python environment
/// (`target/pyenv`, beside the FPGA tools `cargo xtask synth` installs there).
struct PyPiTool {
    program: &'static str,
    /// Pinned: the tests were written against this release's behaviour.
    package: &'static str,
    why: &'static str,
    /// A module that must import, for a package that installs no program (`program` is
    /// then the venv's `python`, always there).
    module: Option<&'static str>,
}

impl PyPiTool {
    /// Whether its program is in `target/pyenv` and, if it names one, its module imports.
    fn present(&self, root: &Path) -> bool {
        synth::pyenv(root).join("bin").join(self.program).is_file()
            && self.module.is_none_or(|m| synth::imports(root, m))
    }

    /// Installs the pinned package into `target/pyenv` if its probes fail.
    fn ensure(&self, root: &Path) -> Result<()> {
        synth::ensure_pypi(root, self.program, self.package)?;
        if let Some(module) = self.module {
            synth::ensure_module(root, module, self.package)?;
        }
        Ok(())
    }
}

/// The PyPI tools the tests drive.
const PYPI: &[PyPiTool] = &[
    PyPiTool {
        program: "msp430-bsl",
        package: "python-msp430-tools==0.10.0",
        why: "the third-party MSP430 ROM BSL client `fpgfx-sim --bootloader msp430` is checked against (host-cli/tests/integration/flash.rs)",
        module: None,
    },
    PyPiTool {
        program: "maturin",
        package: "maturin==1.16.0",
        why: "builds the Python package's wheel (python/, docs/python.md)",
        module: None,
    },
    PyPiTool {
        program: "numpy-config",
        package: "numpy==2.4.6",
        why: "the arrays the Python package takes and returns (python/)",
        module: None,
    },
    PyPiTool {
        program: "pytest",
        package: "pytest==9.2.0",
        why: "runs the Python package's tests (python/tests/)",
        module: None,
    },
    PyPiTool {
        program: "python",
        package: "pillow==13.0.0",
        why: "reads and writes the PNGs the Python package's tests hold it to (python/tests/)",
        module: Some("PIL"),
    },
    PyPiTool {
        program: "abi3audit",
        package: "abi3audit==0.0.26",
        why: "checks that the Python package's wheel uses only the stable ABI of CPython 3.9, so one wheel serves 3.9 on (python/)",
        module: None,
    },
    PyPiTool {
        program: "stubtest",
        package: "mypy==2.4.1",
        why: "holds the Python package's type stubs to the native module (python/fpgfx/*.pyi)",
        module: None,
    },
    PyPiTool {
        program: "cocotb-config",
        // 1.9.2, not 2.x: cocotbext-spi's last release (0.5.0) imports cocotb 1.x's
        // BaseClock, which cocotb 2.0 removed.
        package: "cocotb==1.9.2",
        why: "simulates the FITkit block's cocotb testbench on Icarus (hw/fitkit-raster/cocotb/)",
        module: None,
    },
    PyPiTool {
        program: "python",
        package: "cocotbext-spi==0.5.0",
        why: "the SPI master that testbench drives the block's pins with",
        module: Some("cocotbext.spi"),
    },
];

/// Whether `program` is on the PATH.
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).any(|d| d.join(program).is_file()))
        .unwrap_or(false)
}

/// Whether this process runs as root (otherwise apt and writes under /etc go through sudo).
fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// `apt-get ARGS`, through sudo when not root.
fn apt(args: &[&str]) -> Result<()> {
    let mut full = vec!["apt-get"];
    full.extend_from_slice(args);
    if is_root() {
        run(full[0], &full[1..])
    } else {
        run("sudo", &full)
    }
}

/// Installs Debian `packages` without removing anything (`--no-remove`, see
/// [`install_packages`]), updating the package lists once if the first try fails; for a
/// command outside the test command that needs a library, not a program on the PATH.
fn apt_install(packages: &[&str]) -> Result<()> {
    let mut install = vec!["install", "-y", "--no-install-recommends", "--no-remove"];
    install.extend_from_slice(packages);
    if apt(&install).is_ok() {
        return Ok(());
    }
    apt(&["update"])?;
    apt(&install).with_context(|| {
        format!("cannot install {packages:?} from Debian without removing a package (apt's message is above)")
    })
}

/// Installs the Debian packages that are missing or too old (their `needs` probe fails).
///
/// `--no-remove`: apt may otherwise resolve a conflict by removing an installed package
/// (it once removed qemu-utils to make room for qemu-system-arm), and a test command must
/// never take anything off a user's machine; with it apt refuses instead, and its own
/// message says why. `apt-get update` runs only if the first try fails (a fresh image may
/// have no package lists). Through sudo when not root.
fn install_packages() -> Result<()> {
    let missing: Vec<&Package> = PACKAGES.iter().filter(|p| !p.present()).collect();
    if missing.is_empty() {
        return Ok(());
    }
    eprintln!("xtask setup: installing from Debian (nothing is removed):");
    for p in &missing {
        eprintln!("  {:<16} {}", p.package, p.why);
    }
    let root = is_root();
    let mut install = vec!["install", "-y", "--no-install-recommends", "--no-remove"];
    install.extend(missing.iter().map(|p| p.package));
    // apt succeeds without upgrading a package that is installed but too old for its
    // probe, so success here means every probe now passes.
    let installed = || missing.iter().all(|p| p.present());
    if apt(&install).is_ok() && installed() {
        return Ok(());
    }
    apt(&["update"])?;
    if apt(&install).is_ok() && installed() {
        return Ok(());
    }
    // The image may carry a package from Debian's backports (this machine's qemu-utils
    // is 10.0 from bookworm-backports), and the release's own qemu-system-arm (7.2)
    // breaks it: apt would remove it. The same release's backports suite has matching
    // versions, so install from there instead of removing anything. The same suite has
    // the newer QEMU a probe may ask for (bookworm's 7.2 has no MicroBlaze V machine).
    let names: Vec<&str> = missing.iter().map(|p| p.package).collect();
    let codename = release_codename()
        .with_context(|| format!("the release cannot give {names:?} without removing a package or with what the tests need (apt's message is above), and /etc/os-release names no release to take backports from"))?;
    let suite = format!("{codename}-backports");
    let source = std::path::Path::new("/etc/apt/sources.list.d/fpgfx-backports.sources");
    // Written once and never rewritten or deleted: an earlier setup's file (or a suite the
    // machine already lists elsewhere, which `apt-cache policy` shows after the update
    // above) is used as it is, so a second run changes nothing and adds no duplicate.
    let listed = prints("apt-cache", &["policy"], &format!("n={suite},"));
    if !source.exists() && !listed {
        eprintln!(
            "xtask setup: {codename} alone cannot give {names:?} (apt would remove a package, or a version is too old); adding Debian's {suite} suite ({}) to install versions that fit instead",
            source.display()
        );
        let text = format!(
            "Types: deb\nURIs: http://deb.debian.org/debian\nSuites: {suite}\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n"
        );
        if root {
            std::fs::write(source, text)
                .with_context(|| format!("cannot write {}", source.display()))?;
        } else {
            let tmp = std::env::temp_dir().join("fpgfx-backports.sources");
            std::fs::write(&tmp, text)?;
            run(
                "sudo",
                &["cp", &tmp.to_string_lossy(), &source.to_string_lossy()],
            )?;
        }
        apt(&["update"])?;
    }
    let mut from_backports = vec![
        "install",
        "-y",
        "--no-install-recommends",
        "--no-remove",
        "-t",
        &suite,
    ];
    // Only what the release could not provide: what it did install stays its version.
    from_backports.extend(missing.iter().filter(|p| !p.present()).map(|p| p.package));
    apt(&from_backports).with_context(|| {
        format!("cannot install {names:?} from Debian ({codename} or {suite}) without removing a package (apt's message is above)")
    })?;
    let short: Vec<&str> = missing
        .iter()
        .filter(|p| !p.present())
        .map(|p| p.program)
        .collect();
    if !short.is_empty() {
        bail!("after installing {names:?}, {short:?} still lack what the tests need (see the `needs` probes in xtask/src/main.rs)");
    }
    Ok(())
}

/// The ray-casting core's folder: lint and testbenches here, its differential tests in
/// its bridge crate (run with the workspace's tests).
const RT_CORE: &str = "hw/rt-core";

/// The RTL's own checks: Verilator's lint on the synthesisable files (warnings are
/// errors) and each block's `run-tests.sh` (its lints, formal proofs and Icarus
/// testbenches). They run side by side, and beside the synthesis gate in the test
/// command: each takes a core from [`cores::take`] like the gate's tools, so the two
/// cores stay busy (the scripts are single-threaded, about 140 s and 35 s here).
fn rtl_sims() -> Result<()> {
    let root = workspace_root();
    let files: Vec<String> = synth::sources(&root, synth::BLOCK)?
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let include = format!("-I{}", synth::rtl_dir(&root, synth::BLOCK).display());
    let mut lint = vec!["--lint-only", "-Wall", &include, "--top-module", synth::TOP];
    lint.extend(files.iter().map(String::as_str));
    let scripts: Vec<(String, u32)> = [(synth::BLOCK, 140), (RT_CORE, 35)]
        .iter()
        .map(|(block, cost)| {
            (
                root.join(block)
                    .join("run-tests.sh")
                    .to_string_lossy()
                    .into_owned(),
                *cost,
            )
        })
        .collect();
    std::thread::scope(|s| {
        let lint = s.spawn(|| captured("verilator", &lint, 5));
        let runs: Vec<_> = scripts
            .iter()
            .map(|(script, cost)| s.spawn(move || captured("sh", &[script], *cost)))
            .collect();
        let mut result = lint
            .join()
            .unwrap_or_else(|_| Err(anyhow::anyhow!("the lint's thread panicked")));
        for r in runs {
            let r = r
                .join()
                .unwrap_or_else(|_| Err(anyhow::anyhow!("a testbench script's thread panicked")));
            result = both(result, r);
        }
        result
    })
}

/// `program args` on a core of its own ([`cores::take`] with `priority`, its rough
/// cost in core-seconds); its output is printed whole when it ends, so that checks
/// running side by side never interleave their lines.
fn captured(program: &str, args: &[&str], priority: u32) -> Result<()> {
    let _core = cores::take(priority);
    let started = std::time::Instant::now();
    let out = Command::new(program)
        .args(args)
        .output()
        .with_context(|| format!("could not start `{program}`: run `cargo xtask setup`"))?;
    eprintln!(
        "+ {program} {} ({:.1} s, side by side with other checks; its output:)",
        args.join(" "),
        started.elapsed().as_secs_f64()
    );
    eprint!("{}", String::from_utf8_lossy(&out.stdout));
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
    if !out.status.success() {
        bail!(
            "`{program} {}` failed with {} (its output is just above)",
            args.join(" "),
            out.status
        );
    }
    Ok(())
}

/// Both results: the first error, with the second's added when both failed.
fn both(a: Result<()>, b: Result<()>) -> Result<()> {
    match (a, b) {
        (Err(a), Err(b)) => Err(a.context(format!("and also: {b:#}"))),
        (a, b) => a.and(b),
    }
}

/// The RTL checks beside the synthesis gate (both hold cores from [`cores::take`]).
fn rtl_and_synth_gate() -> Result<()> {
    std::thread::scope(|s| {
        let rtl = s.spawn(rtl_sims);
        let gate = synth_gate();
        let rtl = rtl
            .join()
            .unwrap_or_else(|_| Err(anyhow::anyhow!("the RTL checks' thread panicked")));
        both(gate, rtl)
    })
}

fn synth_gate() -> Result<()> {
    synth::synth(
        &workspace_root(),
        &synth::Options {
            test: true,
            ..synth::Options::default()
        },
    )?;
    Ok(())
}

/// The Debian release this machine runs (`VERSION_CODENAME` in /etc/os-release).
fn release_codename() -> Option<String> {
    let text = std::fs::read_to_string("/etc/os-release").ok()?;
    text.lines()
        .find_map(|l| l.strip_prefix("VERSION_CODENAME="))
        .map(|v| v.trim_matches('"').to_string())
        .filter(|v| !v.is_empty())
}

/// The file naming the nightly the MSP430 binary is built with (read by
/// `firmware/tests/msp430.rs` too). Pinned to a date, not `nightly`: the target is tier 3
/// and builds its `core` from rust-src with `-Zbuild-std`, `panic=immediate-abort` and
/// `asm_experimental_arch` are unstable, so a later nightly may break or resize the build
/// (every figure in docs/firmware.md was measured with this one).
const MSP430_TOOLCHAIN_FILE: &str = "firmware/msp430-toolchain";

/// The pinned MSP430 nightly's name.
fn msp430_toolchain() -> Result<String> {
    let file = workspace_root().join(MSP430_TOOLCHAIN_FILE);
    let name = std::fs::read_to_string(&file)
        .with_context(|| format!("cannot read {}", file.display()))?;
    Ok(name.trim().to_string())
}

/// Installs the pinned nightly with rust-src if it or its rust-src is missing.
fn install_msp430_toolchain() -> Result<()> {
    let toolchain = msp430_toolchain()?;
    let plus = format!("+{toolchain}");
    let installed = |component| {
        prints(
            "rustup",
            &[&plus, "component", "list", "--installed"],
            component,
        )
    };
    if installed("rust-src") && installed("clippy") {
        return Ok(());
    }
    eprintln!(
        "xtask setup: installing the Rust toolchain {toolchain} with rust-src and clippy (the MSP430 board binary builds its core with it and is linted with it)"
    );
    run(
        "rustup",
        &[
            "toolchain",
            "install",
            &toolchain,
            "--profile",
            "minimal",
            "--component",
            "rust-src,clippy",
        ],
    )
}

fn setup() -> Result<()> {
    for board in BOARDS {
        if !prints("rustup", &["target", "list", "--installed"], board.target) {
            eprintln!(
                "xtask setup: adding the Rust target {} (the firmware's `{}` binary builds for it)",
                board.target, board.feature
            );
            run("rustup", &["target", "add", board.target])?;
        }
    }
    install_msp430_toolchain()?;
    fuzz::install_cargo_fuzz(&msp430_toolchain()?)?;
    install_packages()?;
    let root = workspace_root();
    for tool in PYPI {
        if !tool.present(&root) {
            eprintln!(
                "xtask setup: installing {} into {} ({})",
                tool.package,
                synth::pyenv(&root).display(),
                tool.why
            );
        }
        tool.ensure(&root)?;
    }
    Ok(())
}

fn test() -> Result<()> {
    let mut steps = steps::Steps::new();
    let out = test_steps(&mut steps);
    steps.report(&workspace_root().join("target/xtask-test-times.md"));
    out
}

/// The test command's steps, each timed by `steps`.
fn test_steps(steps: &mut steps::Steps) -> Result<()> {
    steps.run("setup (installs)", setup)?;
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let cargo = cargo.as_str();
    steps.run("fmt", || run(cargo, &["fmt", "--all", "--check"]))?;
    steps.run("layers", || layers::check(cargo))?;
    steps.run("clippy (workspace)", || {
        run(
            cargo,
            &[
                "clippy",
                "--workspace",
                "--all-targets",
                "--",
                "-D",
                "warnings",
            ],
        )
    })?;
    steps.run("embedded builds and clippy", || {
        run(cargo, &["build", "-p", "protocol", "--target", MCU_TARGET])?;
        // The board binaries are behind a feature and a target each, so the workspace
        // clippy run above does not see them; built here, the QEMU tests find them up to
        // date.
        for board in BOARDS {
            let common = [
                "-p",
                "firmware",
                "--features",
                board.feature,
                "--target",
                board.target,
                "--profile",
                "firmware",
            ];
            let mut clippy = vec!["clippy"];
            clippy.extend(common);
            clippy.extend(["--", "-D", "warnings"]);
            run(cargo, &clippy)?;
            let mut build = vec!["build"];
            build.extend(common);
            run(cargo, &build)?;
        }
        Ok(())
    })?;
    // The MSP430 binary: nightly, so linted here through rustup's `cargo +TOOLCHAIN`
    // (the workspace's stable cargo cannot); once per part's register module. The
    // build and its simulator run are `firmware/tests/msp430.rs`, among the tests below.
    steps.run("MSP430 clippy", msp430_clippy)?;
    steps.run(
        "RTL lint and simulations beside the synthesis gate",
        rtl_and_synth_gate,
    )?;
    steps.run("cargo test: build", || {
        run(cargo, &["test", "--workspace", "--no-run"])
    })?;
    // The fuzz smoke (a nightly build of its own into fuzz/target, then each target
    // briefly) beside the three steps that follow, which leave a core idle much of the
    // time; collected, and its output printed, after them (`beside`).
    let log = workspace_root().join("target").join("xtask-fuzz-smoke.log");
    let fuzz = beside::Beside::start(&["fuzz", "--smoke"], &log)?;
    steps.run("cargo test: run", || run(cargo, &["test", "--workspace"]))?;
    steps.run("Python package", python_package)?;
    steps.run("cocotb", || cocotb::run(&workspace_root()))?;
    steps.run_measured("fuzz smoke (beside the three steps above)", || {
        fuzz.finish()
    })?;
    eprintln!("xtask test: all checks passed");
    Ok(())
}

/// Lints the MSP430 binary with the pinned nightly, once per part.
fn msp430_clippy() -> Result<()> {
    let plus = format!("+{}", msp430_toolchain()?);
    for part in ["f2617", "f168"] {
        eprintln!("+ FPGFX_MSP430_PART={part}");
        let status = Command::new("cargo")
            .env("FPGFX_MSP430_PART", part)
            .env_remove("RUSTUP_TOOLCHAIN")
            .args([
                &plus,
                "clippy",
                "-q",
                "-Zbuild-std=core",
                "--target",
                "msp430-none-elf",
                "-p",
                "firmware",
                "--features",
                "board-msp430",
                "--profile",
                "firmware",
                "--",
                "-D",
                "warnings",
            ])
            .status()
            .context("could not start cargo")?;
        if !status.success() {
            bail!("clippy on the MSP430 binary (FPGFX_MSP430_PART={part}) failed with {status}");
        }
    }
    Ok(())
}

/// The Python package (`python/`, docs/python.md): its wheel built by maturin and installed
/// into the workspace's venv (`target/pyenv`, where `setup` put maturin, numpy and pytest),
/// then its pytest suite, which holds it to the `fpgfx` binary the workspace's tests just
/// built. The dev profile, so that maturin finds every workspace crate already built by
/// those tests and compiles only PyO3 (with `extension-module`) and the bindings.
fn python_package() -> Result<()> {
    let root = workspace_root();
    let env = synth::pyenv(&root);
    let bin = |p: &str| env.join("bin").join(p).to_string_lossy().into_owned();
    let wheels = root.join("target").join("wheels");
    // Only this build's wheel in the folder, so the install below cannot pick a stale one.
    if let Ok(entries) = std::fs::read_dir(&wheels) {
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if name.starts_with("fpgfx-") && name.ends_with(".whl") {
                std::fs::remove_file(e.path())
                    .with_context(|| format!("cannot remove {}", e.path().display()))?;
            }
        }
    }
    let manifest = root.join("python").join("Cargo.toml");
    run(
        &bin("maturin"),
        &[
            "build",
            "--quiet",
            "--profile",
            "dev",
            "-m",
            &manifest.to_string_lossy(),
            "-o",
            &wheels.to_string_lossy(),
            "-i",
            &bin("python"),
        ],
    )?;
    let wheel = std::fs::read_dir(&wheels)
        .with_context(|| format!("maturin wrote no {}", wheels.display()))?
        .flatten()
        .map(|e| e.path())
        .find(|p| {
            let name = p.file_name().unwrap_or_default().to_string_lossy();
            name.starts_with("fpgfx-") && name.ends_with(".whl")
        })
        .with_context(|| format!("maturin wrote no fpgfx wheel into {}", wheels.display()))?;
    run(
        &bin("pip"),
        &[
            "install",
            "--quiet",
            "--disable-pip-version-check",
            "--force-reinstall",
            "--no-deps",
            &wheel.to_string_lossy(),
        ],
    )?;
    let fpgfx = root.join("target").join("debug").join("fpgfx");
    eprintln!("+ FPGFX_BIN={} pytest python/tests", fpgfx.display());
    let status = Command::new(bin("pytest"))
        .args(["-q", "-p", "no:cacheprovider", "python/tests"])
        .current_dir(&root)
        .env("FPGFX_BIN", &fpgfx)
        .status()
        .context("could not start pytest")?;
    if !status.success() {
        bail!("the Python package's tests (pytest python/tests) failed with {status}");
    }
    // One wheel for CPython 3.9 on is a claim about the symbols it imports: checked, as
    // only one interpreter is at hand to test it with.
    run(
        &bin("abi3audit"),
        &["--strict", "--summary", &wheel.to_string_lossy()],
    )?;
    // The stubs are typed by hand beside the native module: every name, signature and
    // default held to what the module has at run time.
    run(&bin("stubtest"), &["--ignore-disjoint-bases", "fpgfx"])?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_captured_check_that_fails_says_which_and_with_what() {
        captured("sh", &["-c", "exit 0"], 1).expect("a passing command passes");
        let e = captured("sh", &["-c", "echo half-way; exit 3"], 1).expect_err("exit 3 fails");
        let text = format!("{e:#}");
        assert!(
            text.contains("`sh -c echo half-way; exit 3` failed"),
            "{text}"
        );
        assert!(text.contains("exit status: 3"), "{text}");
    }

    #[test]
    fn side_by_side_checks_report_every_failure() {
        let fail = |m: &str| Err(anyhow::anyhow!("{m}"));
        assert!(both(Ok(()), Ok(())).is_ok());
        assert_eq!(
            format!("{:#}", both(fail("gate"), Ok(())).expect_err("one")),
            "gate"
        );
        assert_eq!(
            format!("{:#}", both(Ok(()), fail("rtl")).expect_err("one")),
            "rtl"
        );
        let e = format!("{:#}", both(fail("gate"), fail("rtl")).expect_err("two"));
        assert!(e.contains("gate") && e.contains("rtl"), "{e}");
    }
}
