//! `cargo xtask mitsuba`: fpgfx against Mitsuba 3 on one scene, in one run
//! (`bench/mitsuba/compare.py`, docs/bench.md).
//!
//! Mitsuba lives in a venv of its own (`target/mitsuba-env`), not in the test command's
//! `target/pyenv`: it is 60 MB, only this benchmark needs it, and its pins must not move
//! a package the checks were written against.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{bail, Context, Result};

/// The PyPI packages the comparison runs with, pinned. Mitsuba 3.6.4 with Dr.Jit 1.0.5:
/// Mitsuba 3.9.1 (Dr.Jit 1.5) emits `llvm.minimum` on scalars, which the LLVM 15 that
/// Debian bookworm ships cannot select ("LLVM ERROR: Cannot select … fminimum"), so
/// `llvm_ad_rgb` aborts on its first kernel.
const PACKAGES: &[&str] = &["mitsuba==3.6.4", "drjit==1.0.5", "numpy==2.4.6"];

/// The Debian package that gives Dr.Jit the shared LLVM its `llvm_*` variants compile
/// with (it loads `libLLVM*.so` at run time; nothing else here needs it).
const LLVM_PACKAGE: &str = "libllvm15";

/// Options of `cargo xtask mitsuba`.
#[derive(Debug, PartialEq)]
pub struct Options {
    /// The scene file, relative to the workspace or absolute.
    pub scene: PathBuf,
    /// Timed runs of each renderer.
    pub runs: u32,
}

impl Options {
    /// Parses `[--scene FILE] [--runs N]`.
    pub fn parse(args: &[String]) -> Result<Options> {
        let mut o = Options {
            scene: PathBuf::from("bench/mitsuba/lambert.toml"),
            runs: 5,
        };
        let mut it = args.iter();
        while let Some(a) = it.next() {
            let mut value = || {
                it.next()
                    .with_context(|| format!("{a} needs a value"))
                    .cloned()
            };
            match a.as_str() {
                "--scene" => o.scene = PathBuf::from(value()?),
                "--runs" => {
                    let v = value()?;
                    o.runs = v
                        .parse()
                        .ok()
                        .filter(|n| *n >= 1)
                        .with_context(|| format!("--runs: expected a count ≥ 1, got {v:?}"))?;
                }
                other => bail!("mitsuba: unknown argument {other:?} (--scene FILE, --runs N)"),
            }
        }
        Ok(o)
    }
}

/// The comparison's venv.
fn env(root: &Path) -> PathBuf {
    root.join("target").join("mitsuba-env")
}

/// Makes sure the venv holds [`PACKAGES`]; returns its Python.
fn ensure_env(root: &Path) -> Result<PathBuf> {
    let env = env(root);
    let python = env.join("bin").join("python");
    crate::synth::ensure_venv(&env, PACKAGES, "Mitsuba", !python.is_file())?;
    Ok(python)
}

/// Whether the dynamic loader knows a shared LLVM (Dr.Jit's `llvm_*` variants need one).
fn has_libllvm() -> bool {
    Command::new("ldconfig")
        .arg("-p")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).contains("libLLVM"))
        .unwrap_or(false)
}

/// Runs the comparison: the release `fpgfx`, the venv, then `compare.py`, which leaves
/// the frames, the mismatch masks and the figures in `target/mitsuba/`.
pub fn run(root: &Path, opts: &Options) -> Result<()> {
    if !has_libllvm() {
        eprintln!(
            "xtask mitsuba: installing {LLVM_PACKAGE} from Debian (Mitsuba's llvm_ad_rgb variant compiles its kernels with it)"
        );
        crate::apt_install(&[LLVM_PACKAGE])?;
    }
    let python = ensure_env(root)?;
    crate::run(
        "cargo",
        &[
            "build",
            "--release",
            "--quiet",
            "-p",
            "host-cli",
            "--bin",
            "fpgfx",
        ],
    )
    .context("building the release fpgfx")?;
    let fpgfx = root.join("target").join("release").join("fpgfx");
    let scene = root.join(&opts.scene);
    let script = root.join("bench").join("mitsuba").join("compare.py");
    let status = Command::new(&python)
        .arg(&script)
        .arg("--fpgfx")
        .arg(&fpgfx)
        .arg("--scene")
        .arg(&scene)
        .args(["--runs", &opts.runs.to_string()])
        .arg("--out")
        .arg(root.join("target").join("mitsuba"))
        .status()
        .with_context(|| format!("could not start {}", python.display()))?;
    if !status.success() {
        bail!("{} failed with {status}", script.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn options_default_to_the_lambert_scene_and_five_runs() {
        let o = Options::parse(&[]).expect("no arguments");
        assert_eq!(o.scene, PathBuf::from("bench/mitsuba/lambert.toml"));
        assert_eq!(o.runs, 5);
        let o = Options::parse(&args(&["--runs", "2", "--scene", "x.toml"])).expect("both");
        assert_eq!((o.runs, o.scene), (2, PathBuf::from("x.toml")));
    }

    #[test]
    fn bad_options_say_which() {
        for (a, says) in [
            (&["--runs", "0"][..], "--runs"),
            (&["--runs", "many"][..], "--runs"),
            (&["--runs"][..], "needs a value"),
            (&["--spp", "4"][..], "--spp"),
        ] {
            let e = Options::parse(&args(a)).expect_err("refused");
            assert!(format!("{e:#}").contains(says), "{a:?}: {e:#}");
        }
    }
}
