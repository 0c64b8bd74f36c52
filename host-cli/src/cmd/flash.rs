//! `fpgfx flash`: an image onto the board's STM32F405 through its ROM bootloader, with a
//! progress bar on stderr (hidden when stderr is not a terminal) and a summary.

use std::path::PathBuf;

use anyhow::{Context, Result};
use host_cli::flash::{self, FlashOptions, Image, Progress, Stage};

use super::TargetArgs;

/// Arguments of `fpgfx flash` (the port and baud rate are the tool's global options).
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// Firmware image: raw .bin (placed at --address), Intel .hex or .elf (PT_LOAD
    /// segments at their physical addresses).
    image: PathBuf,
    /// Where a .bin goes; ignored for .hex and .elf, which carry their addresses.
    #[arg(long, default_value = "0x08000000", value_parser = flash::parse_u32)]
    address: u32,
    /// Jump to the image's first address (its vector table) when done.
    #[arg(long)]
    go: bool,
    /// Skip the read-back comparison.
    #[arg(long)]
    no_verify: bool,
    /// Flash a chip whose ID is not the STM32F405's 0x413.
    #[arg(long)]
    force: bool,
    /// Attempts per block before giving up.
    #[arg(long, default_value_t = 4)]
    retries: u32,
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

fn program(target: &TargetArgs, a: &Args) -> Result<()> {
    let image = Image::load(&a.image, a.address)?;
    // --port/--baud, else the config file `fpgfx ports --help` describes (--timeout is
    // the link's handshake: the bootloader has its own).
    let settings = target.settings().context("config file")?;
    let mut client = flash::open(settings.port.as_deref(), settings.baud)?;

    let bar = indicatif::ProgressBar::with_draw_target(
        Some(image.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let style = indicatif::ProgressStyle::with_template(
        "{msg:>7} [{bar:40}] {bytes}/{total_bytes} {bytes_per_sec}",
    )
    .map(|s| s.progress_chars("=> "))
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    bar.set_style(style);
    let mut bar = Bar(bar);
    let result = flash::flash(
        &mut client,
        &image,
        FlashOptions {
            verify: !a.no_verify,
            go: a.go,
            force: a.force,
            attempts: a.retries.max(1),
        },
        &mut bar,
    );
    bar.0.finish_and_clear();
    let report = result?;
    let secs = report.elapsed.as_secs_f64().max(1e-9);
    eprintln!(
        "chip {:#05x}, bootloader v{}.{}",
        report.chip.pid,
        report.chip.version >> 4,
        report.chip.version & 0xF
    );
    eprintln!(
        "erased sectors {:?}; wrote {} bytes in {} blocks{}; {:.2} s ({:.0} blocks/s){}",
        report.sectors,
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
        eprintln!("jumped to {a:#010x}");
    }
    Ok(())
}
