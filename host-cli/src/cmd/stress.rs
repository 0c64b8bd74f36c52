//! `fpgfx stress`: the adversarial runner of [`host_cli::stress`], its table on stdout.

use anyhow::Result;
use host_cli::stress::{self, AcneCase, AcneList, Category};
use protocol::names::Named;

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
        acne: acne_list(),
    })?;
    for case in &report.acne {
        print_acne(case);
    }
    print!("{}", report.table());
    anyhow::ensure!(
        !report.failed(),
        "stress found failures (panics, NaN/inf, cracks, double writes, coverage, wraps or accepted non-finite input)"
    );
    Ok(())
}

/// Debugging aid, from the environment rather than a flag: `FPGFX_STRESS_ACNE=1` lists
/// the cases with acne on stderr, `FPGFX_STRESS_ACNE=2` (with `--case K`) also each
/// one's scene and black pixels.
fn acne_list() -> AcneList {
    match std::env::var_os("FPGFX_STRESS_ACNE") {
        None => AcneList::Off,
        Some(v) if v == "2" => AcneList::Pixels,
        Some(_) => AcneList::Cases,
    }
}

/// One entry of the acne list, on stderr (the table owns stdout).
fn print_acne(c: &AcneCase) {
    let format = c.numeric.name();
    if c.beyond_range {
        eprintln!(
            "acne: case {} {format} {} pixels, scene beyond the format's range",
            c.index, c.pixels
        );
    } else {
        eprintln!(
            "acne: case {} {format} {}/{} pixels",
            c.index, c.pixels, c.checked
        );
    }
    if let Some(d) = &c.detail {
        eprintln!("acne in {} scene, {format}: {:?}", d.kind, d.scene);
        for p in &d.pixels {
            eprintln!(
                "  pixel ({}, {}): t {:e} p {:?} n {:?} n·wi {:.4} dist {:e} ref rgb {:?}",
                p.x, p.y, p.t, p.point, p.normal, p.n_dot_wi, p.light_distance, p.reference_rgb
            );
        }
    }
}
