//! Puts the workspace's `memory.x` on the linker path for the board binary.
fn main() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(std::path::Path::to_path_buf)
        .unwrap_or_default();
    println!("cargo:rustc-link-search={}", root.display());
    println!("cargo:rerun-if-changed={}", root.join("memory.x").display());
    println!("cargo:rerun-if-env-changed=FPGFX_CORE_HZ");
    if std::env::var("CARGO_FEATURE_BOARD").is_ok() {
        println!("cargo:rustc-link-arg-bins=-Tlink.x");
        // defmt keeps its format strings in a section of the ELF the host decoder reads.
        println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
    }
}
