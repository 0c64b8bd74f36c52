//! `fpgfx`: the desktop tool. Each subcommand is a thin layer over `host_cli`; this file
//! parses arguments and turns errors into messages.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use host_cli::builtin;
use host_cli::raster_file;
use host_cli::session::Session;

#[derive(Parser)]
#[command(
    name = "fpgfx",
    version,
    about = "Drive an FPGA graphics accelerator, or its golden model"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Draw a raster command file (TOML or JSON) and write the framebuffer as PNG.
    Raster {
        /// The command file.
        file: PathBuf,
        /// Output PNG.
        #[arg(short, long, default_value = "raster.png")]
        output: PathBuf,
        /// Triangle traversal: bbox, scanline, zigzag, tiles or simd8 (overrides the file).
        #[arg(long)]
        traversal: Option<String>,
        /// Print fragments, cycles, FIFO stalls, link counters and a board-time estimate.
        #[arg(long)]
        stats: bool,
    },
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Raster {
            file,
            output,
            traversal,
            stats,
        } => raster(&file, &output, traversal.as_deref(), stats),
    }
}

fn raster(file: &Path, output: &Path, traversal: Option<&str>, stats: bool) -> Result<()> {
    let name = file.display().to_string();
    let text = std::fs::read_to_string(file).with_context(|| format!("cannot read {name}"))?;
    let mut job = raster_file::parse(&text, &name)?;
    if let Some(t) = traversal {
        job.setup.traversal =
            raster_file::parse_traversal(t).map_err(|m| anyhow::anyhow!("--traversal: {m}"))?;
    }
    let mut session = Session::new(builtin::sim_target());
    session
        .handshake()
        .context("handshake with the built-in target")?;
    let started = std::time::Instant::now();
    let out = host_cli::raster::run(&mut session, &job, &name)?;
    let elapsed = started.elapsed();
    out.image
        .save(output)
        .with_context(|| format!("cannot write {}", output.display()))?;
    if stats {
        let d = out.stats.device;
        let l = out.stats.link;
        let clock = sim_target::raster::hw::CLOCK_HZ;
        println!("commands      {}", d.commands);
        println!("bus records   {}", d.bus_words);
        println!("fragments     {}", d.fragments);
        println!("FPGA cycles   {}", d.cycles);
        println!(
            "board time    {:.3} ms at {:.0} MHz",
            d.cycles as f64 / clock * 1e3,
            clock / 1e6
        );
        println!("FIFO stalls   {}", d.fifo_stalls);
        println!(
            "link (target) sent {} resent {} delivered {} crc errors {} duplicates {}",
            l.sent, l.resent, l.delivered, l.crc_errors, l.duplicates
        );
        println!("host time     {:.1} ms", elapsed.as_secs_f64() * 1e3);
    }
    eprintln!("wrote {}", output.display());
    Ok(())
}
