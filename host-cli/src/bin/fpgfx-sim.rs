//! `fpgfx-sim`: a whole board on a serial line — the firmware's controller and the FPGA
//! model behind a pseudo-terminal, so `fpgfx --port` is exercised over a real tty.

use std::io::Write;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use clap::Parser;
use firmware::{Controller, ControllerError};
use host_cli::builtin::SimBus;
use host_cli::serial::HostLink;

#[derive(Parser)]
#[command(
    name = "fpgfx-sim",
    version,
    about = "The fpgfx sim board on a pseudo-terminal"
)]
struct Cli {
    /// Create a pseudo-terminal, print its path on the first line of stdout and serve the
    /// controller + FPGA model on it until killed.
    #[arg(long)]
    pty: bool,
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("fpgfx-sim: error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// EIO (read) or EPIPE (write) on a pty master: no process has the slave open.
fn host_gone(e: &std::io::Error) -> bool {
    e.kind() == std::io::ErrorKind::BrokenPipe || matches!(e.raw_os_error(), Some(5) | Some(32))
}

fn run(cli: Cli) -> Result<()> {
    anyhow::ensure!(cli.pty, "nothing to serve: give --pty");
    let (master, slave) =
        serialport::TTYPort::pair().context("cannot create a pseudo-terminal pair")?;
    let path = serialport::SerialPort::name(&slave).context("the pseudo-terminal has no path")?;
    // The host opens the slave by path and takes the exclusive lock a serial port gets;
    // our handle would hold it. The node lives as long as the master is open.
    drop(slave);
    let mut stdout = std::io::stdout();
    writeln!(stdout, "{path}")?;
    stdout.flush()?;

    let layout = &protocol::bus::WIDE;
    let device = sim_target::device::Device::new(layout);
    let caps = device.caps();
    let mut controller = Controller::new(
        HostLink(master),
        SimBus(device),
        caps,
        layout,
        "fpgfx-sim pty",
    );
    let epoch = Instant::now();
    loop {
        let now = epoch.elapsed().as_millis() as u64;
        match controller.poll(now) {
            Ok(()) => {}
            // EIO (read) or EPIPE (write) on the master while no one has the slave open:
            // the host went away; wait for the next one (it will reset the link).
            Err(ControllerError::Host(e)) if host_gone(&e) => {
                std::thread::sleep(Duration::from_millis(20));
            }
            Err(ControllerError::Host(e)) => return Err(e).context("host link"),
            Err(ControllerError::Fpga(e)) => return Err(anyhow::anyhow!("FPGA model: {e}")),
        }
        std::thread::sleep(Duration::from_micros(200));
    }
}
