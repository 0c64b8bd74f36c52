//! `fpgfx flash`: an image onto the board's STM32F405 through its ROM bootloader, or onto
//! the FITkit's MSP430F168 through its ROM BSL, with a progress bar on stderr (hidden
//! when stderr is not a terminal) and a summary.

use std::path::PathBuf;

use anyhow::{Context, Result};
use host_cli::flash::{self, FlashOptions, Image, Progress, Stage, Unlock};

use super::TargetArgs;

/// The chips `fpgfx flash` programs. Chosen by flag, not detected: the STM32 measures its
/// baud rate on the first byte it sees, so probing it with the BSL's 0x80 would leave it
/// mis-timed, and a BSL ignores the STM32's 0x7F.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Chip {
    /// The reference board's STM32F405, ROM bootloader (ST AN3155), BOOT0 high.
    Stm32f405,
    /// The FITkit's MSP430F168, ROM BSL (TI SLAU319), entered with the RST/TEST sequence.
    Msp430f168,
}

/// Arguments of `fpgfx flash` (the port and baud rate are the tool's global options).
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// Firmware image: raw .bin (placed at --address), Intel .hex or .elf (PT_LOAD
    /// segments at their physical addresses).
    image: PathBuf,
    /// The chip behind --port and its bootloader.
    #[arg(long, value_enum, default_value_t = Chip::Stm32f405)]
    chip: Chip,
    /// Where a .bin goes [default: 0x08000000 for the STM32, 0x4000 (start of main
    /// flash) for the MSP430]; ignored for .hex and .elf, which carry their addresses.
    #[arg(long, value_parser = flash::parse_u32)]
    address: Option<u32>,
    /// Jump to the image when done: the STM32 to its first address (its vector table),
    /// the MSP430 to its reset vector (the word at 0xFFFE).
    #[arg(long)]
    go: bool,
    /// Skip the read-back comparison.
    #[arg(long)]
    no_verify: bool,
    /// Flash a chip whose ID is not the one --chip names (0x413; MSP430F168: 0xF169).
    #[arg(long)]
    force: bool,
    /// Attempts per block before giving up.
    #[arg(long, default_value_t = 4)]
    retries: u32,
    /// MSP430: the image the chip holds now (.hex/.elf/.bin at 0x4000), whose vector
    /// table 0xFFE0..0xFFFF is the BSL password. Then only the segments the new image
    /// touches are erased and the rest of the flash is kept; without it the chip is
    /// mass-erased first, which works whatever it held.
    #[arg(long, value_name = "FILE")]
    password: Option<PathBuf>,
}

/// The flash's progress as an indicatif bar: one stage at a time, its name as the message.
struct Bar(indicatif::ProgressBar);

impl Progress for Bar {
    fn stage(&mut self, stage: Stage, total: u64) {
        self.0.set_message(stage.to_string());
        self.0.set_length(total);
        self.0.set_position(0);
    }

    fn advance(&mut self, done: u64) {
        self.0.set_position(done);
    }
}

/// Flashes the image and prints the summary; every error names the image.
pub fn run(target: &TargetArgs, a: &Args) -> Result<()> {
    program(target, a).with_context(|| format!("flash {}", a.image.display()))
}

/// The progress bar both chips draw.
fn bar(len: u64) -> Bar {
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(len),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let style = indicatif::ProgressStyle::with_template(
        "{msg:>7} [{bar:40}] {bytes}/{total_bytes} {bytes_per_sec}",
    )
    .map(|s| s.progress_chars("=> "))
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    bar.set_style(style);
    Bar(bar)
}

fn program(target: &TargetArgs, a: &Args) -> Result<()> {
    let opts = FlashOptions {
        verify: !a.no_verify,
        go: a.go,
        force: a.force,
        attempts: a.retries.max(1),
    };
    // --port/--baud, else the config file `fpgfx ports --help` describes (--timeout is
    // the link's handshake: the bootloader has its own).
    let settings = target.settings().context("config file")?;
    match a.chip {
        Chip::Stm32f405 => {
            anyhow::ensure!(
                a.password.is_none(),
                "--password is the MSP430 BSL's; the STM32 bootloader has none"
            );
            let image = Image::load(&a.image, a.address.unwrap_or(0x0800_0000))?;
            let mut client = flash::open(settings.port.as_deref(), settings.baud)?;
            let mut bar = bar(image.len() as u64);
            let result = flash::flash(&mut client, &image, opts, &mut bar);
            bar.0.finish_and_clear();
            let report = result?;
            eprintln!(
                "chip {:#05x}, bootloader v{}.{}",
                report.chip.pid,
                report.chip.version >> 4,
                report.chip.version & 0xF
            );
            summary(&report, 10);
        }
        Chip::Msp430f168 => {
            let layout = &flash::MSP430F168;
            let image = Image::load_for(&a.image, a.address.unwrap_or(0x4000), layout)?;
            let unlock = match &a.password {
                Some(path) => {
                    let held = Image::load_for(path, 0x4000, layout)
                        .with_context(|| format!("--password {}", path.display()))?;
                    Unlock::Password {
                        vectors: flash::password_of(&held)
                            .with_context(|| format!("--password {}", path.display()))?,
                        from: path.display().to_string(),
                    }
                }
                None => Unlock::MassErase,
            };
            // The BSL starts at 9600 baud whatever the config file says for the link.
            let baud = target.baud.unwrap_or(9600);
            let mut client = flash::open_bsl(settings.port.as_deref(), baud)?;
            let mut bar = bar(image.len() as u64);
            let result = flash::flash_msp430(
                &mut client,
                &image,
                &protocol::msp430_bsl::MSP430F168,
                &unlock,
                opts,
                &mut bar,
            );
            bar.0.finish_and_clear();
            let report = result?;
            eprintln!(
                "chip {:#06x} ({}), BSL {}",
                report.chip.device_id,
                layout.chip,
                report.chip.version_text()
            );
            summary(&report, 6);
        }
    }
    Ok(())
}

/// The summary line and the jump, which both chips print alike; `width` formats
/// addresses (10 for 32-bit, 6 for 16-bit).
fn summary<C>(report: &flash::Report<C>, width: usize) {
    let secs = report.elapsed.as_secs_f64().max(1e-9);
    eprintln!(
        "{}; wrote {} bytes in {} blocks{}; {:.2} s ({:.0} blocks/s){}",
        report.erased,
        report.bytes,
        report.blocks,
        if report.verified { ", verified" } else { "" },
        secs,
        report.blocks as f64 / secs,
        if report.retries > 0 {
            format!(", {} retries", report.retries)
        } else {
            String::new()
        }
    );
    if let Some(a) = report.jumped {
        eprintln!("jumped to {a:#0width$x}");
    }
}
