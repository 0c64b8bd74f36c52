//! Linker scripts for the board binaries, from the workspace root.
//!
//! The STM32F405's is `memory.x`, the name cortex-m-rt's `link.x` includes. riscv-rt's
//! `link.x` includes none, so the MicroBlaze V binary names its memory map on the command
//! line first (it defines the regions `link.x` places sections in). defmt keeps its format
//! strings in a section of the ELF the host decoder reads (`defmt.x`).
fn main() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(std::path::Path::to_path_buf)
        .unwrap_or_default();
    println!("cargo:rustc-link-search={}", root.display());
    for script in [
        "memory.x",
        "memory-microblaze-v.x",
        "msp430.x",
        "msp430f168.x",
        "msp430f2617.x",
        "msp430sim.x",
    ] {
        println!("cargo:rerun-if-changed={}", root.join(script).display());
    }
    println!("cargo:rerun-if-env-changed=FPGFX_CORE_HZ");
    println!("cargo:rerun-if-env-changed=FPGFX_MSP430_PART");
    // The MSP430 binary has its own start-up and no defmt: only its part's memory map,
    // and its part's registers (`msp430_f2617` selects `src/bin/msp430/f2617.rs`, else
    // the F168's). The F168 (FITkit 1.x) unless FPGFX_MSP430_PART says f2617 (FITkit
    // 2.x) or sim (the F168's registers on mspdebug's flat memory).
    println!("cargo::rustc-check-cfg=cfg(msp430_f2617)");
    if std::env::var_os("CARGO_FEATURE_BOARD_MSP430").is_some() {
        let part = std::env::var("FPGFX_MSP430_PART").unwrap_or_else(|_| "f168".into());
        if !["f168", "f2617", "sim"].contains(&part.as_str()) {
            panic!("FPGFX_MSP430_PART={part}: expected f168, f2617 or sim");
        }
        if part == "f2617" {
            println!("cargo:rustc-cfg=msp430_f2617");
        }
        println!("cargo:rustc-link-arg-bin=fpgfx-firmware-msp430=-Tmsp430{part}.x");
    }
    let boards = [
        (
            "CARGO_FEATURE_BOARD_STM32",
            "fpgfx-firmware",
            &["-Tlink.x"][..],
        ),
        (
            "CARGO_FEATURE_BOARD_RISCV",
            "fpgfx-firmware-riscv",
            &["-Tmemory-microblaze-v.x", "-Tlink.x"][..],
        ),
    ];
    for (feature, bin, scripts) in boards {
        if std::env::var_os(feature).is_some() {
            for arg in scripts.iter().chain(&["-Tdefmt.x"]) {
                println!("cargo:rustc-link-arg-bin={bin}={arg}");
            }
        }
    }
}
