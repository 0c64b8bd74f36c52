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

/// Whether `module` imports in the workspace's venv.
pub fn imports(root: &Path, module: &str) -> bool {
    let python = synth::pyenv(root).join("bin").join("python");
    Command::new(python)
        .args(["-c", &format!("import {module}")])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Makes sure the Python module `module` imports in [`synth::pyenv`], installing the
/// pinned `package` when it does not: the probe for a PyPI package that installs no
/// program of its own (cocotbext-spi), where [`synth::ensure_pypi`]'s program probe has
/// nothing to look for. pip only adds: nothing installed is removed.
pub fn ensure_module(root: &Path, module: &str, package: &str) -> Result<()> {
    if imports(root, module) {
        return Ok(());
    }
    let pip = synth::pyenv(root).join("bin").join("pip");
    crate::run(
        &pip.to_string_lossy(),
        &["install", "--quiet", "--disable-pip-version-check", package],
    )?;
    if !imports(root, module) {
        bail!(
            "{package} is installed in {} but `import {module}` still fails",
            synth::pyenv(root).display()
        );
    }
    Ok(())
}

/// Runs the testbench's pytest file with the venv's pytest, on the fpgfx wheel that
/// `python_package` installed there.
pub fn run(root: &Path) -> Result<()> {
    if !crate::on_path("iverilog") || !crate::on_path("vvp") {
        bail!("the cocotb testbench needs Icarus Verilog (iverilog, vvp): run `cargo xtask setup`");
    }
    if !imports(root, "fpgfx") {
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
