//! `fpgfx raster`: a raster command file through the target to a PNG.

use std::path::PathBuf;

use anyhow::{Context, Result};
use protocol::raster::Traversal;

use super::{check_output_file, flag_path, phase_line, TargetArgs};

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
    check_output_file(
        &flag_path("-o/--output", &a.output),
        &a.output,
        "the framebuffer",
        &["png"],
    )?;
    let mut session = target.connect()?;
    let name = a.file.display().to_string();
    let text = std::fs::read_to_string(&a.file).with_context(|| format!("cannot read {name}"))?;
    let mut job = jobs::raster::parse(&text, &name)?;
    if let Some(t) = a.traversal {
        job.setup.traversal = t;
    }
    session.handshake().context("handshake with the target")?;
    let started = std::time::Instant::now();
    let out = host_cli::run::raster::run(&mut session, &job, &name)?;
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
        if target.settings()?.port.as_deref() == Some("rtl") {
            model_beside_rtl(&job, &name, &out)?;
        }
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

/// With `--port rtl --stats`: the golden model's estimate for the same job on the FITkit
/// layout, beside the RTL's measured cycles, and whether the two frames agree. The model
/// walks the bounding box, as the RTL's triangle unit does, whatever the file asks for.
fn model_beside_rtl(
    job: &jobs::raster::RasterJob,
    name: &str,
    rtl: &host_cli::run::raster::RasterOutput,
) -> Result<()> {
    let mut job = job.clone();
    job.setup.traversal = Traversal::BoundingBox;
    let builtin = sim_board::in_process::sim_target_with(&protocol::bus::FITKIT);
    let mut session = host_cli::session::Session::new(builtin);
    session
        .handshake()
        .context("handshake with the golden model")?;
    let model = host_cli::run::raster::run(&mut session, &job, name)?;
    let differ = model
        .image
        .pixels()
        .zip(rtl.image.pixels())
        .filter(|(a, b)| a != b)
        .count();
    println!(
        "model cycles  {} (golden model, FITkit layout, bounding-box traversal; RTL {} = {:+})",
        model.stats.device.cycles,
        rtl.stats.device.cycles,
        rtl.stats.device.cycles as i64 - model.stats.device.cycles as i64
    );
    println!(
        "model frame   {}",
        if differ == 0 {
            "identical to the RTL's".to_string()
        } else {
            format!("{differ} pixels differ from the RTL's")
        }
    );
    Ok(())
}
