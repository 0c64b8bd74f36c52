//! What a run counted, and the table `fpgfx stress` prints.

use protocol::frame::Numeric;
use protocol::names::Named;
use sim_target::rt::Scene;

use super::Category;

/// Counts of one category (or of one case).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    /// Cases run, passed or not: the denominator of every other count.
    pub cases: u64,
    /// Cases that panicked.
    pub panics: u64,
    /// NaN/∞ produced from finite inputs: NaN results of kernel operations and
    /// non-finite depth or normal outputs of a hit.
    pub nonfinite: u64,
    /// Saturated fixed-point results (and float overflows to ∞).
    pub saturations: u64,
    /// NaN from an infinite operand after a float overflow (not a failure).
    pub overflow_nans: u64,
    /// NaN/∞ outputs of scenes whose magnitudes exceed the format's range (see
    /// [`range_demand`](super::range_demand)): reported, not failed: the format cannot
    /// hold the scene.
    pub nonfinite_out_of_range: u64,
    /// Renders of scenes beyond their format's range.
    pub out_of_range: u64,
    /// Results neither exact nor saturated, or negative depths: a wrap-around.
    pub wraps: u64,
    /// Pixels strictly inside a closed mesh that no triangle wrote.
    pub cracks: u64,
    /// Pixels of a mesh (or a single primitive path that must write once) written twice.
    pub double_writes: u64,
    /// Pixels whose write count differs from the exact top-left reference.
    pub coverage: u64,
    /// Lit pixels of a self-shadow-free scene that came out black, in scenes within the
    /// format's range.
    pub acne: u64,
    /// Pixels the acne test looked at in those scenes.
    pub acne_checked: u64,
    /// Black lit pixels of scenes beyond the format's range
    /// ([`range_demand`](super::range_demand): e.g. a light whose squared distance the
    /// format cannot hold, so its irradiance is lost), which are the format's limit rather
    /// than acne.
    pub acne_out_of_range: u64,
    /// Inputs the kernels or parsers refused with an error (expected for bad input).
    pub rejected: u64,
    /// Files with NaN/∞ a parser accepted.
    pub accepted_nonfinite: u64,
    /// Ray-trace renders whose image or AOVs changed when the plan's culling was turned
    /// off: culling must be invisible.
    pub cull_mismatches: u64,
}

impl Counts {
    pub(super) fn add(&mut self, o: &Counts) {
        self.cases += o.cases;
        self.panics += o.panics;
        self.nonfinite += o.nonfinite;
        self.saturations += o.saturations;
        self.overflow_nans += o.overflow_nans;
        self.nonfinite_out_of_range += o.nonfinite_out_of_range;
        self.out_of_range += o.out_of_range;
        self.wraps += o.wraps;
        self.cracks += o.cracks;
        self.double_writes += o.double_writes;
        self.coverage += o.coverage;
        self.acne += o.acne;
        self.acne_checked += o.acne_checked;
        self.acne_out_of_range += o.acne_out_of_range;
        self.rejected += o.rejected;
        self.accepted_nonfinite += o.accepted_nonfinite;
        self.cull_mismatches += o.cull_mismatches;
    }

    /// Whether these counts fail a run.
    pub fn failed(&self) -> bool {
        self.panics
            + self.nonfinite
            + self.wraps
            + self.cracks
            + self.double_writes
            + self.coverage
            + self.accepted_nonfinite
            + self.cull_mismatches
            > 0
    }
}

/// Per-format ray-tracer counts (index: position in [`Numeric::ALL`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FormatCounts {
    /// Renders in this format.
    pub renders: u64,
    /// Saturations seen by the probe.
    pub saturations: u64,
    /// NaN after an overflow.
    pub overflow_nans: u64,
    /// Renders of scenes beyond the format's range.
    pub out_of_range: u64,
    /// NaN/∞ outputs of those.
    pub nonfinite_out_of_range: u64,
    /// NaN/∞ produced.
    pub nonfinite: u64,
    /// Acne pixels in scenes within the format's range.
    pub acne: u64,
    /// Pixels checked for acne in those.
    pub acne_checked: u64,
    /// Black lit pixels of scenes beyond the format's range.
    pub acne_out_of_range: u64,
}

impl FormatCounts {
    /// Adds another run's counts.
    pub fn add(&mut self, o: &FormatCounts) {
        self.renders += o.renders;
        self.saturations += o.saturations;
        self.overflow_nans += o.overflow_nans;
        self.out_of_range += o.out_of_range;
        self.nonfinite_out_of_range += o.nonfinite_out_of_range;
        self.nonfinite += o.nonfinite;
        self.acne += o.acne;
        self.acne_checked += o.acne_checked;
        self.acne_out_of_range += o.acne_out_of_range;
    }
}

/// One failing case, enough to run it again.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Failure {
    /// Category the case belongs to (use with `--only`).
    pub category: Category,
    /// Its index (use with the same `--seed` and `--only`).
    pub index: u64,
    /// What went wrong.
    pub what: String,
}

/// The result of a run.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// Counts per category, in [`Category::ALL`] order.
    pub by_category: [Counts; 3],
    /// Ray-tracer counts per number format, in [`Numeric::ALL`] order.
    pub by_format: [FormatCounts; 7],
    /// The first failures (at most [`MAX_FAILURES`]), lowest index first.
    pub failures: Vec<Failure>,
    /// Wall-clock seconds of the whole run, for the summary line.
    pub seconds: f64,
    /// Seed the run used ([`Config::seed`](super::Config::seed)), printed so a failure can be run again.
    pub seed: u64,
    /// The cases with acne, lowest index first, when [`Config::acne`](super::Config::acne)
    /// asked for them (empty otherwise).
    pub acne: Vec<AcneCase>,
}

/// How much of the acne a run lists case by case ([`Report::acne`]) beyond the counts: a
/// debugging aid for finding the scenes a format self-shadows, off by default because a
/// long run has thousands of such cases and the scenes are large.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum AcneList {
    /// Counts only.
    #[default]
    Off,
    /// Each case with black lit pixels: index, format and pixel counts.
    Cases,
    /// Also each such case's scene and every black pixel (meant for `--case K`).
    Pixels,
}

/// A case whose render left lit pixels black: acne, or, when its scene lies beyond the
/// format's range, the format's range limit.
#[derive(Debug, Clone)]
pub struct AcneCase {
    /// The case index (with the run's seed and `only`).
    pub index: u64,
    /// The format it rendered in.
    pub numeric: Numeric,
    /// Black lit pixels.
    pub pixels: u64,
    /// Pixels the acne check looked at; 0 when `beyond_range` (those are not checked).
    pub checked: u64,
    /// The scene needs more range than the format has, so its black pixels are counted
    /// apart from acne ([`Counts::acne_out_of_range`]).
    pub beyond_range: bool,
    /// With [`AcneList::Pixels`]: the scene and each black pixel.
    pub detail: Option<AcneDetail>,
}

/// The scene of an [`AcneCase`] and its black pixels, for [`AcneList::Pixels`].
#[derive(Debug, Clone)]
pub struct AcneDetail {
    /// Which generator made the scene (`Acne` or `Coincident`).
    pub kind: String,
    /// The scene as rendered.
    pub scene: Scene,
    /// Every black pixel, in raster order.
    pub pixels: Vec<AcnePixel>,
}

/// One black lit pixel, with what the f64 reference saw there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AcnePixel {
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
    /// Distance to the reference's hit along the primary ray.
    pub t: f64,
    /// The reference's hit point.
    pub point: [f64; 3],
    /// The reference's normal there (facing the eye).
    pub normal: [f64; 3],
    /// n·ωᵢ: how squarely the surface faces the light (checked pixels have at least 0.3).
    pub n_dot_wi: f64,
    /// Distance from the hit point to the light.
    pub light_distance: f64,
    /// The reference's colour of the pixel.
    pub reference_rgb: [u8; 3],
}

/// Failures kept in a report.
pub const MAX_FAILURES: usize = 20;

impl Report {
    /// Sum over categories.
    pub fn total(&self) -> Counts {
        let mut t = Counts::default();
        for c in &self.by_category {
            t.add(c);
        }
        t
    }

    /// Whether the run must exit non-zero.
    pub fn failed(&self) -> bool {
        self.total().failed()
    }

    /// The counts as the text table `fpgfx stress` prints.
    pub fn table(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let row = |s: &mut String, name: &str, c: &Counts| {
            let _ = writeln!(
                s,
                "{name:<8}{:>9}{:>7}{:>8}{:>11}{:>7}{:>7}{:>8}{:>9}{:>7}{:>10}{:>9}{:>9}{:>8}",
                c.cases,
                c.panics,
                c.nonfinite,
                c.saturations,
                c.wraps,
                c.cracks,
                c.double_writes,
                c.coverage,
                c.acne,
                c.acne_checked,
                c.rejected,
                c.accepted_nonfinite,
                c.cull_mismatches
            );
        };
        let _ = writeln!(
            s,
            "{:<8}{:>9}{:>7}{:>8}{:>11}{:>7}{:>7}{:>8}{:>9}{:>7}{:>10}{:>9}{:>9}{:>8}",
            "kind",
            "cases",
            "panic",
            "NaN/inf",
            "saturated",
            "wraps",
            "cracks",
            "double",
            "coverage",
            "acne",
            "acne/of",
            "rejected",
            "accepted",
            "culled≠"
        );
        for (k, c) in Category::ALL.iter().zip(&self.by_category) {
            if c.cases > 0 {
                row(&mut s, k.name(), c);
            }
        }
        row(&mut s, "total", &self.total());
        if self.by_format.iter().any(|f| f.renders > 0) {
            let _ = writeln!(
                s,
                "\nrt by format  {:>8}{:>12}{:>10}{:>9}{:>8}{:>9}{:>8}{:>10}{:>11}",
                "renders",
                "saturated",
                "NaN(ovf)",
                "NaN/inf",
                "acne",
                "acne/of",
                "beyond",
                "NaN(bynd)",
                "acne(bynd)"
            );
            for (n, f) in Numeric::ALL.iter().zip(&self.by_format) {
                let _ = writeln!(
                    s,
                    "  {:<11}{:>8}{:>12}{:>10}{:>9}{:>8}{:>9}{:>8}{:>10}{:>11}",
                    n.name(),
                    f.renders,
                    f.saturations,
                    f.overflow_nans,
                    f.nonfinite,
                    f.acne,
                    f.acne_checked,
                    f.out_of_range,
                    f.nonfinite_out_of_range,
                    f.acne_out_of_range
                );
            }
        }
        let _ = writeln!(s, "\nseed {}  {:.2} s", self.seed, self.seconds);
        for f in &self.failures {
            let _ = writeln!(
                s,
                "FAIL {} case {} (reproduce: fpgfx stress --seed {} --only {} --case {}): {}",
                f.category.name(),
                f.index,
                self.seed,
                f.category.name(),
                f.index,
                f.what
            );
        }
        s
    }
}

/// The outcome of one case.
#[derive(Debug, Clone, Default)]
pub struct CaseResult {
    /// What the case counted, added to its category's [`Counts`].
    pub counts: Counts,
    /// Per-format counts (rt only).
    pub formats: [FormatCounts; 7],
    /// Why it failed, if it did.
    pub failure: Option<String>,
    /// The scene and black pixels of an rt case with acne, when asked for
    /// ([`AcneList::Pixels`]).
    pub acne: Option<AcneDetail>,
}
