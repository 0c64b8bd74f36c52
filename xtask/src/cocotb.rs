//! The FITkit raster block's cocotb testbench (`hw/fitkit-raster/cocotb/`, docs/cocotb.md):
//! the test command's step after the Python package's, and `cargo xtask cocotb` alone.
//!
//! The testbench is a pytest file that builds the block with Icarus through cocotb's Python
//! runner and drives it with cocotbext-spi, the fpgfx Python package as its scoreboard: it
//! runs in `target/pyenv`, where `setup` installed the pinned cocotb and cocotbext-spi
//! ([`crate::PYPI`]) and `python_package` the fpgfx wheel.

use std::path::Path;
use std::process::Command;

use anyhow::{bail, Context, Result};

use crate::synth;

/// The testbench's folder, from the workspace root.
pub const TESTBENCH: &str = "hw/fitkit-raster/cocotb";

/// Runs the testbench's pytest file with the venv's pytest, on the fpgfx wheel that
/// `python_package` installed there.
pub fn run(root: &Path) -> Result<()> {
    if !crate::on_path("iverilog") || !crate::on_path("vvp") {
        bail!("the cocotb testbench needs Icarus Verilog (iverilog, vvp): run `cargo xtask setup`");
    }
    if !synth::imports(root, "fpgfx") {
        bail!(
            "the fpgfx package is not installed in {}: run `cargo xtask python` first (it builds and installs the wheel)",
            synth::pyenv(root).display()
        );
    }
    let pytest = synth::pyenv(root).join("bin").join("pytest");
    eprintln!("+ pytest {TESTBENCH}");
    let status = Command::new(&pytest)
        .args(["-q", "-p", "no:cacheprovider", TESTBENCH])
        .current_dir(root)
        .status()
        .with_context(|| format!("could not start {}", pytest.display()))?;
    if !status.success() {
        bail!("the FITkit block's cocotb testbench (pytest {TESTBENCH}) failed with {status}");
    }
    Ok(())
}
