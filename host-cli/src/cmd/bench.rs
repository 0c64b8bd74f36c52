//! `fpgfx bench`: the number-format and sub-pixel sweeps, written as CSV, Markdown and
//! Pareto plots, the table printed.

use std::path::PathBuf;

use anyhow::Result;

/// Arguments of `fpgfx bench`.
#[derive(clap::Args)]
pub struct Args {
    /// Ray-trace scene files (default: examples/reference.toml and examples/rt/*).
    #[arg(long = "scene")]
    scenes: Vec<PathBuf>,
    /// Raster command files (default: examples/raster/*.toml).
    #[arg(long = "raster")]
    raster: Vec<PathBuf>,
    /// Small frames and a reduced sweep (what CI runs).
    #[arg(long)]
    quick: bool,
    /// Timed runs per point; the median is reported.
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Output directory (bench.csv, bench.md, pareto-rt.png, pareto-raster.png).
    #[arg(short, long)]
    output: PathBuf,
}

/// Runs the sweeps, writes the files and prints the Markdown table.
pub fn run(a: &Args) -> Result<()> {
    use std::io::IsTerminal;
    let cfg = host_cli::bench::BenchConfig {
        scenes: a.scenes.clone(),
        raster_files: a.raster.clone(),
        quick: a.quick,
        repeats: a.repeats,
        root: PathBuf::from("."),
        progress: std::io::stderr().is_terminal(),
    };
    let report = host_cli::bench::run(&cfg)?;
    host_cli::bench::write(&report, &a.output)?;
    print!("{}", host_cli::bench::to_markdown(&report));
    Ok(())
}
