//! `fpgfx stress`: adversarial cases through the kernels, and a table of what broke.

use anyhow::Result;

/// Arguments of `fpgfx stress`.
#[derive(clap::Args)]
pub struct Args {
    /// Number of cases.
    #[arg(long, default_value_t = 100_000)]
    cases: u64,
    /// Generator seed: a case is a function of (seed, index).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Only one category: raster, rt or parse.
    #[arg(long)]
    only: Option<String>,
    /// Run only case K (as printed by a failure, with the same --seed and --only).
    #[arg(long)]
    case: Option<u64>,
    /// Worker threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
}

/// Runs the cases, prints the table, and fails if any case failed.
pub fn run(a: &Args) -> Result<()> {
    use host_cli::stress;
    let only = match &a.only {
        Some(name) => Some(
            stress::Category::parse(name)
                .ok_or_else(|| anyhow::anyhow!("--only {name:?}: expected raster, rt or parse"))?,
        ),
        None => None,
    };
    let report = stress::run(&stress::Config {
        cases: a.cases,
        seed: a.seed,
        only,
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
