//! The MSP430F2617 board binary under mspdebug's simulator: built with the pinned
//! nightly (`firmware/msp430-toolchain`), run with a small raster job, its SPI writes
//! held to those of the same controller built for this host, its RAM held to the part's
//! 8 KiB. `cargo xtask setup` installs the toolchain and mspdebug; without them this
//! fails saying so, it never skips.

#[allow(dead_code)]
#[path = "../examples/msp430_sim.rs"]
mod harness;

use std::path::{Path, PathBuf};
use std::process::Command;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}

/// The pinned nightly's name, as xtask installs it.
fn toolchain() -> String {
    let file = workspace().join("firmware/msp430-toolchain");
    std::fs::read_to_string(&file)
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
        .trim()
        .to_string()
}

/// Builds the board binary for `part` and returns its path.
fn build(part: &str) -> PathBuf {
    let toolchain = toolchain();
    let target_dir = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace().join("target"));
    let status = Command::new("cargo")
        .current_dir(workspace())
        .env("FPGFX_MSP430_PART", part)
        // The outer cargo's toolchain must not leak into the nested build.
        .env_remove("RUSTUP_TOOLCHAIN")
        .env_remove("RUSTC")
        .arg(format!("+{toolchain}"))
        .args([
            "build",
            "-q",
            "-Zbuild-std=core",
            "--target",
            "msp430-none-elf",
        ])
        .args([
            "-p",
            "firmware",
            "--features",
            "board-msp430",
            "--profile",
            "firmware",
        ])
        .status()
        .expect("cargo runs");
    assert!(
        status.success(),
        "building the MSP430 binary with {toolchain} failed (run `cargo xtask setup` to \
         install the toolchain and its rust-src)"
    );
    let elf = target_dir.join("msp430-none-elf/firmware/fpgfx-firmware-msp430");
    // Another part's build would overwrite it: keep this one's apart.
    let copy = target_dir.join(format!("msp430-sim/fpgfx-firmware-msp430-{part}.elf"));
    std::fs::create_dir_all(copy.parent().unwrap_or(&target_dir)).expect("target dir");
    std::fs::copy(&elf, &copy).expect("the ELF exists after the build");
    copy
}

#[test]
fn msp430_f2617_under_mspdebug_shifts_the_host_builds_spi_bytes() {
    assert!(
        Command::new("mspdebug").arg("--version").output().is_ok(),
        "mspdebug is not installed: run `cargo xtask setup`"
    );
    let elf = build("f2617");
    let out = elf.with_extension("out");
    let report = harness::run(&elf.to_string_lossy(), &out).expect("the simulator run");
    println!("{}", report.summary.join("\n"));
    assert_eq!(report.part, 2617, "the binary drives the F2617's registers");
    assert!(
        report.same,
        "SPI writes differ from the host build's: {:?}",
        report.summary
    );
    // The stack must stay clear of .bss, with room to spare for paths the job does not
    // take: at least 512 B untouched (docs/firmware.md gives the figures).
    assert!(
        report.stack + 512 <= report.stack_room,
        "stack {} B of {} B between .bss and the top of RAM",
        report.stack,
        report.stack_room
    );
}
