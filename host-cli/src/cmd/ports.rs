//! `fpgfx ports`: the serial ports of this machine, and which one `fpgfx` would use.

use anyhow::{Context, Result};

/// Arguments of `fpgfx ports` (none: it only lists).
#[derive(clap::Args)]
pub struct Args {}

/// Prints every port with its USB identity, and the adapter taken without `--port`.
pub fn run(_: &Args) -> Result<()> {
    let ports = host_cli::serial_ports::list().context("cannot list serial ports")?;
    if ports.is_empty() {
        println!("no serial ports");
    }
    for p in &ports {
        println!("{}", host_cli::serial_ports::describe(p));
    }
    if let Some(one) = host_cli::serial_ports::the_one_adapter(&ports) {
        println!("without --port, fpgfx uses {}", one.path);
    }
    Ok(())
}
