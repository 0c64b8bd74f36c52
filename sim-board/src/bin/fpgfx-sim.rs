//! `fpgfx-sim`: a whole board on a serial line — the firmware's controller and the FPGA
//! model behind a pseudo-terminal, so `fpgfx --port` is exercised over a real tty. The
//! serving is [`sim_board`]'s; this binary parses flags and reports.

use std::io::Write;

use anyhow::Result;
use clap::Parser;
use sim_board::board::Fpga;
use sim_board::bootloader::Bootloader;
use sim_board::bootloader_pty::{self, Chip, RomLoader};
use sim_board::msp430_bsl::Bsl;
use sim_board::FpgaPort;
use sim_board::{board, pty};

#[derive(Parser)]
#[command(
    name = "fpgfx-sim",
    version,
    about = "The fpgfx sim board on a pseudo-terminal or TCP, or its FPGA alone"
)]
struct Cli {
    /// Create a pseudo-terminal, print its path on the first line of stdout and serve the
    /// controller + FPGA model on it until killed.
    #[arg(long)]
    pty: bool,
    /// Serve a ROM bootloader on the pty instead of the board: the STM32F405's (AN3155,
    /// what the chip does with BOOT0 high; the default when no value is given) or the
    /// FITkit MSP430F168's BSL (SLAU319, what it does after the RST/TEST entry sequence).
    /// See docs/flash.md.
    #[arg(long, requires = "pty", value_enum, num_args = 0..=1, default_missing_value = "stm32",
          value_name = "CHIP")]
    bootloader: Option<Loader>,
    /// With --bootloader: keep the emulated flash in FILE (STM32: the 1 MiB flash;
    /// MSP430: the 64 KiB address space, of which the flash is kept), created erased if
    /// missing and updated after every write or erase, so a later run sees it.
    #[arg(long, value_name = "FILE", requires = "bootloader")]
    flash_image: Option<std::path::PathBuf>,
    /// With --bootloader, a test aid: exit (like a board losing power) right after the
    /// Nth successful flash write (Write Memory, RX data block), to interrupt a flash at a
    /// known point.
    #[arg(long, value_name = "N", requires = "bootloader")]
    exit_after_writes: Option<u64>,
    /// With --bootloader msp430, a test aid: every data frame the BSL sends carries a
    /// wrong checksum, as on a line that corrupts the chip's answers.
    #[arg(long, requires = "bootloader")]
    corrupt_answers: bool,
    /// Serve the controller + FPGA model on TCP (e.g. 127.0.0.1:7878; port 0 picks one),
    /// one client at a time; prints the bound address on the first line of stdout.
    #[arg(long, value_name = "ADDR", conflicts_with = "pty")]
    tcp: Option<String>,
    /// Serve only the FPGA (the serial FPGA link, `protocol::fpga_link`) on this serial port,
    /// e.g. the pty QEMU gives the board's USART2.
    #[arg(long, value_name = "PORT", conflicts_with_all = ["pty", "tcp"])]
    fpga_link: Option<String>,
    /// Line rate: of --fpga-link's port, and of the emulated UART with --pace.
    #[arg(long, default_value_t = 921_600)]
    baud: u32,
    /// Move bytes no faster than a UART at --baud would (8N1), both ways, so that
    /// throughput figures through a pty or TCP mean something.
    #[arg(long)]
    pace: bool,
    /// The FPGA: the golden model, or the FITkit raster block's RTL (Verilated
    /// hw/fitkit-raster/rtl/) behind the controller's SPI driver. With --fpga-link the RTL
    /// answers the serial FPGA link through that same driver, so a QEMU board reaches it
    /// too.
    #[arg(long, value_enum, default_value_t = Fpga::Model)]
    fpga: Fpga,
}

/// Which ROM bootloader `--bootloader` emulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Loader {
    /// STM32F405, ST AN3155 (bootloader v3.1).
    Stm32,
    /// MSP430F168, TI SLAU319 ROM BSL 1.61.
    Msp430,
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

fn run(cli: Cli) -> Result<()> {
    match cli.bootloader {
        Some(Loader::Stm32) => {
            anyhow::ensure!(
                !cli.corrupt_answers,
                "--corrupt-answers is for --bootloader msp430"
            );
            return serve_bootloader::<Bootloader>(&cli, |_| {});
        }
        Some(Loader::Msp430) => {
            let corrupt = cli.corrupt_answers;
            return serve_bootloader::<Bsl>(&cli, |bsl| bsl.corrupt_answers(corrupt));
        }
        None => {}
    }
    if let Some(path) = &cli.fpga_link {
        let port = FpgaPort::open(path, cli.baud)?;
        eprintln!("fpgfx-sim: FPGA link on {path}");
        port.serve(cli.fpga, |text| eprintln!("fpgfx-sim: FPGA fault: {text}"))?;
        // The board went away (QEMU exited): nothing left to serve.
        eprintln!("fpgfx-sim: FPGA-link peer closed {path}");
        return Ok(());
    }
    let pace = cli.pace.then_some(cli.baud);
    if let Some(addr) = &cli.tcp {
        let listener = board::listen(addr)?;
        announce(&listener.local_addr()?.to_string())?;
        let never = board::serve_tcp(listener, pace, cli.fpga, fpga_fault)?;
        match never {}
    }
    anyhow::ensure!(
        cli.pty,
        "nothing to serve: give --pty, --tcp ADDR or --fpga-link PORT"
    );
    let (master, path) = pty::open()?;
    announce(&path)?;
    let never = board::serve(master, pace, cli.fpga, fpga_fault)?;
    match never {}
}

/// The host was answered with a Device error and the board keeps serving; the operator
/// hears of it here.
fn fpga_fault(e: &dyn std::fmt::Display) {
    eprintln!("fpgfx-sim: FPGA fault: {e}");
}

/// Prints where we listen on stdout's first line (tests and scripts read it).
fn announce(what: &str) -> Result<()> {
    let mut stdout = std::io::stdout();
    writeln!(stdout, "{what}")?;
    stdout.flush()?;
    Ok(())
}

/// `--bootloader`: the emulated ROM bootloader on a pty; `setup` applies test aids.
fn serve_bootloader<B: RomLoader>(cli: &Cli, setup: impl FnOnce(&mut B)) -> Result<()> {
    let mut chip = match &cli.flash_image {
        Some(path) => Chip::<B>::with_image(path)?,
        None => Chip::<B>::new(),
    };
    setup(chip.model());
    let (master, path) = pty::open()?;
    announce(&path)?;
    let width = if B::IMAGE_SIZE > 0x1_0000 { 10 } else { 6 };
    let writes = bootloader_pty::serve(master, chip, cli.exit_after_writes, |address| {
        eprintln!("fpgfx-sim: Go {address:#0width$x}")
    })?;
    eprintln!("fpgfx-sim: exiting after {writes} writes (--exit-after-writes)");
    Ok(())
}
