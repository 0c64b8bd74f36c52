//! `fpgfx stress`: the adversarial runner of [`host_cli::stress`], its table on stdout.

use anyhow::Result;
use host_cli::stress::{self, Category};

/// Arguments of `fpgfx stress`.
#[derive(clap::Args)]
pub struct Args {
    /// Number of cases.
    #[arg(long, default_value_t = 100_000)]
    pub cases: u64,
    /// Generator seed: a case is a function of (seed, index).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Only one category.
    #[arg(long)]
    pub only: Option<Category>,
    /// Run only case K (as printed by a failure, with the same --seed and --only).
    #[arg(long)]
    pub case: Option<u64>,
    /// Worker threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
}

/// Runs the cases and prints the table; fails when the run found failures.
pub fn run(a: &Args) -> Result<()> {
    let report = stress::run(&stress::Config {
        cases: a.cases,
        seed: a.seed,
        only: a.only,
        case: a.case,
        threads: a.threads,
    })?;
    print!("{}", report.table());
    anyhow::ensure!(
        !report.failed(),
        "stress found failures (panics, NaN/inf, cracks, double writes, coverage, wraps or accepted non-finite input)"
    );
    Ok(())
}
