//! `fpgfx stress`: adversarial cases from docs/requirements.md §5.4 run through the
//! product's own kernels (the raster block, the ray tracer, the two file parsers), counting
//! what goes wrong.
//!
//! Every case is a pure function of `(seed, index)`: a failure prints both, and
//! `--case K` runs that one case again. Categories, and what each counts:
//! - **raster**: closed meshes (fans, strips, jittered grids) whose shared edges must
//!   cover every pixel exactly once (cracks, double writes, mismatches against an exact
//!   `i128` reference of the top-left rule); single degenerate, sliver and limit-sized
//!   triangles (coverage against the reference); every other primitive with extreme
//!   values (no panic, errors counted as rejections).
//! - **rt**: tiny frames in every number format through [`Probe`], which counts
//!   saturations, NaN and wrap-arounds of each operation; grazing and parallel rays, huge
//!   and tiny scales, near-coincident surfaces; shadow acne on scenes where no lit pixel
//!   can be in shadow.
//! - **parse**: NaN/∞ and random damage injected into valid scene and raster files; a
//!   parser must reject every non-finite number and never panic.
//!
//! A run fails (non-zero exit) on any panic, NaN/∞ reaching an output, crack, double
//! write or coverage mismatch, wrap-around, or a non-finite input a parser accepted.
//!
//! One file per job: `report` (the counts and the table), `runner` (the run, its worker
//! threads and panic hook, each case's generator), `raster`, `rt` and `damage` (the
//! parse category: damaged scene and raster files).
//!
//! [`Probe`]: sim_target::num::instrumented::Probe

mod damage;
mod raster;
mod report;
mod rt;
mod runner;

pub use jobs::scene::range::range_demand;
pub use report::{
    AcneCase, AcneDetail, AcneList, AcnePixel, CaseResult, Counts, Failure, FormatCounts, Report,
    MAX_FAILURES,
};
pub use runner::{category_of, run, run_case};

/// Which kernels a case attacks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Category {
    /// The raster block's golden model: meshes, degenerate triangles, extreme primitives.
    Raster,
    /// The ray tracer in every number format, through the instrumented [`Probe`](sim_target::num::instrumented::Probe) format.
    Rt,
    /// The scene-file and raster-file parsers.
    Parse,
}

impl Category {
    /// All categories, in table order.
    pub const ALL: [Category; 3] = [Category::Raster, Category::Rt, Category::Parse];
}

// The one spelling of each category (`--only`, the table, a failure's reproduce line).
protocol::named! {
    Category, what = "category", ignore_case = false, values = Category::ALL,
    { Raster => ["raster"], Rt => ["rt"], Parse => ["parse"] }
}

/// Errors of the stress runner itself (not of the kernels, which are counted).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StressError {
    /// A worker pool could not be built.
    #[error("cannot start worker pool: {0}")]
    Pool(String),
}

/// What one run does.
#[derive(Debug, Clone, Copy)]
pub struct Config {
    /// Cases to run (indices `0..cases`).
    pub cases: u64,
    /// Seed every case's generator is derived from, with its index.
    pub seed: u64,
    /// Restrict to one category (indices keep their meaning within it).
    pub only: Option<Category>,
    /// Run only this case index.
    pub case: Option<u64>,
    /// Worker threads (0 = all cores).
    pub threads: usize,
    /// Which acne cases to list in [`Report::acne`].
    pub acne: AcneList,
}
