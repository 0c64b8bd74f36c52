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
    for script in ["memory.x", "memory-microblaze-v.x"] {
        println!("cargo:rerun-if-changed={}", root.join(script).display());
    }
    println!("cargo:rerun-if-env-changed=FPGFX_CORE_HZ");
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
