//! `fpgfx bench`: the sweeps of [`host_cli::sweep`], with a progress bar per sweep on a
//! terminal's stderr, the outputs written to `--output` and the tables on stdout.

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::Result;
use host_cli::sweep::{self, BenchConfig, Progress};

/// Arguments of `fpgfx bench`.
#[derive(clap::Args)]
pub struct Args {
    /// Ray-trace scene files (default: examples/reference.toml and examples/rt/*, which
    /// the binary carries: it runs from any directory).
    #[arg(long = "scene")]
    pub scenes: Vec<PathBuf>,
    /// Raster command files (default: examples/raster/*.toml, carried in the binary).
    #[arg(long = "raster")]
    pub raster: Vec<PathBuf>,
    /// Small frames and a reduced sweep (what CI runs).
    #[arg(long)]
    pub quick: bool,
    /// Timed runs per point; the median is reported.
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// Output directory (bench.csv, bench.md, pareto-rt.png, pareto-raster.png).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Runs both sweeps, writes the outputs and prints the Markdown tables.
pub fn run(a: &Args) -> Result<()> {
    super::check_output_dir(&super::flag_path("-o/--output", &a.output), &a.output)?;
    let cfg = BenchConfig {
        scenes: a.scenes.clone(),
        raster_files: a.raster.clone(),
        quick: a.quick,
        repeats: a.repeats,
    };
    let mut bars = Bars::new(std::io::stderr().is_terminal());
    let report = sweep::run_with_progress(&cfg, &mut |p| bars.show(p))?;
    sweep::write(&report, &a.output)?;
    print!("{}", sweep::to_markdown(&report));
    Ok(())
}

/// One indicatif bar per sweep, drawn from the library's progress events (hidden when
/// stderr is not a terminal, so that logs stay clean).
struct Bars {
    visible: bool,
    bar: Option<indicatif::ProgressBar>,
}

impl Bars {
    fn new(visible: bool) -> Self {
        Self { visible, bar: None }
    }

    fn show(&mut self, p: Progress) {
        match p {
            Progress::Started { sweep, runs } => {
                let b = if self.visible {
                    indicatif::ProgressBar::new(runs)
                } else {
                    indicatif::ProgressBar::hidden()
                };
                if let Ok(style) = indicatif::ProgressStyle::with_template(
                    "{msg} [{bar:40}] {pos}/{len} {elapsed_precise}",
                ) {
                    b.set_style(style);
                }
                b.set_message(sweep.name());
                self.bar = Some(b);
            }
            Progress::Ran { .. } => {
                if let Some(b) = &self.bar {
                    b.inc(1);
                }
            }
            Progress::Finished { .. } => {
                if let Some(b) = self.bar.take() {
                    b.finish_and_clear();
                }
            }
        }
    }
}
