//! `cargo xtask test` — the README's test command and the only thing `.ci/run` calls.
//!
//! It installs what the checks need (the Cortex-M target; from Debian, QEMU for the
//! firmware's end-to-end test and the third-party `stm32flash` the bootloader test drives)
//! idempotently, so a fresh machine needs nothing done by hand, then runs every
//! check in the order that fails fastest: formatting, lints, the no_std builds, tests.

use std::process::Command;

use anyhow::{bail, Context, Result};

/// The MCU target the protocol crate (and later the firmware) must build for.
const MCU_TARGET: &str = "thumbv7em-none-eabihf";

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("test") => test(),
        Some("setup") => setup(),
        _ => {
            eprintln!("usage: cargo xtask <test|setup>\n  setup  install the Rust target and packages the tests need\n  test   setup, then fmt, clippy, no_std builds and every test");
            bail!("unknown or missing xtask command: {args:?}")
        }
    }
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

/// Debian packages the tests drive, as (program the test runs, package that provides it).
const PACKAGES: &[(&str, &str)] = &[
    ("qemu-system-arm", "qemu-system-arm"),
    ("stm32flash", "stm32flash"),
];

/// Whether `program` is on the PATH.
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).any(|d| d.join(program).is_file()))
        .unwrap_or(false)
}

/// Installs the missing Debian packages; `apt-get update` only if the first try fails
/// (a fresh image may have no package lists), and through sudo when not root.
fn install_packages() -> Result<()> {
    let missing: Vec<&str> = PACKAGES
        .iter()
        .filter(|(program, _)| !on_path(program))
        .map(|&(_, package)| package)
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    let root = Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false);
    let apt = |args: &[&str]| -> Result<()> {
        let mut full = vec!["apt-get"];
        full.extend_from_slice(args);
        if root {
            run(full[0], &full[1..])
        } else {
            run("sudo", &full)
        }
    };
    let mut install = vec!["install", "-y", "--no-install-recommends"];
    install.extend_from_slice(&missing);
    if apt(&install).is_err() {
        apt(&["update"])?;
        apt(&install).with_context(|| format!("cannot install {missing:?} from Debian"))?;
    }
    Ok(())
}

fn setup() -> Result<()> {
    if !prints("rustup", &["target", "list", "--installed"], MCU_TARGET) {
        run("rustup", &["target", "add", MCU_TARGET])?;
    }
    install_packages()
}

fn test() -> Result<()> {
    setup()?;
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    run(&cargo, &["fmt", "--all", "--check"])?;
    run(
        &cargo,
        &[
            "clippy",
            "--workspace",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ],
    )?;
    run(&cargo, &["build", "-p", "protocol", "--target", MCU_TARGET])?;
    // The board binary is behind a feature and a target, so the workspace clippy run
    // above does not see it.
    run(
        &cargo,
        &[
            "clippy",
            "-p",
            "firmware",
            "--features",
            "board",
            "--target",
            MCU_TARGET,
            "--profile",
            "firmware",
            "--",
            "-D",
            "warnings",
        ],
    )?;
    run(
        &cargo,
        &[
            "build",
            "-p",
            "firmware",
            "--features",
            "board",
            "--target",
            MCU_TARGET,
            "--profile",
            "firmware",
        ],
    )?;
    run(&cargo, &["test", "--workspace"])?;
    eprintln!("xtask test: all checks passed");
    Ok(())
}
