//! `fpgfx raster`: a raster command file through the target to a PNG.

use std::path::PathBuf;

use anyhow::{Context, Result};
use host_cli::raster_file;
use protocol::frame::Traversal;

use super::{phase_line, TargetArgs};

/// Arguments of `fpgfx raster`.
#[derive(clap::Args)]
pub struct Args {
    /// The command file.
    file: PathBuf,
    /// Output PNG.
    #[arg(short, long, default_value = "raster.png")]
    output: PathBuf,
    /// Triangle traversal (overrides the file).
    #[arg(long)]
    traversal: Option<Traversal>,
    /// Print fragments, cycles, FIFO stalls, link counters and a board-time estimate.
    #[arg(long)]
    stats: bool,
}

/// Draws the file on the target, writes the PNG and, with `--stats`, prints the counters.
pub fn run(target: &TargetArgs, a: &Args) -> Result<()> {
    let mut session = target.connect()?;
    let name = a.file.display().to_string();
    let text = std::fs::read_to_string(&a.file).with_context(|| format!("cannot read {name}"))?;
    let mut job = raster_file::parse(&text, &name)?;
    if let Some(t) = a.traversal {
        job.setup.traversal = t;
    }
    session.handshake().context("handshake with the target")?;
    let started = std::time::Instant::now();
    let out = host_cli::raster::run(&mut session, &job, &name)?;
    let elapsed = started.elapsed();
    out.image
        .save(&a.output)
        .with_context(|| format!("cannot write {}", a.output.display()))?;
    if a.stats {
        let d = out.stats.device;
        let l = out.stats.link;
        let clock = sim_target::raster::CLOCK_HZ;
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
        for (what, phase) in [("commands →", out.send), ("read-back ←", out.read_back)] {
            println!("{}", phase_line(what, phase, target.baud));
        }
    }
    eprintln!("wrote {}", a.output.display());
    Ok(())
}
