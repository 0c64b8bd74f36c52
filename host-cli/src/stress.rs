//! `fpgfx stress`: adversarial cases from SPEC §5 run through the product's own kernels
//! (the raster block, the ray tracer, the two file parsers), counting what goes wrong.
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

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use protocol::frame::{
    Aa, AaPattern, Bezier, BezierPatch, Circle, Connectivity, Cull, FillRule, Filter, Line,
    LineAlgo, Numeric, Pixel, Point, Polygon, RasterCmd, RasterSetup, Rgb, SeedFill, Shade, TexRef,
    Traversal, Triangle, Wrap,
};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use sim_target::num::{Q16_16, Q24_8, Q32_32, Q8_24};
use sim_target::raster::tri::{COORD_LIMIT, MAX_SUBPIXEL_BITS};
use sim_target::raster::Raster;
use sim_target::rt::{self, Frame, RenderOptions, Scene};

pub use probe::{Probe, Seen};

/// Which kernels a case attacks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Category {
    /// The raster block.
    Raster,
    /// The ray tracer.
    Rt,
    /// The scene-file and raster-file parsers.
    Parse,
}

impl Category {
    /// All categories, in table order.
    pub const ALL: [Category; 3] = [Category::Raster, Category::Rt, Category::Parse];

    /// Name as the CLI spells it.
    pub fn name(self) -> &'static str {
        match self {
            Category::Raster => "raster",
            Category::Rt => "rt",
            Category::Parse => "parse",
        }
    }

    /// Parses a CLI name.
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.name() == s)
    }
}

/// Errors of the stress runner itself (not of the kernels, which are counted).
#[derive(Debug, thiserror::Error)]
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
    /// Generator seed.
    pub seed: u64,
    /// Restrict to one category (indices keep their meaning within it).
    pub only: Option<Category>,
    /// Run only this case index.
    pub case: Option<u64>,
    /// Worker threads (0 = all cores).
    pub threads: usize,
}

/// Counts of one category (or of one case).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    /// Cases run.
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
    /// [`range_demand`]): reported, not failed: the format cannot hold the scene.
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
    /// Black lit pixels of scenes beyond the format's range ([`range_demand`]: e.g. a
    /// light whose squared distance the format cannot hold, so its irradiance is lost),
    /// which are the format's limit rather than acne.
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
    fn add(&mut self, o: &Counts) {
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
    /// Its category.
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
    /// Wall-clock seconds.
    pub seconds: f64,
    /// The seed.
    pub seed: u64,
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

    /// The human-readable table.
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
                    numeric_name(*n),
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

fn numeric_name(n: Numeric) -> &'static str {
    match n {
        Numeric::F64 => "f64",
        Numeric::F32 => "f32",
        Numeric::F16 => "f16",
        Numeric::Q16_16 => "q16.16",
        Numeric::Q8_24 => "q8.24",
        Numeric::Q24_8 => "q24.8",
        Numeric::Q32_32 => "q32.32",
    }
}

/// The outcome of one case.
#[derive(Debug, Clone, Default)]
pub struct CaseResult {
    /// Its counts.
    pub counts: Counts,
    /// Per-format counts (rt only).
    pub formats: [FormatCounts; 7],
    /// Why it failed, if it did.
    pub failure: Option<String>,
}

/// The category of case `index` when `only` is not given.
pub fn category_of(index: u64, only: Option<Category>) -> Category {
    only.unwrap_or(Category::ALL[(index % 3) as usize])
}

fn case_rng(seed: u64, index: u64, cat: Category) -> SmallRng {
    let mut x = seed ^ 0x5851_f42d_4c95_7f2d_u64.wrapping_mul(index.wrapping_add(1));
    x ^= (cat as u64) << 61;
    // splitmix64 so that neighbouring indices give unrelated streams
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    SmallRng::seed_from_u64(x ^ (x >> 31))
}

thread_local! {
    /// Where the last panic on this thread happened (filled by the run's panic hook).
    static PANIC_AT: std::cell::RefCell<String> = const { std::cell::RefCell::new(String::new()) };
}

/// Runs one case, catching a panic, on a private one-thread pool (so that the probe's
/// per-thread counts see the whole render and nothing else). Panics are caught but still
/// reported by the current panic hook; [`run`] silences it.
pub fn run_case(
    seed: u64,
    index: u64,
    only: Option<Category>,
) -> Result<(Category, CaseResult), StressError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| StressError::Pool(e.to_string()))?;
    Ok(pool.install(|| case_on_this_thread(seed, index, only)))
}

/// [`run_case`] on the calling thread, which must be the only thread of the current rayon
/// pool.
fn case_on_this_thread(seed: u64, index: u64, only: Option<Category>) -> (Category, CaseResult) {
    let cat = category_of(index, only);
    let mut rng = case_rng(seed, index, cat);
    probe::take();
    let out = catch_unwind(AssertUnwindSafe(|| match cat {
        Category::Raster => raster_case(&mut rng),
        Category::Rt => rt_case(&mut rng),
        Category::Parse => parse_case(&mut rng),
    }));
    let mut r = match out {
        Ok(r) => r,
        Err(e) => {
            let msg = e
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| e.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "non-string panic".into());
            let at = PANIC_AT.with(|p| std::mem::take(&mut *p.borrow_mut()));
            CaseResult {
                counts: Counts {
                    panics: 1,
                    ..Counts::default()
                },
                formats: Default::default(),
                failure: Some(format!("panic: {msg}{at}")),
            }
        }
    };
    r.counts.cases = 1;
    if r.counts.acne + r.counts.acne_out_of_range > 0 && list_acne() {
        // Debugging aid (FPGFX_STRESS_ACNE=1): which cases, in which format, have acne.
        let fmt = r.formats.iter().position(|f| f.renders > 0).unwrap_or(0);
        if r.counts.acne > 0 {
            eprintln!(
                "acne: case {index} {} {}/{} pixels",
                numeric_name(Numeric::ALL[fmt]),
                r.counts.acne,
                r.counts.acne_checked
            );
        } else {
            eprintln!(
                "acne: case {index} {} {} pixels, scene beyond the format's range",
                numeric_name(Numeric::ALL[fmt]),
                r.counts.acne_out_of_range
            );
        }
    }
    if r.failure.is_none() && r.counts.failed() {
        r.failure = Some(format!("{:?}", r.counts));
    }
    (cat, r)
}

fn list_acne() -> bool {
    static LIST: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *LIST.get_or_init(|| std::env::var_os("FPGFX_STRESS_ACNE").is_some())
}

fn list_acne_verbose() -> bool {
    static LIST: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *LIST.get_or_init(|| std::env::var_os("FPGFX_STRESS_ACNE").is_some_and(|v| v == "2"))
}

/// Runs `cfg.cases` cases (or the one of `cfg.case`) on all cores. Each worker thread owns
/// a one-thread rayon pool, so a ray-trace render (which is itself parallel over rows)
/// stays on that thread and its probe counts belong to one case.
pub fn run(cfg: &Config) -> Result<Report, StressError> {
    let started = Instant::now();
    let indices: Vec<u64> = match cfg.case {
        Some(k) => vec![k],
        None => (0..cfg.cases).collect(),
    };
    let threads = if cfg.threads == 0 {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    } else {
        cfg.threads
    };
    let next = AtomicU64::new(0);
    let total = Mutex::new(Report {
        seed: cfg.seed,
        ..Report::default()
    });
    // A panicking case is counted, not printed: silence the default hook meanwhile.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|info| {
        let at = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        PANIC_AT.with(|p| *p.borrow_mut() = at);
    }));
    let pools: Result<Vec<rayon::ThreadPool>, StressError> = (0..threads)
        .map(|_| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .map_err(|e| StressError::Pool(e.to_string()))
        })
        .collect();
    let pools = match pools {
        Ok(p) => p,
        Err(e) => {
            std::panic::set_hook(hook);
            return Err(e);
        }
    };
    std::thread::scope(|sc| {
        for pool in &pools {
            sc.spawn(|| {
                pool.install(|| {
                    let mut local = Report::default();
                    loop {
                        let k = next.fetch_add(1, Ordering::Relaxed) as usize;
                        let Some(&index) = indices.get(k) else { break };
                        let (cat, r) = case_on_this_thread(cfg.seed, index, cfg.only);
                        local.by_category[cat as usize].add(&r.counts);
                        for (a, b) in local.by_format.iter_mut().zip(&r.formats) {
                            a.add(b);
                        }
                        if let Some(what) = r.failure {
                            local.failures.push(Failure {
                                category: cat,
                                index,
                                what,
                            });
                        }
                    }
                    let mut t = total.lock().unwrap_or_else(|p| p.into_inner());
                    for (a, b) in t.by_category.iter_mut().zip(&local.by_category) {
                        a.add(b);
                    }
                    for (a, b) in t.by_format.iter_mut().zip(&local.by_format) {
                        a.add(b);
                    }
                    t.failures.extend(local.failures);
                });
            });
        }
    });
    std::panic::set_hook(hook);
    let mut report = total.into_inner().unwrap_or_else(|p| p.into_inner());
    report.failures.sort_by_key(|f| f.index);
    report.failures.truncate(MAX_FAILURES);
    report.seconds = started.elapsed().as_secs_f64();
    Ok(report)
}

// ---------------------------------------------------------------------------------------
// Raster
// ---------------------------------------------------------------------------------------

const TRAVERSALS: [Traversal; 5] = [
    Traversal::BoundingBox,
    Traversal::Scanline,
    Traversal::Zigzag,
    Traversal::Tiles,
    Traversal::Simd8,
];

fn rgb(rng: &mut SmallRng) -> Rgb {
    Rgb::new(rng.gen(), rng.gen(), rng.gen())
}

/// A coordinate in sub-pixel units: mostly near the viewport, sometimes at the guard
/// band's limit or just beyond it (which must be refused).
fn coord(rng: &mut SmallRng, bits: u8, side: u32) -> i32 {
    let unit = 1i64 << bits;
    let v: i64 = match rng.gen_range(0..10) {
        0 => COORD_LIMIT as i64 * if rng.gen() { 1 } else { -1 },
        1 => (COORD_LIMIT as i64 - rng.gen_range(0..4)) * if rng.gen() { 1 } else { -1 },
        2 => (COORD_LIMIT as i64 + rng.gen_range(1..4)) * if rng.gen() { 1 } else { -1 },
        3 => rng.gen_range(-(COORD_LIMIT as i64)..=COORD_LIMIT as i64),
        _ => rng.gen_range(-2 * unit..(side as i64 + 2) * unit),
    };
    v as i32
}

fn rand_point(rng: &mut SmallRng, bits: u8, side: u32) -> Point {
    Point {
        x: coord(rng, bits, side),
        y: coord(rng, bits, side),
    }
}

/// The exact top-left rule, written independently of the kernel: doubled sub-pixel units,
/// `i128`, the interior side from the signed area, and "top-left" from the outward
/// normal (left edge: it points to −x; top edge: horizontal, it points to −y, i.e. up).
fn ref_inside(v: &[Point; 3], bits: u8, cull: Cull, px: i64, py: i64) -> bool {
    let p: [(i128, i128); 3] = core::array::from_fn(|k| (2 * v[k].x as i128, 2 * v[k].y as i128));
    let area2 = (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[1].1 - p[0].1) * (p[2].0 - p[0].0);
    if area2 == 0 {
        return false;
    }
    // y down: a positive signed area is clockwise on screen.
    match (cull, area2 > 0) {
        (Cull::Clockwise, true) | (Cull::CounterClockwise, false) => return false,
        _ => {}
    }
    let s: i128 = area2.signum();
    let h = 1i128 << bits;
    let (cx, cy) = ((2 * px as i128 + 1) * h, (2 * py as i128 + 1) * h);
    for k in 0..3 {
        let (a, b) = (p[k], p[(k + 1) % 3]);
        // Inward normal n = s·(−(by − ay), bx − ax); E = n·(c − a).
        let nx = -s * (b.1 - a.1);
        let ny = s * (b.0 - a.0);
        let e = nx * (cx - a.0) + ny * (cy - a.1);
        if e < 0 {
            return false;
        }
        if e == 0 {
            // outward = −n
            let top_left = -nx < 0 || (nx == 0 && -ny < 0);
            if !top_left {
                return false;
            }
        }
    }
    true
}

/// Where a point lies with respect to a simple closed polygon, exactly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Inside,
    Boundary,
    Outside,
}

fn polygon_side(poly: &[(i128, i128)], q: (i128, i128)) -> Side {
    let mut wn = 0i32;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let cross = (b.0 - a.0) * (q.1 - a.1) - (b.1 - a.1) * (q.0 - a.0);
        if cross == 0
            && q.0 >= a.0.min(b.0)
            && q.0 <= a.0.max(b.0)
            && q.1 >= a.1.min(b.1)
            && q.1 <= a.1.max(b.1)
        {
            return Side::Boundary;
        }
        if a.1 <= q.1 {
            if b.1 > q.1 && cross > 0 {
                wn += 1;
            }
        } else if b.1 <= q.1 && cross < 0 {
            wn -= 1;
        }
    }
    if wn != 0 {
        Side::Inside
    } else {
        Side::Outside
    }
}

fn cross(o: Point, a: Point, b: Point) -> i128 {
    (a.x as i128 - o.x as i128) * (b.y as i128 - o.y as i128)
        - (a.y as i128 - o.y as i128) * (b.x as i128 - o.x as i128)
}

/// A closed mesh: triangles, and the outline of their union when the mesh is known to
/// tile it (then every pixel strictly inside must be written exactly once).
struct Mesh {
    tris: Vec<[Point; 3]>,
    outline: Option<Vec<Point>>,
}

fn pt(x: i64, y: i64) -> Point {
    Point {
        x: x.clamp(-(COORD_LIMIT as i64), COORD_LIMIT as i64) as i32,
        y: y.clamp(-(COORD_LIMIT as i64), COORD_LIMIT as i64) as i32,
    }
}

/// A fan around a centre: boundary points at sorted angles with gaps below π, so that the
/// union is the star-shaped outline. Sometimes a boundary point is split exactly on its
/// edge (a collinear vertex: zero-area neighbours in the outline) or repeated.
fn fan(rng: &mut SmallRng, bits: u8, side: u32) -> Mesh {
    let unit = 1i64 << bits;
    let huge = rng.gen_ratio(1, 4);
    let c = (
        rng.gen_range(0..=side as i64 * unit),
        rng.gen_range(0..=side as i64 * unit),
    );
    let n = rng.gen_range(3..=10);
    let mut angles: Vec<f64> = (0..n)
        .map(|_| rng.gen_range(0.0..std::f64::consts::TAU))
        .collect();
    angles.sort_by(f64::total_cmp);
    let max_r = if huge {
        COORD_LIMIT as f64
    } else {
        side as f64 * unit as f64
    };
    let mut pts: Vec<Point> = angles
        .iter()
        .map(|a| {
            let r = rng.gen_range(1.0..max_r.max(2.0));
            pt(
                c.0 + (r * a.cos()).round() as i64,
                c.1 + (r * a.sin()).round() as i64,
            )
        })
        .collect();
    if rng.gen_ratio(1, 3) {
        let k = rng.gen_range(0..pts.len());
        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
        if (a.x + b.x) % 2 == 0 && (a.y + b.y) % 2 == 0 {
            pts.insert(
                k + 1,
                pt((a.x as i64 + b.x as i64) / 2, (a.y as i64 + b.y as i64) / 2),
            );
        }
    }
    let cp = pt(c.0, c.1);
    let mut tris = Vec::new();
    let mut valid = true;
    for k in 0..pts.len() {
        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
        // Consistent winding (angles increase); a reflex gap breaks the star.
        if cross(cp, a, b) < 0 {
            valid = false;
        }
        let mut t = [cp, a, b];
        if rng.gen() {
            t.swap(1, 2);
        }
        tris.push(t);
    }
    // The outline must turn by the sum of the fan angles, i.e. once: check with exact
    // orientation that every boundary point is strictly around the centre.
    let total: f64 = (0..pts.len())
        .map(|k| {
            let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
            let a0 = (a.y as f64 - cp.y as f64).atan2(a.x as f64 - cp.x as f64);
            let b0 = (b.y as f64 - cp.y as f64).atan2(b.x as f64 - cp.x as f64);
            (b0 - a0).rem_euclid(std::f64::consts::TAU)
        })
        .sum();
    if (total - std::f64::consts::TAU).abs() > 1e-6 || pts.contains(&cp) {
        valid = false;
    }
    Mesh {
        tris,
        outline: valid.then_some(pts),
    }
}

/// A jittered grid of convex quads, each split along a random diagonal; one row is a
/// strip. Jitter below a quarter of a cell keeps every quad convex (checked exactly).
fn grid(rng: &mut SmallRng, bits: u8, side: u32) -> Mesh {
    let unit = 1i64 << bits;
    let (nx, ny) = (rng.gen_range(1..=5usize), rng.gen_range(1..=5usize));
    let huge = rng.gen_ratio(1, 5);
    let span = if huge {
        (COORD_LIMIT as i64) / 3
    } else {
        side as i64 * unit
    };
    let cw = rng.gen_range(4..=(span / nx as i64).max(5));
    let ch = rng.gen_range(4..=(span / ny as i64).max(5));
    let j = (cw.min(ch) - 1) / 4;
    let ox = rng.gen_range(-2 * unit..=side as i64 * unit) - if huge { span / 2 } else { 0 };
    let oy = rng.gen_range(-2 * unit..=side as i64 * unit) - if huge { span / 2 } else { 0 };
    let mut v = vec![vec![Point { x: 0, y: 0 }; nx + 1]; ny + 1];
    for (r, row) in v.iter_mut().enumerate() {
        for (c, p) in row.iter_mut().enumerate() {
            let jx = if j > 0 { rng.gen_range(-j..=j) } else { 0 };
            let jy = if j > 0 { rng.gen_range(-j..=j) } else { 0 };
            *p = pt(ox + c as i64 * cw + jx, oy + r as i64 * ch + jy);
        }
    }
    let mut tris = Vec::new();
    let mut valid = true;
    for r in 0..ny {
        for c in 0..nx {
            let q = [v[r][c], v[r][c + 1], v[r + 1][c + 1], v[r + 1][c]];
            let s: Vec<i128> = (0..4)
                .map(|k| cross(q[k], q[(k + 1) % 4], q[(k + 2) % 4]))
                .collect();
            if !(s.iter().all(|&x| x > 0) || s.iter().all(|&x| x < 0)) {
                valid = false;
            }
            let (a, b) = if rng.gen() {
                ([q[0], q[1], q[2]], [q[0], q[2], q[3]])
            } else {
                ([q[0], q[1], q[3]], [q[1], q[2], q[3]])
            };
            for mut t in [a, b] {
                if rng.gen() {
                    t.swap(0, 1);
                }
                tris.push(t);
            }
        }
    }
    let mut outline = Vec::new();
    outline.extend((0..=nx).map(|c| v[0][c]));
    outline.extend((1..=ny).map(|r| v[r][nx]));
    outline.extend((0..nx).rev().map(|c| v[ny][c]));
    outline.extend((1..ny).rev().map(|r| v[r][0]));
    // Clamping at the guard band can fold the outline: only then is it not a tiling.
    if v.iter().flatten().any(|p| {
        p.x.unsigned_abs() >= COORD_LIMIT as u32 || p.y.unsigned_abs() >= COORD_LIMIT as u32
    }) {
        valid = false;
    }
    Mesh {
        tris,
        outline: valid.then_some(outline),
    }
}

fn setup(rng: &mut SmallRng, w: u32, h: u32, bits: u8) -> RasterSetup {
    RasterSetup {
        width: w as u16,
        height: h as u16,
        subpixel_bits: bits,
        background: Rgb::new(0, 0, 0),
        aa: Aa::default(),
        cull: Cull::None,
        traversal: TRAVERSALS[rng.gen_range(0..TRAVERSALS.len())],
    }
}

fn raster_case(rng: &mut SmallRng) -> CaseResult {
    let mut r = CaseResult::default();
    let (w, h) = (rng.gen_range(1..=16u32), rng.gen_range(1..=16u32));
    let bits = rng.gen_range(0..=MAX_SUBPIXEL_BITS);
    match rng.gen_range(0..10) {
        0..=3 => raster_mesh(rng, w, h, bits, &mut r),
        4..=7 => raster_triangle(rng, w, h, bits, &mut r),
        _ => raster_prims(rng, w, h, bits, &mut r),
    }
    r
}

fn raster_mesh(rng: &mut SmallRng, w: u32, h: u32, bits: u8, r: &mut CaseResult) {
    let side = w.max(h);
    let mesh = if rng.gen() {
        fan(rng, bits, side)
    } else {
        grid(rng, bits, side)
    };
    let s = setup(rng, w, h, bits);
    let Ok(mut block) = Raster::new(w, h, &s) else {
        r.counts.rejected += 1;
        return;
    };
    block.framebuffer_mut().track_writes(true);
    let color = rgb(rng);
    for t in &mesh.tris {
        let cmd = RasterCmd::Triangle(Triangle {
            v: *t,
            shade: Shade::Flat(color),
            z: None,
            w: None,
            tex: None,
        });
        if block.draw(&cmd).is_err() {
            r.counts.rejected += 1;
        }
    }
    let Some(counts) = block.framebuffer().write_counts() else {
        return;
    };
    let outline: Option<Vec<(i128, i128)>> = mesh.outline.as_ref().map(|o| {
        o.iter()
            .map(|p| (2 * p.x as i128, 2 * p.y as i128))
            .collect()
    });
    let hh = 1i128 << bits;
    for y in 0..h {
        for x in 0..w {
            let got = counts[(y * w + x) as usize] as u64;
            let want = mesh
                .tris
                .iter()
                .filter(|t| ref_inside(t, bits, Cull::None, x as i64, y as i64))
                .count() as u64;
            if got != want {
                r.counts.coverage += 1;
            }
            if let Some(o) = &outline {
                if got > 1 {
                    r.counts.double_writes += 1;
                }
                let c = ((2 * x as i128 + 1) * hh, (2 * y as i128 + 1) * hh);
                if got == 0 && polygon_side(o, c) == Side::Inside {
                    r.counts.cracks += 1;
                }
            }
        }
    }
    if r.counts.coverage + r.counts.cracks + r.counts.double_writes > 0 {
        r.failure = Some(format!(
            "mesh ({} triangles, {}x{}, {bits} bits, {:?}): {} cracks, {} double writes, {} coverage mismatches; triangles {:?}",
            mesh.tris.len(),
            w,
            h,
            s.traversal,
            r.counts.cracks,
            r.counts.double_writes,
            r.counts.coverage,
            mesh.tris
        ));
    }
}

/// A triangle that is degenerate, a sliver, at the coordinate limits, or random, with
/// random shading, depth, perspective, texture and AA.
fn adversarial_triangle(rng: &mut SmallRng, bits: u8, side: u32) -> [Point; 3] {
    let (a, b) = (rand_point(rng, bits, side), rand_point(rng, bits, side));
    let third = rand_point(rng, bits, side);
    match rng.gen_range(0..6) {
        // collinear: a + k(b − a) for small rational k
        0 => {
            let k = rng.gen_range(-2i64..=3);
            [
                a,
                b,
                pt(
                    a.x as i64 + k * (b.x as i64 - a.x as i64),
                    a.y as i64 + k * (b.y as i64 - a.y as i64),
                ),
            ]
        }
        // coincident vertices
        1 => [a, a, if rng.gen() { a } else { b }],
        // sliver: the midpoint nudged by one sub-pixel unit
        2 => {
            let m = pt(
                (a.x as i64 + b.x as i64) / 2 + rng.gen_range(-1..=1),
                (a.y as i64 + b.y as i64) / 2 + rng.gen_range(-1..=1),
            );
            [a, m, b]
        }
        // axis-aligned edges (exercise the top/left distinction exactly on centres)
        3 => {
            let u = 1i64 << bits;
            let q = |v: i64| (v.div_euclid(u) * u + u / 2) as i32;
            let (x0, y0, x1, y1) = (q(a.x as i64), q(a.y as i64), q(b.x as i64), q(b.y as i64));
            [
                Point { x: x0, y: y0 },
                Point { x: x1, y: y0 },
                Point {
                    x: if rng.gen() { x0 } else { x1 },
                    y: y1,
                },
            ]
        }
        _ => [a, b, third],
    }
}

fn raster_triangle(rng: &mut SmallRng, w: u32, h: u32, bits: u8, r: &mut CaseResult) {
    let side = w.max(h);
    let v = adversarial_triangle(rng, bits, side);
    let mut s = setup(rng, w, h, bits);
    s.cull = [Cull::None, Cull::Clockwise, Cull::CounterClockwise][rng.gen_range(0..3)];
    let aa = rng.gen_ratio(1, 5);
    if aa {
        s.aa = Aa {
            pattern: [
                AaPattern::Regular,
                AaPattern::Jitter,
                AaPattern::Rotated,
                AaPattern::Poisson,
                AaPattern::Coverage,
            ][rng.gen_range(0..5)],
            samples: if rng.gen_ratio(1, 4) {
                rng.gen()
            } else {
                rng.gen_range(1..=16)
            },
        };
    }
    let shade = if rng.gen() {
        Shade::Flat(rgb(rng))
    } else {
        Shade::Gouraud([rgb(rng), rgb(rng), rgb(rng)])
    };
    let extreme_u32 = |rng: &mut SmallRng| match rng.gen_range(0..4) {
        0 => 0,
        1 => u32::MAX,
        2 => 1,
        _ => rng.gen(),
    };
    let z = rng
        .gen_ratio(1, 4)
        .then(|| [0; 3].map(|_: u32| extreme_u32(rng) & 0xff_ffff));
    let wv = rng
        .gen_ratio(1, 4)
        .then(|| [0; 3].map(|_: u32| extreme_u32(rng)));
    let tex = rng.gen_ratio(1, 4).then(|| {
        let e = |rng: &mut SmallRng| match rng.gen_range(0..4) {
            0 => i32::MAX,
            1 => i32::MIN,
            _ => rng.gen_range(-(1 << 20)..(1 << 20)),
        };
        TexRef {
            base: if rng.gen_ratio(1, 8) { rng.gen() } else { 0 },
            width_log2: rng.gen_range(0..=12),
            height_log2: rng.gen_range(0..=12),
            uv: [[e(rng), e(rng)], [e(rng), e(rng)], [e(rng), e(rng)]],
            wrap: if rng.gen() { Wrap::Repeat } else { Wrap::Clamp },
            filter: [Filter::Nearest, Filter::Bilinear, Filter::Trilinear][rng.gen_range(0..3)],
        }
    });
    let Ok(mut block) = Raster::new(w, h, &s) else {
        r.counts.rejected += 1;
        return;
    };
    block.framebuffer_mut().track_writes(true);
    let t = Triangle {
        v,
        shade,
        z,
        w: wv,
        tex,
    };
    if block.draw(&RasterCmd::Triangle(t)).is_err() {
        r.counts.rejected += 1;
        return;
    }
    // Coverage is exact only where every covered pixel is written: no AA (which blends
    // partial pixels) and no depth test.
    if aa || z.is_some() {
        return;
    }
    let Some(counts) = block.framebuffer().write_counts() else {
        return;
    };
    for y in 0..h {
        for x in 0..w {
            let got = counts[(y * w + x) as usize];
            let want = ref_inside(&v, bits, s.cull, x as i64, y as i64) as u8;
            if got > 1 {
                r.counts.double_writes += 1;
            }
            if got != want {
                r.counts.coverage += 1;
            }
        }
    }
    if r.counts.coverage + r.counts.double_writes > 0 {
        r.failure = Some(format!(
            "triangle {v:?} ({w}x{h}, {bits} bits, {:?}, {:?}): {} coverage mismatches",
            s.traversal, s.cull, r.counts.coverage
        ));
    }
}

fn raster_prims(rng: &mut SmallRng, w: u32, h: u32, bits: u8, r: &mut CaseResult) {
    // Set-ups at and beyond their limits too.
    let (w, h, bits) = match rng.gen_range(0..12) {
        0 => (0, h, bits),
        1 => (w, 5000, bits),
        2 => (w, h, MAX_SUBPIXEL_BITS + rng.gen_range(1..4)),
        _ => (w, h, bits),
    };
    let s = setup(rng, w.max(1), h.max(1), bits);
    let Ok(mut block) = Raster::new(w, h, &s) else {
        r.counts.rejected += 1;
        return;
    };
    let side = w.max(h);
    for _ in 0..rng.gen_range(1..4) {
        let p = |rng: &mut SmallRng| rand_point(rng, bits, side);
        let cmd = match rng.gen_range(0..7) {
            0 => RasterCmd::Line(Line {
                from: p(rng),
                to: p(rng),
                color: Rgb::new(255, 255, 255),
                color_to: None,
                width: 0,
                aa: false,
                algo: LineAlgo::Bresenham,
            }),
            1 => {
                let (from, to) = (p(rng), p(rng));
                RasterCmd::Line(Line {
                    from,
                    to,
                    color: rgb(rng),
                    color_to: rng.gen::<bool>().then(|| rgb(rng)),
                    width: match rng.gen_range(0..4) {
                        0 => u32::MAX,
                        1 => rng.gen_range(0..(64 << bits)),
                        _ => 0,
                    },
                    aa: rng.gen(),
                    algo: if rng.gen() {
                        LineAlgo::Dda
                    } else {
                        LineAlgo::Bresenham
                    },
                })
            }
            2 => RasterCmd::Circle(Circle {
                center: p(rng),
                radius: match rng.gen_range(0..4) {
                    0 => u32::MAX,
                    1 => 0,
                    2 => COORD_LIMIT as u32,
                    _ => rng.gen_range(0..(64 << bits)),
                },
                color: rgb(rng),
                fill: rng.gen(),
            }),
            3 => {
                let mut points = heapless::Vec::new();
                for _ in 0..rng.gen_range(0..=protocol::frame::MAX_POLYGON) {
                    let _ = points.push(p(rng));
                }
                RasterCmd::Polygon(Polygon {
                    points,
                    rule: if rng.gen() {
                        FillRule::EvenOdd
                    } else {
                        FillRule::NonZero
                    },
                    color: rgb(rng),
                })
            }
            4 => {
                let mut points = heapless::Vec::new();
                for _ in 0..rng.gen_range(0..=4) {
                    let _ = points.push(p(rng));
                }
                RasterCmd::Bezier(Bezier {
                    points,
                    color: rgb(rng),
                    tolerance: match rng.gen_range(0..3) {
                        0 => 0,
                        1 => u32::MAX,
                        _ => rng.gen_range(1..1000),
                    },
                })
            }
            5 => {
                let points = core::array::from_fn(|_| p(rng));
                RasterCmd::Patch(BezierPatch {
                    points,
                    steps: if rng.gen_ratio(1, 8) {
                        rng.gen()
                    } else {
                        rng.gen_range(0..6)
                    },
                    color: rgb(rng),
                })
            }
            _ => RasterCmd::Fill(SeedFill {
                seed: Pixel {
                    x: rng.gen_range(0..=side as u16 + 2),
                    y: rng.gen_range(0..=side as u16 + 2),
                },
                color: rgb(rng),
                connectivity: if rng.gen() {
                    Connectivity::Four
                } else {
                    Connectivity::Eight
                },
            }),
        };
        if block.draw(&cmd).is_err() {
            r.counts.rejected += 1;
        }
    }
}

// ---------------------------------------------------------------------------------------
// Ray tracer
// ---------------------------------------------------------------------------------------

use sim_target::rt::{
    Camera, DiffuseModel, Filter as TexFilter, Light, Mapping, Material, Object, Reflection, Shape,
    Specular, SpecularModel, Spot, Term, Texture, TextureKind,
};

const SHAPES: [Shape; 7] = [
    Shape::Sphere,
    Shape::Plane,
    Shape::Disk,
    Shape::Square,
    Shape::Cylinder,
    Shape::Cone,
    Shape::Cube,
];

/// Rendered side of an rt case.
const RT_SIDE: u32 = 8;

/// log-uniform in [10^lo, 10^hi]
fn log_uniform(rng: &mut SmallRng, lo: f64, hi: f64) -> f64 {
    10f64.powf(rng.gen_range(lo..=hi))
}

fn matte() -> Material {
    Material {
        name: "matte".into(),
        ambient: None,
        diffuse: Term {
            k: 1.0,
            color: [1.0, 1.0, 1.0],
        },
        diffuse_model: DiffuseModel::Lambert,
        specular: None,
        reflection: Reflection::None,
        texture: None,
    }
}

fn random_material(rng: &mut SmallRng) -> Material {
    let mut m = matte();
    m.ambient = rng.gen::<bool>().then(|| Term {
        k: rng.gen_range(0.0..=1.0),
        color: [rng.gen(), rng.gen(), rng.gen()],
    });
    m.diffuse.k = rng.gen_range(0.0..=1.0);
    if rng.gen() {
        m.diffuse_model = DiffuseModel::OrenNayar {
            sigma2: rng.gen_range(0.0..=1.0),
        };
    }
    if rng.gen() {
        m.specular = Some(Specular {
            k: rng.gen_range(0.0..=1.0),
            color: [1.0, 1.0, 1.0],
            model: if rng.gen() {
                SpecularModel::BlinnPhong
            } else {
                SpecularModel::TorranceSparrow {
                    eta: rng.gen_range(1.0..3.0),
                    k: rng.gen_range(0.0..4.0),
                }
            },
            exponent: if rng.gen() {
                rng.gen_range(0..=1023)
            } else {
                rng.gen_range(0..64)
            },
        });
    }
    m.reflection = match rng.gen_range(0..4) {
        0 => Reflection::None,
        1 => Reflection::Constant(rng.gen_range(0.0..=1.0)),
        2 => Reflection::Fresnel {
            eta: rng.gen_range(0.1..4.0),
            k: rng.gen_range(0.0..4.0),
        },
        _ => Reflection::Glass {
            eta: rng.gen_range(1.0..2.5),
        },
    };
    if rng.gen_ratio(1, 3) {
        m.texture = Some(Texture {
            kind: match rng.gen_range(0..5) {
                0 => TextureKind::Xor,
                1 => TextureKind::Checkerboard {
                    cell: rng.gen_range(1..64),
                },
                2 => TextureKind::RgbDots,
                3 => TextureKind::Marble { seed: rng.gen() },
                _ => TextureKind::Wood { seed: rng.gen() },
            },
            mapping: [Mapping::Planar, Mapping::Cylindrical, Mapping::Spherical]
                [rng.gen_range(0..3)],
            scale: [log_uniform(rng, -3.0, 3.0), log_uniform(rng, -3.0, 3.0)],
            offset: [rng.gen_range(-1e3..1e3), rng.gen_range(-1e3..1e3)],
            color2: [rng.gen(), rng.gen(), rng.gen()],
            filter: if rng.gen() {
                TexFilter::Nearest
            } else {
                TexFilter::Bilinear
            },
        });
    }
    m
}

fn base_scene(camera: Camera) -> Scene {
    Scene {
        width: RT_SIDE,
        height: RT_SIDE,
        depth: 1,
        bias: 0.001,
        max_distance: 1e6,
        background: [0.0; 3],
        spp: 1,
        camera,
        ambient: [0.0; 3],
        lights: Vec::new(),
        materials: vec![matte()],
        objects: Vec::new(),
        shadows: true,
    }
}

fn unit_dir(rng: &mut SmallRng) -> [f64; 3] {
    loop {
        let v: [f64; 3] = [
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        ];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.1 && n <= 1.0 {
            return [v[0] / n, v[1] / n, v[2] / n];
        }
    }
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn mul(a: [f64; 3], k: f64) -> [f64; 3] {
    [a[0] * k, a[1] * k, a[2] * k]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: [f64; 3]) -> [f64; 3] {
    mul(a, 1.0 / dot(a, a).sqrt())
}
fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Kinds of rt case.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RtKind {
    /// One convex or flat object and one light: no lit point can be in shadow.
    Acne,
    /// A square lying (almost) on a plane, lit from above: coincident within CORE_BIAS/4.
    Coincident,
    /// The camera in or just above a plane/face, rays parallel to it.
    Grazing,
    /// Everything random: shapes, huge and tiny scales, materials, spot lights, depth.
    Wild,
}

fn rt_case(rng: &mut SmallRng) -> CaseResult {
    let mut r = CaseResult::default();
    let kind = [
        RtKind::Acne,
        RtKind::Coincident,
        RtKind::Grazing,
        RtKind::Wild,
    ][rng.gen_range(0..4)];
    let scene = match kind {
        RtKind::Acne => acne_scene(rng),
        RtKind::Coincident => coincident_scene(rng),
        RtKind::Grazing => grazing_scene(rng),
        RtKind::Wild => wild_scene(rng),
    };
    let fmt = rng.gen_range(0..Numeric::ALL.len());
    let opts = RenderOptions {
        aovs: true,
        ..RenderOptions::default()
    };
    let numeric = Numeric::ALL[fmt];
    // the same render with the plan's culling off: must match bit for bit (its probe
    // counts are dropped, the culled render's are kept)
    let unculled = render_probed(
        &scene,
        &RenderOptions {
            cull: false,
            ..opts
        },
        numeric,
    );
    let _ = probe::take();
    let frame = render_probed(&scene, &opts, numeric);
    let seen = probe::take();
    if let (Ok(a), Ok(b)) = (&frame, &unculled) {
        let bits = |v: &Option<Vec<f32>>| -> Vec<u32> {
            v.iter().flatten().map(|x| x.to_bits()).collect()
        };
        if a.rgb8 != b.rgb8
            || bits(&a.depth) != bits(&b.depth)
            || bits(&a.normal) != bits(&b.normal)
        {
            r.counts.cull_mismatches = 1;
            r.failure = Some(format!(
                "{kind:?} scene in {}: culling changed the render; scene {scene:?}",
                numeric_name(numeric)
            ));
            return r;
        }
    }
    let frame = match frame {
        Ok(f) => f,
        Err(_) => {
            r.counts.rejected += 1;
            return r;
        }
    };
    let mut nonfinite = seen.nans;
    let mut wraps = seen.wraps;
    let (depth, normal) = match (&frame.depth, &frame.normal) {
        (Some(d), Some(n)) => (d, n),
        _ => {
            r.failure = Some("render returned no AOVs".into());
            r.counts.nonfinite += 1;
            return r;
        }
    };
    for (k, &t) in depth.iter().enumerate() {
        let n = &normal[3 * k..3 * k + 3];
        let hit = n.iter().any(|v| *v != 0.0);
        if t.is_nan() || (hit && !t.is_finite()) || n.iter().any(|v| !v.is_finite()) {
            nonfinite += 1;
        }
        if t < 0.0 {
            // A distance below zero: a sign flipped somewhere on the way to the pixel.
            wraps += 1;
        }
    }
    let fits = range_demand(&scene) <= format_max(numeric);
    if fits {
        r.counts.nonfinite = nonfinite;
    } else {
        r.counts.out_of_range = 1;
        r.counts.nonfinite_out_of_range = nonfinite;
    }
    r.counts.wraps = wraps;
    r.counts.saturations = seen.saturations;
    r.counts.overflow_nans = seen.overflow_nans;
    if matches!(kind, RtKind::Acne | RtKind::Coincident) {
        if let Ok(reference) = rt::render(
            &scene,
            &RenderOptions {
                numeric: Numeric::F64,
                ..opts
            },
        ) {
            let (acne, checked) = count_acne(&scene, &reference, &frame);
            if acne > 0 && list_acne_verbose() {
                eprintln!(
                    "acne in {kind:?} scene, {}: {scene:?}",
                    numeric_name(numeric)
                );
            }
            if fits {
                r.counts.acne = acne;
                r.counts.acne_checked = checked;
            } else {
                r.counts.acne_out_of_range = acne;
            }
        }
    }
    let f = &mut r.formats[fmt];
    f.renders = 1;
    f.saturations = r.counts.saturations;
    f.overflow_nans = r.counts.overflow_nans;
    f.out_of_range = r.counts.out_of_range;
    f.nonfinite_out_of_range = r.counts.nonfinite_out_of_range;
    f.nonfinite = r.counts.nonfinite;
    f.acne = r.counts.acne;
    f.acne_checked = r.counts.acne_checked;
    f.acne_out_of_range = r.counts.acne_out_of_range;
    if r.counts.nonfinite + r.counts.wraps > 0 {
        r.failure = Some(format!(
            "{kind:?} scene in {}: {} NaN/inf, {} wraps; scene {scene:?}",
            numeric_name(numeric),
            r.counts.nonfinite,
            r.counts.wraps
        ));
    }
    r
}

fn render_probed(scene: &Scene, opts: &RenderOptions, n: Numeric) -> Result<Frame, rt::RtError> {
    match n {
        Numeric::F64 => rt::render_instrumented::<Probe<f64>>(scene, opts),
        Numeric::F32 => rt::render_instrumented::<Probe<f32>>(scene, opts),
        Numeric::F16 => rt::render_instrumented::<Probe<half::f16>>(scene, opts),
        Numeric::Q16_16 => rt::render_instrumented::<Probe<Q16_16>>(scene, opts),
        Numeric::Q8_24 => rt::render_instrumented::<Probe<Q8_24>>(scene, opts),
        Numeric::Q24_8 => rt::render_instrumented::<Probe<Q24_8>>(scene, opts),
        Numeric::Q32_32 => rt::render_instrumented::<Probe<Q32_32>>(scene, opts),
    }
}

/// Largest finite magnitude of a format.
fn format_max(n: Numeric) -> f64 {
    match n {
        Numeric::F64 => f64::MAX,
        Numeric::F32 => f32::MAX as f64,
        Numeric::F16 => 65504.0,
        Numeric::Q16_16 => 32768.0,
        Numeric::Q8_24 => 128.0,
        Numeric::Q24_8 => 8_388_608.0,
        Numeric::Q32_32 => 2_147_483_648.0,
    }
}

/// The largest magnitude the kernel must represent for a scene: the quadratic
/// coefficients of every object (|d′|² = 1/s², |o′|² = (|eye − T| + |T|… )²/s²), distances
/// squared, light intensities. A format whose range is below this cannot hold the scene:
/// a fixed format saturates (counted), a float one overflows to ∞ and may produce NaN,
/// which `stress` reports apart from NaN in scenes that fit.
pub fn range_demand(scene: &Scene) -> f64 {
    // MAX_DISTANCE is not a demand: the kernel clips it to the format's largest value.
    let mut m: f64 = 1.0;
    let eye = scene.camera.position;
    let len = |v: [f64; 3]| dot(v, v).sqrt();
    let mut far = len(eye);
    for l in &scene.lights {
        far = far.max(len(l.position));
        m = m.max(l.color.iter().fold(0.0f64, |a, c| a.max(c.abs())));
    }
    for o in &scene.objects {
        far = far.max(len(o.translate));
        let smin = o.scale.iter().fold(f64::INFINITY, |a, s| a.min(*s));
        let smax = o.scale.iter().fold(0.0f64, |a, s| a.max(*s));
        // The unit ray direction becomes d/s in object space: 1/s must fit as well.
        let reach = (2.0 * far + smax).max(1.0) / smin;
        m = m.max(reach * reach).max(smax);
    }
    m.max(4.0 * far * far)
}

/// Light intensity that makes n·ωᵢ ≥ 0.25 saturate white at distance `d` (Lambert 1/π).
fn bright(d: f64) -> [f64; 3] {
    let i = 4.0 * std::f64::consts::PI * d * d;
    [i, i, i]
}

fn look_at(rng: &mut SmallRng, target: [f64; 3], dist: f64) -> Camera {
    let dir = unit_dir(rng);
    Camera {
        position: add(target, mul(dir, dist)),
        look_at: target,
        up: if dir[1].abs() > 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        },
        fov_y: rng.gen_range(5.0..120.0),
    }
}

fn acne_scene(rng: &mut SmallRng) -> Scene {
    let shape = [
        Shape::Sphere,
        Shape::Cube,
        Shape::Plane,
        Shape::Disk,
        Shape::Square,
    ][rng.gen_range(0..5)];
    let s = if rng.gen_ratio(1, 4) {
        log_uniform(rng, -4.0, 4.0)
    } else {
        log_uniform(rng, -1.0, 1.5)
    };
    let centre = [
        rng.gen_range(-10.0..10.0) * s,
        rng.gen_range(-10.0..10.0) * s,
        rng.gen_range(-10.0..10.0) * s,
    ];
    let dist = s * rng.gen_range(2.0..8.0);
    let mut scene = base_scene(look_at(rng, centre, dist));
    let flat = matches!(shape, Shape::Plane | Shape::Disk | Shape::Square);
    if flat {
        // Look from above so that the lit side is seen.
        let mut p = scene.camera.position;
        p[1] = centre[1] + (p[1] - centre[1]).abs().max(0.2 * s);
        scene.camera.position = p;
        scene.camera.up = [1.0, 0.0, 0.0];
    }
    scene.objects.push(Object {
        shape,
        translate: centre,
        scale: [s, s, s],
        rotate: if rng.gen() {
            [
                rng.gen_range(0.0..360.0),
                rng.gen_range(0.0..360.0),
                rng.gen_range(0.0..360.0),
            ]
        } else {
            [0.0; 3]
        },
        material: 0,
    });
    // The light on the camera's side, sometimes grazing (almost in the tangent plane).
    let mut ld = unit_dir(rng);
    let to_cam = norm(add(scene.camera.position, mul(centre, -1.0)));
    if dot(ld, to_cam) < 0.0 {
        ld = mul(ld, -1.0);
    }
    if flat {
        ld[1] = if rng.gen_ratio(1, 3) {
            0.02
        } else {
            ld[1].abs().max(0.05)
        };
        ld = norm(ld);
    }
    let dl = s * rng.gen_range(2.0..20.0);
    scene.lights.push(Light {
        position: add(centre, mul(ld, dl)),
        color: bright(dl * 2.0),
        spot: None,
    });
    scene
}

fn coincident_scene(rng: &mut SmallRng) -> Scene {
    let s = log_uniform(rng, -1.0, 2.0);
    let delta = [0.0, 1e-9, 1e-6, 0.00025][rng.gen_range(0..4)];
    let mut scene = base_scene(Camera {
        position: [
            rng.gen_range(-1.0..1.0) * s,
            s * rng.gen_range(0.3..3.0),
            s * rng.gen_range(1.0..4.0),
        ],
        look_at: [0.0, 0.0, 0.0],
        up: [0.0, 1.0, 0.0],
        fov_y: rng.gen_range(20.0..90.0),
    });
    scene.objects.push(Object {
        shape: Shape::Plane,
        translate: [0.0, 0.0, 0.0],
        scale: [s, s, s],
        rotate: [0.0; 3],
        material: 0,
    });
    scene.objects.push(Object {
        shape: if rng.gen() {
            Shape::Square
        } else {
            Shape::Disk
        },
        translate: [0.0, delta, 0.0],
        scale: [s, s, s],
        rotate: [0.0; 3],
        material: 0,
    });
    let l = [
        rng.gen_range(-1.0..1.0) * s,
        s * rng.gen_range(0.5..4.0),
        rng.gen_range(-1.0..1.0) * s,
    ];
    let d = dot(l, l).sqrt();
    scene.lights.push(Light {
        position: l,
        color: bright(d * 2.0),
        spot: None,
    });
    scene
}

fn grazing_scene(rng: &mut SmallRng) -> Scene {
    let s = log_uniform(rng, -3.0, 3.0);
    let h = [0.0, 1e-9, 1e-6, 1e-3, -1e-6][rng.gen_range(0..5)] * s;
    let shape = [
        Shape::Plane,
        Shape::Square,
        Shape::Disk,
        Shape::Cube,
        Shape::Cylinder,
        Shape::Sphere,
    ][rng.gen_range(0..6)];
    // For a cube or cylinder the camera sits on the level of a face/cap (y = s).
    let level = if matches!(shape, Shape::Cube | Shape::Cylinder | Shape::Sphere) {
        s
    } else {
        0.0
    };
    let cam = Camera {
        position: [0.0, level + h, s * rng.gen_range(1.5..10.0)],
        look_at: [rng.gen_range(-0.5..0.5) * s, level + h, 0.0],
        up: [0.0, 1.0, 0.0],
        fov_y: rng.gen_range(1.0..170.0),
    };
    let mut scene = base_scene(cam);
    scene.materials.push(random_material(rng));
    scene.objects.push(Object {
        shape,
        translate: [0.0; 3],
        scale: [s, s, s],
        rotate: [0.0; 3],
        material: rng.gen_range(0..2),
    });
    let ld = unit_dir(rng);
    scene.lights.push(Light {
        position: mul(ld, s * rng.gen_range(1.1..10.0)),
        color: bright(s * 10.0),
        spot: None,
    });
    scene.depth = rng.gen_range(1..=3);
    scene
}

fn wild_scene(rng: &mut SmallRng) -> Scene {
    let world = log_uniform(rng, -6.0, 6.0);
    let dist = world * rng.gen_range(1.0..10.0);
    let cam = look_at(rng, [0.0; 3], dist);
    let mut scene = base_scene(cam);
    scene.bias = [0.001, 0.0, 1e-6, 0.1][rng.gen_range(0..4)];
    scene.max_distance = [1e6, 1e3, 1e12, 10.0][rng.gen_range(0..4)];
    scene.depth = rng.gen_range(1..=4);
    scene.ambient = [rng.gen(), rng.gen(), rng.gen()];
    scene.background = [rng.gen(), rng.gen(), rng.gen()];
    scene.materials = (0..rng.gen_range(1..=3))
        .map(|_| random_material(rng))
        .collect();
    for _ in 0..rng.gen_range(1..=8) {
        let scale = |rng: &mut SmallRng| {
            if rng.gen_ratio(1, 3) {
                log_uniform(rng, -6.0, 6.0)
            } else {
                world * log_uniform(rng, -1.0, 0.5)
            }
        };
        scene.objects.push(Object {
            shape: SHAPES[rng.gen_range(0..SHAPES.len())],
            translate: mul(unit_dir(rng), world * rng.gen_range(0.0..3.0)),
            scale: [scale(rng), scale(rng), scale(rng)],
            rotate: if rng.gen() {
                [
                    rng.gen_range(-720.0..720.0),
                    rng.gen_range(-720.0..720.0),
                    rng.gen_range(-720.0..720.0),
                ]
            } else {
                [0.0; 3]
            },
            material: rng.gen_range(0..scene.materials.len()),
        });
    }
    for _ in 0..rng.gen_range(0..=2) {
        let pos = mul(unit_dir(rng), world * rng.gen_range(0.5..5.0));
        let spot = rng.gen::<bool>().then(|| {
            let outer = rng.gen_range(-1.0..1.0);
            Spot {
                direction: mul(unit_dir(rng), log_uniform(rng, -3.0, 3.0)),
                cos_outer: outer,
                cos_inner: if rng.gen_ratio(1, 4) {
                    outer
                } else {
                    rng.gen_range(outer..=1.0)
                },
            }
        });
        scene.lights.push(Light {
            position: pos,
            color: mul(
                [rng.gen(), rng.gen(), rng.gen()],
                log_uniform(rng, -3.0, 8.0),
            ),
            spot,
        });
    }
    scene
}

/// The primary ray direction of pixel (i, j) as the camera of SPEC-RT defines it.
fn primary_dir(c: &Camera, w: u32, h: u32, i: u32, j: u32) -> [f64; 3] {
    let wv = norm(add(c.position, mul(c.look_at, -1.0)));
    let u = norm(cross3(c.up, wv));
    let v = cross3(wv, u);
    let s = (c.fov_y.to_radians() / 2.0).tan();
    let a = w as f64 / h as f64;
    let x = (2.0 * (i as f64 + 0.5) / w as f64 - 1.0) * s * a;
    let y = (1.0 - 2.0 * (j as f64 + 0.5) / h as f64) * s;
    norm(add(add(mul(u, x), mul(v, y)), mul(wv, -1.0)))
}

/// Acne: a pixel the f64 reference hits on a face turned well towards the light (n·ωᵢ ≥
/// 0.3, so the light alone saturates it white), which the tested format hits on the same
/// face (normals within 25°) and renders black. In these scenes no lit point *seen from
/// outside* can be shadowed (one convex or flat object; or a square on a plane within
/// CORE_BIAS/4 with the light above), so black can only be a false self-shadow.
///
/// Pixels that show the inside of a closed object (sphere or cube) are not checked: valid
/// hits start at t = CORE_BIAS (SPEC-RT), so an eye nearer than CORE_BIAS to the object
/// sees its near face clipped away and the far face from inside, where the near face
/// rightly shadows it (seed 1, case 551791: a cube of half-size 1.15·10⁻³ seen from
/// 2.4·10⁻³, 22 black pixels in f64). The normal AOV faces the eye, so such a hit is the one
/// whose normal points towards the object's centre.
fn count_acne(scene: &Scene, reference: &Frame, test: &Frame) -> (u64, u64) {
    let (Some(rd), Some(rn), Some(tn)) = (&reference.depth, &reference.normal, &test.normal) else {
        return (0, 0);
    };
    let Some(light) = scene.lights.first() else {
        return (0, 0);
    };
    let (mut acne, mut checked) = (0, 0);
    for j in 0..reference.height {
        for i in 0..reference.width {
            let k = (j * reference.width + i) as usize;
            let t = rd[k] as f64;
            if !t.is_finite() {
                continue;
            }
            let n = [rn[3 * k] as f64, rn[3 * k + 1] as f64, rn[3 * k + 2] as f64];
            let d = primary_dir(&scene.camera, reference.width, reference.height, i, j);
            let p = add(scene.camera.position, mul(d, t));
            let wi = norm(add(light.position, mul(p, -1.0)));
            if dot(n, wi) < 0.3 || seen_from_inside(scene, p, n) {
                continue;
            }
            let m = [tn[3 * k] as f64, tn[3 * k + 1] as f64, tn[3 * k + 2] as f64];
            if dot(n, m) < 0.9 {
                continue;
            }
            checked += 1;
            if test.rgb8[3 * k..3 * k + 3].iter().all(|&c| c == 0) {
                if list_acne_verbose() {
                    eprintln!(
                        "  pixel ({i}, {j}): t {t:e} p {p:?} n {n:?} n·wi {:.4} dist {:e} ref rgb {:?}",
                        dot(n, wi),
                        dot(add(light.position, mul(p, -1.0)), add(light.position, mul(p, -1.0))).sqrt(),
                        &reference.rgb8[3 * k..3 * k + 3]
                    );
                }
                acne += 1;
            }
        }
    }
    (acne, checked)
}

/// Whether the hit at `p` with eye-facing normal `n` is on the inside of a scene's only
/// object, a closed convex one (its centre is inside, so the outward normal points away
/// from it).
fn seen_from_inside(scene: &Scene, p: [f64; 3], n: [f64; 3]) -> bool {
    match scene.objects.as_slice() {
        [o] if matches!(o.shape, Shape::Sphere | Shape::Cube) => {
            dot(n, add(p, mul(o.translate, -1.0))) < 0.0
        }
        _ => false,
    }
}

// ---------------------------------------------------------------------------------------
// Parsers
// ---------------------------------------------------------------------------------------

const SCENES: [&str; 5] = [
    include_str!("../../examples/reference.toml"),
    include_str!("../../examples/rt/brdf.toml"),
    include_str!("../../examples/rt/fresnel.toml"),
    include_str!("../../examples/rt/shapes.toml"),
    include_str!("../../examples/rt/textures.toml"),
];

const RASTERS: [&str; 3] = [
    include_str!("../../examples/raster/aa.toml"),
    include_str!("../../examples/raster/fitkit.toml"),
    include_str!("../../examples/raster/gallery.toml"),
];

/// Spellings of a non-finite number that TOML (or the float parser behind it) accepts.
const NON_FINITE: [&str; 7] = ["nan", "+nan", "-nan", "inf", "+inf", "-inf", "1e999"];

/// Byte ranges of number literals with a fraction or exponent (float fields) in `text`.
fn float_literals(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let mut in_comment = false;
    while i < b.len() {
        let c = b[i];
        if c == b'#' {
            in_comment = true;
        }
        if c == b'\n' {
            in_comment = false;
        }
        if c == b'"' && !in_comment {
            // skip strings
            i += 1;
            while i < b.len() && b[i] != b'"' && b[i] != b'\n' {
                i += 1;
            }
            i += 1;
            continue;
        }
        let starts = (c.is_ascii_digit() || c == b'-' || c == b'+')
            && (i == 0
                || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.'));
        if !in_comment && starts {
            let s = i;
            i += 1;
            while i < b.len()
                && (b[i].is_ascii_digit()
                    || matches!(b[i], b'.' | b'e' | b'E' | b'-' | b'+' | b'_'))
            {
                i += 1;
            }
            let lit = &text[s..i];
            if (lit.contains('.') || lit.contains(['e', 'E']))
                && lit.bytes().any(|d| d.is_ascii_digit())
            {
                out.push((s, i));
            }
            continue;
        }
        i += 1;
    }
    out
}

fn parse_case(rng: &mut SmallRng) -> CaseResult {
    let mut r = CaseResult::default();
    let scene_file = rng.gen();
    let base = if scene_file {
        SCENES[rng.gen_range(0..SCENES.len())]
    } else {
        RASTERS[rng.gen_range(0..RASTERS.len())]
    };
    let mut text = base.to_string();
    let mut injected = None;
    match rng.gen_range(0..4) {
        0 | 1 => {
            let lits = float_literals(&text);
            if !lits.is_empty() {
                let (s, e) = lits[rng.gen_range(0..lits.len())];
                let v = NON_FINITE[rng.gen_range(0..NON_FINITE.len())];
                injected = Some(format!("{} -> {v} at byte {s}", &text[s..e]));
                text.replace_range(s..e, v);
            }
        }
        2 => {
            // finite extremes: must not panic, may be refused
            let lits = float_literals(&text);
            for _ in 0..rng.gen_range(1..4) {
                if let Some(&(s, e)) = lits.get(rng.gen_range(0..lits.len().max(1))) {
                    let v = [
                        "1e308", "-1e308", "5e-324", "0.0", "-0.0", "1e38", "65505.0", "32768.0",
                    ][rng.gen_range(0..8)];
                    if e <= text.len() && text.is_char_boundary(s) && text.is_char_boundary(e) {
                        text.replace_range(s..e, v);
                    }
                    break;
                }
            }
        }
        _ => {
            // random byte damage
            let mut bytes = text.into_bytes();
            for _ in 0..rng.gen_range(1..6) {
                let k = rng.gen_range(0..bytes.len().max(1));
                match rng.gen_range(0..3) {
                    0 if k < bytes.len() => bytes[k] = rng.gen_range(0x20..0x7f),
                    1 if k < bytes.len() => {
                        bytes.remove(k);
                    }
                    _ => bytes.insert(k.min(bytes.len()), b"[]{}=\".,\n0e-#"[rng.gen_range(0..13)]),
                }
            }
            text = String::from_utf8_lossy(&bytes).into_owned();
        }
    }
    let ok = if scene_file {
        match rt::scene_file::parse(&text, "stress.toml") {
            Ok(scene) => {
                // What parses must also render (tiny, f32) without panicking.
                let opts = RenderOptions {
                    size: Some((4, 4)),
                    spp: Some(1),
                    ..RenderOptions::default()
                };
                if rng.gen_ratio(1, 4) && rt::render(&scene, &opts).is_err() {
                    r.counts.rejected += 1;
                }
                true
            }
            Err(_) => false,
        }
    } else {
        match crate::raster_file::parse(&text, "stress.toml") {
            Ok(job) => {
                if rng.gen_ratio(1, 4) {
                    let w = u32::from(job.setup.width).min(64);
                    let h = u32::from(job.setup.height).min(64);
                    if let Ok(mut block) = Raster::new(w, h, &job.setup) {
                        for c in &job.cmds {
                            if block.draw(c).is_err() {
                                r.counts.rejected += 1;
                            }
                        }
                    }
                }
                true
            }
            Err(_) => false,
        }
    };
    if !ok {
        r.counts.rejected += 1;
    } else if let Some(what) = injected {
        r.counts.accepted_nonfinite += 1;
        r.failure = Some(format!(
            "{} accepted a non-finite number ({what})",
            if scene_file {
                "scene file"
            } else {
                "raster file"
            }
        ));
    }
    r
}

pub mod probe {
    //! A number format that watches the one it wraps: every arithmetic result is checked
    //! against the exact result (integer arithmetic on the raw bits for fixed point), so a
    //! render through [`Probe`] counts saturations, NaN produced from non-NaN operands and
    //! results that are neither exact nor the saturated value (a wrap-around), while giving
    //! the kernel bit for bit the values the bare format would. Nothing in the kernel changes.

    use core::cell::Cell;
    use core::ops::{Add, Div, Mul, Neg, Sub};

    use sim_target::num::{Scalar, Q16_16, Q24_8, Q32_32, Q8_24};

    /// What the probes saw on this thread.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
    pub struct Seen {
        /// Results clipped to the format's range (fixed point), or finite operands that
        /// overflowed to ±∞ (floating point), division by zero included.
        pub saturations: u64,
        /// NaN results from finite operands (0/0, a NaN from nothing): always a bug.
        pub nans: u64,
        /// NaN results from an infinite operand (∞ − ∞, 0·∞): the aftermath of an overflow
        /// already counted as a saturation; reported, not failed (see docs/stress.md).
        pub overflow_nans: u64,
        /// Results that are neither the exact value nor the clipped one: a wrap-around.
        pub wraps: u64,
    }

    thread_local! {
        static SEEN: Cell<Seen> = const { Cell::new(Seen { saturations: 0, nans: 0, overflow_nans: 0, wraps: 0 }) };
    }

    /// Returns and clears this thread's counts. The stress runner renders each case wholly on
    /// one thread, so the counts of one case are not mixed with another's.
    pub fn take() -> Seen {
        SEEN.with(|s| s.replace(Seen::default()))
    }

    #[inline]
    fn note(f: impl FnOnce(&mut Seen)) {
        SEEN.with(|s| {
            let mut v = s.get();
            let before = v;
            f(&mut v);
            s.set(v);
            if v.nans > before.nans && trap() {
                // Debugging aid (FPGFX_STRESS_TRAP=1 with --case K): stop at the first NaN
                // and say where it came from.
                panic!(
                    "first NaN produced at\n{}",
                    std::backtrace::Backtrace::force_capture()
                );
            }
        });
    }

    fn trap() -> bool {
        static TRAP: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
        *TRAP.get_or_init(|| std::env::var_os("FPGFX_STRESS_TRAP").is_some())
    }

    /// Binary operations the probe checks.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Op {
        /// a + b
        Add,
        /// a − b
        Sub,
        /// a · b
        Mul,
        /// a / b
        Div,
    }

    /// How a format's exact result is known.
    pub trait Exact: Scalar {
        /// Checks `r = a op b` and records the outcome.
        fn check(op: Op, a: Self, b: Self, r: Self);
        /// Checks `r = −a`.
        fn check_neg(a: Self, r: Self);
        /// Checks `r = from_f64(x)`.
        fn check_from(x: f64, r: Self);
        /// Checks `r = Σ aᵢ·bᵢ` computed with one rounding (`mul_rn`, `dot2`, `dot3`).
        fn check_sum(pairs: &[(Self, Self)], r: Self);
    }

    macro_rules! exact_float {
        ($t:ty) => {
            impl Exact for $t {
                #[inline]
                fn check(_op: Op, a: Self, b: Self, r: Self) {
                    let (a, b, r) = (a.to_f64(), b.to_f64(), r.to_f64());
                    if r.is_nan() && a.is_finite() && b.is_finite() {
                        note(|s| s.nans += 1);
                    } else if r.is_nan() && !a.is_nan() && !b.is_nan() {
                        note(|s| s.overflow_nans += 1);
                    } else if r.is_infinite() && a.is_finite() && b.is_finite() {
                        note(|s| s.saturations += 1);
                    }
                }
                #[inline]
                fn check_neg(_a: Self, _r: Self) {}
                #[inline]
                fn check_sum(pairs: &[(Self, Self)], r: Self) {
                    let finite = pairs
                        .iter()
                        .all(|(a, b)| a.to_f64().is_finite() && b.to_f64().is_finite());
                    // a product beyond the range overflows to ∞ first: a NaN after that
                    // is an overflow NaN, as with the separate operations
                    let max = <$t as Scalar>::max_value().to_f64();
                    let overflow = pairs
                        .iter()
                        .any(|(a, b)| (a.to_f64() * b.to_f64()).abs() > max);
                    let r = r.to_f64();
                    if r.is_nan() && finite && !overflow {
                        note(|s| s.nans += 1);
                    } else if r.is_nan() && finite {
                        note(|s| s.overflow_nans += 1);
                    } else if r.is_infinite() && finite {
                        note(|s| s.saturations += 1);
                    }
                }
                #[inline]
                fn check_from(x: f64, r: Self) {
                    if r.to_f64().is_infinite() && x.is_finite() {
                        note(|s| s.saturations += 1);
                    }
                }
            }
        };
    }

    exact_float!(f64);
    exact_float!(f32);
    exact_float!(half::f16);

    macro_rules! exact_fixed {
        ($t:ty, $bits:ty, $frac:literal) => {
            impl Exact for $t {
                #[inline]
                fn check(op: Op, a: Self, b: Self, r: Self) {
                    let (x, y) = (a.0.to_bits() as i128, b.0.to_bits() as i128);
                    let exact = match op {
                        Op::Add => x + y,
                        Op::Sub => x - y,
                        Op::Mul => (x * y) >> $frac,
                        Op::Div => {
                            if y == 0 {
                                // The divider's defined answer: the signed maximum.
                                let want = if x >= 0 { <$bits>::MAX } else { <$bits>::MIN };
                                note(|s| {
                                    s.saturations += 1;
                                    if r.0.to_bits() != want {
                                        s.wraps += 1;
                                    }
                                });
                                return;
                            }
                            (x << $frac) / y
                        }
                    };
                    settle(
                        exact,
                        r.0.to_bits() as i128,
                        <$bits>::MIN as i128,
                        <$bits>::MAX as i128,
                    );
                }
                #[inline]
                fn check_sum(pairs: &[(Self, Self)], r: Self) {
                    // the exact sum of the double-width products, then the one rounding
                    // (either direction accepted: the mode is the format's business)
                    let wide = pairs.iter().fold(0i128, |acc, (a, b)| {
                        acc.saturating_add(
                            (a.0.to_bits() as i128).saturating_mul(b.0.to_bits() as i128),
                        )
                    });
                    let exact = wide >> $frac;
                    let (lo, hi) = (<$bits>::MIN as i128, <$bits>::MAX as i128);
                    let clipped = exact.clamp(lo, hi);
                    let got = r.0.to_bits() as i128;
                    if clipped != exact || (got - clipped).abs() > 1 {
                        note(|s| {
                            if clipped != exact {
                                s.saturations += 1;
                            }
                            if (got - clipped).abs() > 1 {
                                s.wraps += 1;
                            }
                        });
                    }
                }
                #[inline]
                fn check_neg(a: Self, r: Self) {
                    let x = a.0.to_bits() as i128;
                    settle(
                        -x,
                        r.0.to_bits() as i128,
                        <$bits>::MIN as i128,
                        <$bits>::MAX as i128,
                    );
                }
                #[inline]
                fn check_from(x: f64, r: Self) {
                    if x.is_nan() {
                        note(|s| s.nans += 1);
                        return;
                    }
                    let scaled = x * (1u64 << $frac) as f64;
                    // Round half away from zero, as the format documents; `as i128` saturates.
                    let exact = (scaled + 0.5f64.copysign(scaled)) as i128;
                    settle(
                        exact,
                        r.0.to_bits() as i128,
                        <$bits>::MIN as i128,
                        <$bits>::MAX as i128,
                    );
                }
            }
        };
    }

    /// Records whether `got` is `exact`, its clipped value (a saturation) or neither (a wrap).
    #[inline]
    fn settle(exact: i128, got: i128, lo: i128, hi: i128) {
        let clipped = exact.clamp(lo, hi);
        if clipped != exact || got != clipped {
            note(|s| {
                if clipped != exact {
                    s.saturations += 1;
                }
                if got != clipped {
                    s.wraps += 1;
                }
            });
        }
    }

    exact_fixed!(Q16_16, i32, 16);
    exact_fixed!(Q8_24, i32, 24);
    exact_fixed!(Q24_8, i32, 8);
    exact_fixed!(Q32_32, i64, 32);

    /// `S`, observed. Every method delegates to `S` (so results are identical) and then
    /// checks the result.
    #[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
    pub struct Probe<S>(pub S);

    macro_rules! bin {
        ($tr:ident, $m:ident, $op:expr) => {
            impl<S: Exact> $tr for Probe<S> {
                type Output = Self;
                #[inline]
                fn $m(self, o: Self) -> Self {
                    let r = $tr::$m(self.0, o.0);
                    S::check($op, self.0, o.0, r);
                    Probe(r)
                }
            }
        };
    }

    bin!(Add, add, Op::Add);
    bin!(Sub, sub, Op::Sub);
    bin!(Mul, mul, Op::Mul);
    bin!(Div, div, Op::Div);

    impl<S: Exact> Neg for Probe<S> {
        type Output = Self;
        #[inline]
        fn neg(self) -> Self {
            let r = -self.0;
            S::check_neg(self.0, r);
            Probe(r)
        }
    }

    impl<S: Exact> Scalar for Probe<S> {
        const NAME: &'static str = S::NAME;
        #[inline]
        fn from_f64(x: f64) -> Self {
            let r = S::from_f64(x);
            S::check_from(x, r);
            Probe(r)
        }
        #[inline]
        fn to_f64(self) -> f64 {
            self.0.to_f64()
        }
        #[inline]
        fn sqrt(self) -> Self {
            let r = self.0.sqrt();
            if r.to_f64().is_nan() && !self.0.to_f64().is_nan() {
                note(|s| s.nans += 1);
            }
            Probe(r)
        }
        #[inline]
        fn rsqrt(self) -> Self {
            let r = self.0.rsqrt();
            if self.0 <= S::zero() {
                // The documented answer for x ≤ 0 is the format's maximum: a clip.
                note(|s| s.saturations += 1);
            }
            Probe(r)
        }
        fn max_value() -> Self {
            Probe(S::max_value())
        }
        fn rounding() -> Option<(f64, f64)> {
            S::rounding()
        }
        #[inline]
        fn mul_rn(self, o: Self) -> Self {
            let r = self.0.mul_rn(o.0);
            S::check_sum(&[(self.0, o.0)], r);
            Probe(r)
        }
        #[inline]
        fn dot2(a: Self, b: Self, c: Self, d: Self) -> Self {
            let r = S::dot2(a.0, b.0, c.0, d.0);
            S::check_sum(&[(a.0, b.0), (c.0, d.0)], r);
            Probe(r)
        }
        #[inline]
        fn dot3(a: Self, b: Self, c: Self, d: Self, e: Self, f: Self) -> Self {
            let r = S::dot3(a.0, b.0, c.0, d.0, e.0, f.0);
            S::check_sum(&[(a.0, b.0), (c.0, d.0), (e.0, f.0)], r);
            Probe(r)
        }
        #[inline]
        fn floor(self) -> Self {
            Probe(self.0.floor())
        }
        #[inline]
        fn zero() -> Self {
            Probe(S::zero())
        }
        #[inline]
        fn one() -> Self {
            Probe(S::one())
        }
        #[inline]
        fn recip(self) -> Self {
            let r = self.0.recip();
            S::check(Op::Div, S::one(), self.0, r);
            Probe(r)
        }
        #[inline]
        fn abs(self) -> Self {
            let r = self.0.abs();
            if self.0 < S::zero() {
                S::check_neg(self.0, r);
            }
            Probe(r)
        }
        #[inline]
        fn min(self, other: Self) -> Self {
            Probe(self.0.min(other.0))
        }
        #[inline]
        fn max(self, other: Self) -> Self {
            Probe(self.0.max(other.0))
        }
        #[inline]
        fn clamp(self, lo: Self, hi: Self) -> Self {
            Probe(self.0.clamp(lo.0, hi.0))
        }
        #[inline]
        fn is_finite(self) -> bool {
            self.0.is_finite()
        }
        #[inline]
        fn fract(self) -> Self {
            Probe(self.0.fract())
        }
    }
}
