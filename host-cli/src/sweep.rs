//! `fpgfx bench`: run time and hardware cost against error, for every number format ×
//! approximation set of the ray tracer and every sub-pixel precision × AA pattern × sample
//! count of the rasterizer, with the Pareto front marked (docs/requirements.md §5.3).
//!
//! Host time cannot rank formats for an FPGA (on a CPU f64 costs what f32 costs, and fixed
//! point pays for saturation in software), so the front is computed on a documented
//! hardware cost model ([`rt_unit_cost`], [`raster_cost`]; docs/bench.md). Host time is
//! measured and reported alongside: the median of `repeats` runs, every point timed in the
//! same run, interleaved repeat by repeat so that a load change hits all points alike.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use protocol::names::Named;
use protocol::raster::{Aa, AaPattern, RasterSetup};
use sim_target::num::instrumented::{self, Counted, OpKind};
use sim_target::raster::Raster;
use sim_target::rt::{self, Kernel, Math, Numeric, RenderOptions, Scene};

/// Errors of a bench run. Every one names the file or point it is about.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BenchError {
    /// A scene or command file could not be read.
    #[error("cannot read {path}")]
    Read {
        /// The scene or command file, as given.
        path: String,
        /// The underlying error, reported as this one's `source()`.
        source: std::io::Error,
    },
    /// A scene file is invalid.
    #[error(transparent)]
    Scene(#[from] jobs::scene::SceneFileError),
    /// The ray tracer refused a scene at one of the swept configurations.
    #[error("cannot render {scene}")]
    Render {
        /// The scene file, as given.
        scene: String,
        /// The underlying error, reported as this one's `source()`.
        source: rt::RtError,
    },
    /// A raster command file is invalid or the model refused it.
    #[error("{file}: {message}")]
    Raster {
        /// The raster command file, as given.
        file: String,
        /// The parser's or the model's refusal, naming the line or command.
        message: String,
    },
    /// An output could not be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The output (CSV, Markdown or plot) that could not be written.
        path: String,
        /// The I/O, CSV or plot encoder's error, as text.
        message: String,
    },
}

/// What to sweep.
#[derive(Debug, Clone)]
pub struct BenchConfig {
    /// Ray-trace scene files (empty: the scenes built into the binary, [`builtin_scenes`]).
    pub scenes: Vec<PathBuf>,
    /// Raster command files (empty: the files built into the binary, [`builtin_raster`]).
    pub raster_files: Vec<PathBuf>,
    /// Small sizes and a reduced sweep (CI).
    pub quick: bool,
    /// Timed runs per point (the median is reported).
    pub repeats: usize,
}

/// The two sweeps, as progress events name them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    /// Every number format × approximation set of the ray tracer.
    Rt,
    /// Every sub-pixel precision × AA setting of the rasterizer.
    Raster,
}

impl Sweep {
    /// Short name, for a progress bar's label.
    pub fn name(self) -> &'static str {
        match self {
            Sweep::Rt => "rt",
            Sweep::Raster => "raster",
        }
    }
}

/// How far a run is, told to the caller of [`run_with_progress`] (the library prints
/// nothing; `fpgfx bench` draws a bar per sweep from these).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress {
    /// A sweep's timed runs begin: `runs` of them (repeats × points × inputs).
    Started {
        /// The sweep starting (ray tracer or raster).
        sweep: Sweep,
        /// How many timed runs follow.
        runs: u64,
    },
    /// One timed run finished.
    Ran {
        /// The sweep the run belongs to.
        sweep: Sweep,
    },
    /// The sweep's timed runs are done (its metrics follow without further events).
    Finished {
        /// The sweep that finished.
        sweep: Sweep,
    },
}

/// The ray-trace approximation sets swept.
pub const MATH_SETS: [(&str, Math); 4] = [
    ("exact", Math::EXACT),
    ("poly", Math::POLY),
    ("seed", Math::SEED),
    ("better", Math::BETTER),
];

/// The default configuration of the product: f32 with `Math::default()` (= `exact`).
pub const DEFAULT_RT: (Numeric, &str) = (Numeric::F32, "exact");
/// The raster file default: 8 sub-pixel bits, no AA.
pub const DEFAULT_RASTER: (u8, AaPattern, u8) = (8, AaPattern::None, 1);

/// One measured configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// "rt" or "raster".
    pub block: &'static str,
    /// Configuration label (format/set, or bits/pattern/samples).
    pub config: String,
    /// Hardware cost estimate (rt: LUT-equivalents per sample, raster: per pixel).
    pub cost: f64,
    /// Median host time over all scenes (ms, summed over the scenes).
    pub host_ms: f64,
    /// The same on the scalar kernel (`Kernel::Scalar`), for the formats whose default
    /// kernel traces packets ([`rt::PACKET_FORMATS`]): what the packets gain.
    pub scalar_ms: Option<f64>,
    /// Mean PSNR over the scenes (dB; capped at [`PSNR_CAP`] for identical images).
    pub psnr: f64,
    /// Worst channel error over the scenes (0–255).
    pub max_err: u8,
    /// RMSE of the depth AOV (rt; over pixels both hit), worst scene.
    pub depth_rmse: f64,
    /// Pixels differing in any channel, summed over the scenes.
    pub mismatched: u64,
    /// Raster: pixels written by one configuration and not by the reference, or back.
    pub coverage_mismatch: u64,
    /// Raster: mean |Δ| per channel / 255 — the AA area error.
    pub aa_area_err: f64,
    /// This point is the product's default configuration ([`DEFAULT_RT`] or
    /// [`DEFAULT_RASTER`]), marked in the Markdown table.
    pub is_default: bool,
    /// On the Pareto front (cost ↓, PSNR ↑).
    pub front: bool,
}

/// PSNR reported for bit-identical images.
pub const PSNR_CAP: f64 = 120.0;

/// Everything a bench run measured, what [`write()`] turns into CSV, Markdown and plots.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// One point per number format × approximation set of the ray tracer.
    pub rt: Vec<Point>,
    /// One point per sub-pixel precision × AA pattern × sample count of the rasterizer.
    pub raster: Vec<Point>,
    /// Scenes and files measured, with the size used.
    pub inputs: Vec<String>,
}

/// One input of a sweep: a scene or raster command file's text, with the name that
/// messages and the report give it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Workload {
    /// The file's name: its repository path for a built-in one, the path as given else.
    pub name: String,
    /// The file's text.
    pub text: String,
}

impl Workload {
    /// Reads a file given on the command line; the path as given is its name.
    pub fn read(path: &Path) -> Result<Workload, BenchError> {
        let name = path.display().to_string();
        match std::fs::read_to_string(path) {
            Ok(text) => Ok(Workload { name, text }),
            Err(source) => Err(BenchError::Read { path: name, source }),
        }
    }

    fn builtin(list: &[(&str, &str)], n: usize) -> Vec<Workload> {
        list[..n.min(list.len())]
            .iter()
            .map(|(name, text)| Workload {
                name: (*name).to_string(),
                text: (*text).to_string(),
            })
            .collect()
    }
}

/// The ray-trace scenes the binary carries (`include_str!` of the example files, named by
/// their repository paths), so that `fpgfx bench` runs from any directory; in sweep
/// order, `--quick` takes the first two.
pub const BUILTIN_SCENES: [(&str, &str); 5] = [
    (
        "examples/reference.toml",
        include_str!("../../examples/reference.toml"),
    ),
    (
        "examples/rt/shapes.toml",
        include_str!("../../examples/rt/shapes.toml"),
    ),
    (
        "examples/rt/textures.toml",
        include_str!("../../examples/rt/textures.toml"),
    ),
    (
        "examples/rt/brdf.toml",
        include_str!("../../examples/rt/brdf.toml"),
    ),
    (
        "examples/rt/fresnel.toml",
        include_str!("../../examples/rt/fresnel.toml"),
    ),
];

/// The raster command files the binary carries: `examples/raster/*.toml`, sorted by name
/// (a test holds this list to the directory); `--quick` takes the first two.
pub const BUILTIN_RASTER: [(&str, &str); 3] = [
    (
        "examples/raster/aa.toml",
        include_str!("../../examples/raster/aa.toml"),
    ),
    (
        "examples/raster/fitkit.toml",
        include_str!("../../examples/raster/fitkit.toml"),
    ),
    (
        "examples/raster/gallery.toml",
        include_str!("../../examples/raster/gallery.toml"),
    ),
];

/// The built-in ray-trace scenes a run sweeps ([`BUILTIN_SCENES`]; `quick`: the first two).
pub fn builtin_scenes(quick: bool) -> Vec<Workload> {
    Workload::builtin(&BUILTIN_SCENES, if quick { 2 } else { usize::MAX })
}

/// The built-in raster command files a run sweeps ([`BUILTIN_RASTER`]; `quick`: the first
/// two).
pub fn builtin_raster(quick: bool) -> Vec<Workload> {
    Workload::builtin(&BUILTIN_RASTER, if quick { 2 } else { usize::MAX })
}

/// The files given, read, or the built-in list when none was.
fn workloads(
    given: &[PathBuf],
    builtin: impl FnOnce() -> Vec<Workload>,
) -> Result<Vec<Workload>, BenchError> {
    if given.is_empty() {
        Ok(builtin())
    } else {
        given.iter().map(|p| Workload::read(p)).collect()
    }
}

// ---------------------------------------------------------------------------------------
// The hardware cost model

/// Operations per sample of one (scene, approximation set), from a counted render.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct OpMix {
    /// Per kind, in [`OpKind::ALL`] order: add/sub, mul, div, sqrt, rsqrt, atan core, acos
    /// core, floor.
    pub per_sample: [f64; 8],
}

/// Counts the operations of one frame, rendered in [`Counted`] f64 in a count scope of its
/// own (so a caller's counts are not disturbed). Culling is turned off: the board tests
/// every object with every ray, and the cost model prices the board's datapath.
pub fn op_mix(scene: &Scene, opts: &RenderOptions) -> Result<OpMix, rt::RtError> {
    let opts = RenderOptions {
        cull: false,
        ..*opts
    };
    let (f, counts) = instrumented::count(|| rt::render_instrumented::<Counted<f64>>(scene, &opts));
    let f = f?;
    let samples = f.width as f64 * f.height as f64 * opts.spp.unwrap_or(scene.spp).max(1) as f64;
    let mut per_sample = [0.0; 8];
    for (p, k) in per_sample.iter_mut().zip(OpKind::ALL) {
        *p = counts.ops.get(k) as f64 / samples;
    }
    Ok(OpMix { per_sample })
}

/// LUT-equivalent area of one fully pipelined operator of each kind in a format (a DSP48
/// slice counted as 100 LUTs), in the order of [`OpMix::per_sample`]. Rough figures for a
/// Kintex UltraScale+ (docs/bench.md gives the derivation); what matters for the front
/// is their ratio between formats, which follows the datapath width.
pub fn rt_unit_cost(n: Numeric) -> [f64; 8] {
    // CORDIC core: one stage of three w-bit adders per result bit, w = precision + 2.
    let cordic = |w: f64| 3.0 * w * w;
    match n {
        //                add    mul     div     sqrt    rsqrt   atan          acos               floor
        Numeric::F64 => [
            700.0,
            1100.0,
            3200.0,
            3000.0,
            3600.0,
            cordic(55.0),
            2.0 * cordic(55.0),
            60.0,
        ],
        Numeric::F32 => [
            350.0,
            330.0,
            800.0,
            700.0,
            900.0,
            cordic(26.0),
            2.0 * cordic(26.0),
            30.0,
        ],
        Numeric::F16 => [
            160.0,
            130.0,
            250.0,
            200.0,
            260.0,
            cordic(13.0),
            2.0 * cordic(13.0),
            15.0,
        ],
        Numeric::Q16_16 | Numeric::Q8_24 | Numeric::Q24_8 => [
            32.0,
            400.0,
            1100.0,
            600.0,
            800.0,
            cordic(34.0),
            2.0 * cordic(34.0),
            0.0,
        ],
        Numeric::Q32_32 => [
            64.0,
            1000.0,
            4200.0,
            2200.0,
            3000.0,
            cordic(66.0),
            2.0 * cordic(66.0),
            0.0,
        ],
    }
}

/// Cost of an op mix in a format: LUT-equivalents per sample.
pub fn rt_cost(mix: &OpMix, n: Numeric) -> f64 {
    mix.per_sample
        .iter()
        .zip(rt_unit_cost(n))
        .map(|(c, u)| c * u)
        .sum()
}

/// Samples a pattern really takes (grid patterns round to a square, as `raster::aa`).
pub fn effective_samples(p: AaPattern, samples: u8) -> u32 {
    match p {
        AaPattern::None => 1,
        // analytic coverage: one area evaluation per pixel, costed as 8 samples (three
        // edge distances, a clip and a table of segment areas; docs/bench.md)
        AaPattern::Coverage => 8,
        AaPattern::Poisson => samples.max(1) as u32,
        _ => {
            let m = ((samples.max(1) as f64).sqrt().round() as u32).max(1);
            m * m
        }
    }
}

/// Raster cost per pixel: three edge functions per sample, each a multiply-accumulate of
/// (12 + bits)-bit coordinates into a 2·(12 + bits) + 2-bit accumulator (LUTs).
pub fn raster_cost(bits: u8, p: AaPattern, samples: u8) -> f64 {
    let w = 12.0 + bits as f64;
    effective_samples(p, samples) as f64 * 3.0 * (2.0 * w + 2.0)
}

// ---------------------------------------------------------------------------------------
// Metrics

/// Max channel error, mismatched pixels, mean |Δ|/255 of two RGB888 images.
fn image_errors(a: &[u8], b: &[u8]) -> (u8, u64, f64) {
    let mut max = 0u8;
    let mut mism = 0u64;
    let mut sum = 0u64;
    for (p, q) in a.chunks_exact(3).zip(b.chunks_exact(3)) {
        let mut differs = false;
        for (x, y) in p.iter().zip(q) {
            let d = x.abs_diff(*y);
            max = max.max(d);
            sum += d as u64;
            differs |= d != 0;
        }
        mism += differs as u64;
    }
    let n = a.len().max(1) as f64;
    (max, mism, sum as f64 / n / 255.0)
}

fn psnr_capped(a: &[u8], b: &[u8]) -> f64 {
    let p = rt::psnr(a, b);
    if p.is_finite() {
        p.min(PSNR_CAP)
    } else {
        PSNR_CAP
    }
}

fn depth_rmse(a: &Option<Vec<f32>>, b: &Option<Vec<f32>>) -> f64 {
    let (Some(a), Some(b)) = (a, b) else {
        return 0.0;
    };
    let (mut s, mut n) = (0.0, 0usize);
    for (x, y) in a.iter().zip(b) {
        if x.is_finite() && y.is_finite() {
            s += (*x as f64 - *y as f64).powi(2);
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        (s / n as f64).sqrt()
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    match v.len() {
        0 => 0.0,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// Relative cost difference below which the model cannot rank two points: its unit
/// costs are estimates good to tens of percent, so a 0.1 % difference is noise.
pub const COST_RESOLUTION: f64 = 0.01;
/// PSNR difference (dB) below which two points count as equally good.
pub const PSNR_RESOLUTION: f64 = 0.01;

/// ε-Pareto front of (cost ↓, quality ↑): a point is on it when no other point is at most
/// as costly and at least as good, and better by more than the model's resolution in one
/// of the two ([`COST_RESOLUTION`] relative cost, [`PSNR_RESOLUTION`] dB).
pub fn pareto_front(pts: &[(f64, f64)]) -> Vec<bool> {
    pts.iter()
        .map(|&(c, q)| {
            !pts.iter().any(|&(c2, q2)| {
                c2 <= c && q2 >= q && (c2 < c * (1.0 - COST_RESOLUTION) || q2 > q + PSNR_RESOLUTION)
            })
        })
        .collect()
}

// ---------------------------------------------------------------------------------------
// The sweeps

struct RtScene {
    name: String,
    scene: Scene,
    size: (u32, u32),
    reference: rt::Frame,
}

/// Ray-trace sweep: every format × approximation set on every scene.
pub fn sweep_rt(
    cfg: &BenchConfig,
    inputs: &mut Vec<String>,
    progress: &mut dyn FnMut(Progress),
) -> Result<Vec<Point>, BenchError> {
    let files = workloads(&cfg.scenes, || builtin_scenes(cfg.quick))?;
    let size = if cfg.quick { (48, 27) } else { (160, 90) };
    let opts_with = |numeric, math, kernel| RenderOptions {
        numeric,
        math,
        aovs: true,
        size: Some(size),
        kernel,
        ..Default::default()
    };
    let opts = |numeric, math| opts_with(numeric, math, Kernel::Planned);
    let mut scenes = Vec::new();
    for Workload { name, text } in files {
        let scene = jobs::scene::parse(&text, &name)?;
        let reference = rt::render(&scene, &opts(Numeric::F64, Math::EXACT)).map_err(|source| {
            BenchError::Render {
                scene: name.clone(),
                source,
            }
        })?;
        inputs.push(format!("{name} at {}×{}", size.0, size.1));
        scenes.push(RtScene {
            name,
            scene,
            size,
            reference,
        });
    }
    let configs: Vec<(Numeric, &str, Math)> = Numeric::ALL
        .iter()
        .flat_map(|n| MATH_SETS.iter().map(move |(s, m)| (*n, *s, *m)))
        .collect();
    // op mixes per (scene, set): format-independent up to branches
    let mut mixes = vec![vec![OpMix::default(); MATH_SETS.len()]; scenes.len()];
    for (si, s) in scenes.iter().enumerate() {
        for (mi, (_, m)) in MATH_SETS.iter().enumerate() {
            mixes[si][mi] =
                op_mix(&s.scene, &opts(Numeric::F64, *m)).map_err(|source| BenchError::Render {
                    scene: s.name.clone(),
                    source,
                })?;
        }
    }
    let repeats = cfg.repeats.max(1);
    let sweep = Sweep::Rt;
    progress(Progress::Started {
        sweep,
        runs: (repeats * configs.len() * scenes.len()) as u64,
    });
    let mut times = vec![vec![Vec::new(); scenes.len()]; configs.len()];
    let mut scalar_times = vec![vec![Vec::new(); scenes.len()]; configs.len()];
    let mut frames: Vec<Vec<Option<rt::Frame>>> = vec![vec![None; scenes.len()]; configs.len()];
    for _ in 0..repeats {
        for (ci, (n, _, m)) in configs.iter().enumerate() {
            for (si, s) in scenes.iter().enumerate() {
                let t = Instant::now();
                let f =
                    rt::render(&s.scene, &opts(*n, *m)).map_err(|source| BenchError::Render {
                        scene: s.name.clone(),
                        source,
                    })?;
                times[ci][si].push(t.elapsed().as_secs_f64() * 1e3);
                frames[ci][si] = Some(f);
                if rt::PACKET_FORMATS.contains(n) {
                    let t = Instant::now();
                    rt::render(&s.scene, &opts_with(*n, *m, Kernel::Scalar)).map_err(|source| {
                        BenchError::Render {
                            scene: s.name.clone(),
                            source,
                        }
                    })?;
                    scalar_times[ci][si].push(t.elapsed().as_secs_f64() * 1e3);
                }
                progress(Progress::Ran { sweep });
            }
        }
    }
    progress(Progress::Finished { sweep });
    let mut points = Vec::new();
    for (ci, (n, set, _)) in configs.iter().enumerate() {
        let mi = MATH_SETS.iter().position(|(s, _)| s == set).unwrap_or(0);
        let mut p = Point {
            block: "rt",
            config: format!("{}/{set}", n.name()),
            cost: 0.0,
            host_ms: 0.0,
            scalar_ms: rt::PACKET_FORMATS.contains(n).then_some(0.0),
            psnr: 0.0,
            max_err: 0,
            depth_rmse: 0.0,
            mismatched: 0,
            coverage_mismatch: 0,
            aa_area_err: 0.0,
            is_default: (*n, *set) == DEFAULT_RT,
            front: false,
        };
        for (si, s) in scenes.iter().enumerate() {
            p.cost += rt_cost(&mixes[si][mi], *n) / scenes.len() as f64;
            p.host_ms += median(&mut times[ci][si]);
            if let Some(ms) = &mut p.scalar_ms {
                *ms += median(&mut scalar_times[ci][si]);
            }
            if let Some(f) = &frames[ci][si] {
                let (max, mism, area) = image_errors(&s.reference.rgb8, &f.rgb8);
                p.psnr += psnr_capped(&s.reference.rgb8, &f.rgb8) / scenes.len() as f64;
                p.max_err = p.max_err.max(max);
                p.mismatched += mism;
                p.aa_area_err += area / scenes.len() as f64;
                p.depth_rmse = p.depth_rmse.max(depth_rmse(&s.reference.depth, &f.depth));
            }
            let _ = s.size;
        }
        points.push(p);
    }
    mark_front(&mut points);
    Ok(points)
}

fn mark_front(points: &mut [Point]) {
    let pts: Vec<(f64, f64)> = points.iter().map(|p| (p.cost, p.psnr)).collect();
    for (p, f) in points.iter_mut().zip(pareto_front(&pts)) {
        p.front = f;
    }
}

/// Re-snaps a raster command file at another precision and AA setting: the file's
/// geometry is in pixels and snapped by the parser, so the TOML is edited and re-parsed.
fn raster_job(
    text: &str,
    file: &str,
    bits: u8,
    aa: Aa,
) -> Result<jobs::raster::RasterJob, BenchError> {
    let err = |message: String| BenchError::Raster {
        file: file.into(),
        message,
    };
    let mut v: toml::Table = toml::from_str(text).map_err(|e| err(e.to_string()))?;
    v.insert("subpixel_bits".into(), toml::Value::Integer(bits as i64));
    let mut a = toml::Table::new();
    a.insert(
        "pattern".into(),
        toml::Value::String(aa.pattern.name().into()),
    );
    if aa.pattern != AaPattern::None {
        a.insert("samples".into(), toml::Value::Integer(aa.samples as i64));
    }
    v.insert("aa".into(), toml::Value::Table(a));
    let edited = toml::to_string(&v).map_err(|e| err(e.to_string()))?;
    jobs::raster::parse(&edited, file).map_err(|e| err(e.to_string()))
}

/// Draws a job on the golden model; returns RGB and per-pixel write counts.
fn raster_draw(
    job: &jobs::raster::RasterJob,
    file: &str,
) -> Result<(Vec<u8>, Vec<u8>), BenchError> {
    let err = |message: String| BenchError::Raster {
        file: file.into(),
        message,
    };
    let s: &RasterSetup = &job.setup;
    let mut r = Raster::new(s.width as u32, s.height as u32, s).map_err(|e| err(e.to_string()))?;
    r.framebuffer_mut().track_writes(true);
    for c in &job.cmds {
        r.draw(c).map_err(|e| err(e.to_string()))?;
    }
    let fb = r.framebuffer();
    Ok((
        fb.rgb().to_vec(),
        fb.write_counts().map(<[u8]>::to_vec).unwrap_or_default(),
    ))
}

/// Raster sweep: sub-pixel bits × AA pattern × samples on every command file, against
/// 8 bits and a 64-sample regular grid.
pub fn sweep_raster(
    cfg: &BenchConfig,
    inputs: &mut Vec<String>,
    progress: &mut dyn FnMut(Progress),
) -> Result<Vec<Point>, BenchError> {
    let files = workloads(&cfg.raster_files, || builtin_raster(cfg.quick))?;
    let bits: &[u8] = if cfg.quick { &[4, 8] } else { &[2, 4, 6, 8] };
    let aas: Vec<(AaPattern, u8)> = if cfg.quick {
        vec![
            (AaPattern::None, 1),
            (AaPattern::Regular, 4),
            (AaPattern::Rotated, 4),
            (AaPattern::Coverage, 1),
        ]
    } else {
        let mut v = vec![(AaPattern::None, 1), (AaPattern::Coverage, 1)];
        for p in [
            AaPattern::Regular,
            AaPattern::Jitter,
            AaPattern::Rotated,
            AaPattern::Poisson,
        ] {
            for n in [4, 16] {
                v.push((p, n));
            }
        }
        v
    };
    let mut texts = Vec::new();
    let mut refs = Vec::new();
    for Workload { name, text } in files {
        let job = raster_job(
            &text,
            &name,
            8,
            Aa {
                pattern: AaPattern::Regular,
                samples: 64,
            },
        )?;
        refs.push(raster_draw(&job, &name)?);
        inputs.push(format!(
            "{name} at {}×{}",
            job.setup.width, job.setup.height
        ));
        texts.push((name, text));
    }
    let configs: Vec<(u8, AaPattern, u8)> = bits
        .iter()
        .flat_map(|b| aas.iter().map(move |(p, n)| (*b, *p, *n)))
        .collect();
    let mut jobs = Vec::new();
    for (b, p, n) in &configs {
        let mut per_file = Vec::new();
        for (name, text) in &texts {
            per_file.push(raster_job(
                text,
                name,
                *b,
                Aa {
                    pattern: *p,
                    samples: *n,
                },
            )?);
        }
        jobs.push(per_file);
    }
    let repeats = cfg.repeats.max(1);
    let sweep = Sweep::Raster;
    progress(Progress::Started {
        sweep,
        runs: (repeats * configs.len() * texts.len()) as u64,
    });
    let mut times = vec![vec![Vec::new(); texts.len()]; configs.len()];
    let mut outs = vec![vec![(Vec::new(), Vec::new()); texts.len()]; configs.len()];
    for _ in 0..repeats {
        for (ci, per_file) in jobs.iter().enumerate() {
            for (fi, job) in per_file.iter().enumerate() {
                let t = Instant::now();
                outs[ci][fi] = raster_draw(job, &texts[fi].0)?;
                times[ci][fi].push(t.elapsed().as_secs_f64() * 1e3);
                progress(Progress::Ran { sweep });
            }
        }
    }
    progress(Progress::Finished { sweep });
    let mut points = Vec::new();
    for (ci, (b, p, n)) in configs.iter().enumerate() {
        let mut pt = Point {
            block: "raster",
            config: format!("{b}bit/{}x{}", p.name(), effective_samples(*p, *n)),
            cost: raster_cost(*b, *p, *n),
            host_ms: 0.0,
            scalar_ms: None,
            psnr: 0.0,
            max_err: 0,
            depth_rmse: 0.0,
            mismatched: 0,
            coverage_mismatch: 0,
            aa_area_err: 0.0,
            is_default: (*b, *p, *n) == DEFAULT_RASTER,
            front: false,
        };
        if *p == AaPattern::Coverage {
            pt.config = format!("{b}bit/coverage");
        }
        for (fi, (rgb_ref, w_ref)) in refs.iter().enumerate() {
            let (rgb, w) = &outs[ci][fi];
            pt.host_ms += median(&mut times[ci][fi]);
            let (max, mism, area) = image_errors(rgb_ref, rgb);
            pt.psnr += psnr_capped(rgb_ref, rgb) / refs.len() as f64;
            pt.max_err = pt.max_err.max(max);
            pt.mismatched += mism;
            pt.aa_area_err += area / refs.len() as f64;
            pt.coverage_mismatch += w_ref
                .iter()
                .zip(w)
                .filter(|(a, b)| (**a > 0) != (**b > 0))
                .count() as u64;
        }
        points.push(pt);
    }
    mark_front(&mut points);
    Ok(points)
}

/// Runs both sweeps.
pub fn run(cfg: &BenchConfig) -> Result<Report, BenchError> {
    run_with_progress(cfg, &mut |_| {})
}

/// [`run`], telling `progress` about every timed run.
pub fn run_with_progress(
    cfg: &BenchConfig,
    progress: &mut dyn FnMut(Progress),
) -> Result<Report, BenchError> {
    let mut inputs = Vec::new();
    let rt = sweep_rt(cfg, &mut inputs, progress)?;
    let raster = sweep_raster(cfg, &mut inputs, progress)?;
    Ok(Report { rt, raster, inputs })
}

// ---------------------------------------------------------------------------------------
// Outputs

/// CSV of every point (one header line).
pub fn to_csv(r: &Report) -> String {
    let mut s = String::from(
        "block,config,cost,host_ms,scalar_host_ms,psnr_db,max_channel_err,depth_rmse,mismatched_px,coverage_mismatch_px,aa_area_err,default,front\n",
    );
    for p in r.rt.iter().chain(&r.raster) {
        let _ = writeln!(
            s,
            "{},{},{:.1},{:.3},{},{:.2},{},{:.6},{},{},{:.6},{},{}",
            p.block,
            p.config,
            p.cost,
            p.host_ms,
            p.scalar_ms.map(|ms| format!("{ms:.3}")).unwrap_or_default(),
            p.psnr,
            p.max_err,
            p.depth_rmse,
            p.mismatched,
            p.coverage_mismatch,
            p.aa_area_err,
            p.is_default,
            p.front
        );
    }
    s
}

/// Markdown tables (one per block), front points in bold, the default marked.
pub fn to_markdown(r: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "Inputs: {}.\n", r.inputs.join("; "));
    for (title, pts, unit) in [
        ("Ray tracer", &r.rt, "LUT-eq/sample"),
        ("Rasterizer", &r.raster, "LUT-eq/pixel"),
    ] {
        let _ = writeln!(s, "### {title}\n");
        let _ = writeln!(
            s,
            "| config | cost ({unit}) | host ms | scalar ms | PSNR dB | max err | depth RMSE | mismatched px | coverage mism. | AA area err | front |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
        let mut sorted: Vec<&Point> = pts.iter().collect();
        sorted.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        for p in sorted {
            let name = if p.is_default {
                format!("**{}** (default)", p.config)
            } else if p.front {
                format!("**{}**", p.config)
            } else {
                p.config.clone()
            };
            let psnr = if p.psnr >= PSNR_CAP {
                "identical".to_string()
            } else {
                format!("{:.2}", p.psnr)
            };
            let _ = writeln!(
                s,
                "| {name} | {:.0} | {:.2} | {} | {psnr} | {} | {:.2e} | {} | {} | {:.2e} | {} |",
                p.cost,
                p.host_ms,
                p.scalar_ms
                    .map(|ms| format!("{ms:.2}"))
                    .unwrap_or_else(|| "—".into()),
                p.max_err,
                p.depth_rmse,
                p.mismatched,
                p.coverage_mismatch,
                p.aa_area_err,
                if p.front { "yes" } else { "" }
            );
        }
        s.push('\n');
    }
    s
}

/// The font the plots' text is drawn in: DejaVu Sans cut down to the characters the plots
/// use (`host-cli/assets/fonts/`, its licence beside it). The binary carries it, so no
/// system font is looked up: CI and users' machines may have none.
const FONT_TTF: &[u8] = include_bytes!("../assets/fonts/DejaVuSans-subset.ttf");

/// The family the font is registered under: plotters' default for labels and legends, so
/// that nothing falls back to a font that is not there.
const FONT: &str = "sans-serif";

/// Size of a Pareto plot, pixels.
pub const PLOT_SIZE: (u32, u32) = (1100, 720);

/// Registers [`FONT_TTF`] with plotters, once per process.
fn register_font() -> Result<(), String> {
    static REGISTERED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, plotters::style::FontStyle::Normal, FONT_TTF).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err("the built-in plot font does not parse".into())
    }
}

/// A plot's title and axis descriptions, by block.
fn plot_text(block: &str) -> (&'static str, &'static str, &'static str) {
    if block == "raster" {
        (
            "Rasterizer: error against hardware cost (sub-pixel bits / AA pattern × samples)",
            "hardware cost: LUT-equivalents per pixel (log scale)",
            "mean PSNR against 8 bits, 64-sample grid (dB)",
        )
    } else {
        (
            "Ray tracer: error against hardware cost (number format / approximation set)",
            "hardware cost: LUT-equivalents per sample (log scale)",
            "mean PSNR against f64/exact (dB; identical = 120)",
        )
    }
}

/// A cost for a tick label: 900, 1.5k, 200k.
fn fmt_cost(c: f64) -> String {
    let short = |v: f64| {
        let s = format!("{v:.1}");
        s.strip_suffix(".0").map(str::to_string).unwrap_or(s)
    };
    if c >= 1e6 {
        format!("{}M", short(c / 1e6))
    } else if c >= 1e3 {
        format!("{}k", short(c / 1e3))
    } else {
        format!("{c:.0}")
    }
}

/// A pixel rectangle `[x0, x1) × [y0, y1)`, for placing point names.
#[derive(Debug, Clone, Copy)]
struct Boxed {
    x0: i32,
    y0: i32,
    x1: i32,
    y1: i32,
}

impl Boxed {
    fn overlaps(&self, o: &Boxed) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }

    fn inside(&self, o: &Boxed) -> bool {
        self.x0 >= o.x0 && self.x1 <= o.x1 && self.y0 >= o.y0 && self.y1 <= o.y1
    }
}

/// Where the name of a point at `(px, py)` (marker radius `r`) goes: beside it on the
/// left first (left of a front point is the empty, unreachable region), then above-left,
/// above-right, below-right and below-left, stepping away from the point until the box
/// overlaps no other name, marker or the legend and stays in the plot. `None`: no room.
fn place_name(
    (px, py): (i32, i32),
    r: i32,
    (tw, th): (i32, i32),
    taken: &[Boxed],
    area: &Boxed,
) -> Option<Boxed> {
    let g = r + 4;
    for level in 0..10 {
        let step = level * (th + 3);
        let mut candidates = Vec::new();
        if level == 0 {
            candidates.push((px - g - tw, py - th / 2));
        }
        let up = py - 3 - th - step;
        let down = py + 3 + step;
        candidates.extend([
            (px - g - tw, up),
            (px + g, up),
            (px + g, down),
            (px - g - tw, down),
        ]);
        for (x0, y0) in candidates {
            let b = Boxed {
                x0,
                y0,
                x1: x0 + tw,
                y1: y0 + th,
            };
            if b.inside(area) && !taken.iter().any(|t| t.overlaps(&b)) {
                return Some(b);
            }
        }
    }
    None
}

/// Draws a Pareto plot into `buf` (RGB8, [`PLOT_SIZE`]): log cost → right, PSNR ↑; grey
/// dots for the dominated points, the front as a blue staircase with blue dots, the
/// default as a red ring; a title, labelled axes with units and tick labels, a legend,
/// and the front's and the default's configurations named beside their points (points
/// that fall on the same pixel share one name: "f16/exact, f16/poly").
fn draw_plot(points: &[Point], buf: &mut [u8]) -> Result<(), String> {
    use plotters::prelude::*;
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    register_font()?;
    let e = |e: plotters::drawing::DrawingAreaErrorKind<_>| e.to_string();
    let root = BitMapBackend::with_buffer(buf, PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(e)?;
    let (title, x_desc, y_desc) = plot_text(points.first().map_or("rt", |p| p.block));
    let (mut cmin, mut cmax) = points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(p.cost.max(1.0)), b.max(p.cost.max(1.0)))
    });
    let (mut qmin, mut qmax) = points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(p.psnr), b.max(p.psnr))
    });
    if points.is_empty() {
        (cmin, cmax, qmin, qmax) = (1.0, 10.0, 0.0, 10.0);
    }
    // room on either side for the markers and the names beside them
    let pad = (cmax / cmin).powf(0.08).max(1.15);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 24))
        .margin(16)
        .x_label_area_size(60)
        .y_label_area_size(76)
        .build_cartesian_2d(
            ((cmin / pad)..(cmax * pad)).log_scale(),
            (qmin - 3.0)..(qmax + 4.0),
        )
        .map_err(e)?;
    let cost_label = |c: &f64| fmt_cost(*c);
    let db_label = |q: &f64| format!("{q:.0}");
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .axis_desc_style((FONT, 18))
        .label_style((FONT, 16))
        .x_labels(12)
        .y_labels(12)
        .x_max_light_lines(1)
        .y_max_light_lines(1)
        .x_label_formatter(&cost_label)
        .y_label_formatter(&db_label)
        .bold_line_style(RGBColor(210, 210, 210))
        .light_line_style(RGBColor(238, 238, 238))
        .axis_style(BLACK)
        .draw()
        .map_err(e)?;

    let grey = RGBColor(150, 150, 150);
    let blue = RGBColor(25, 85, 200);
    let red = RGBColor(215, 25, 25);
    let ink = RGBColor(20, 20, 20);
    let mut front: Vec<&Point> = points.iter().filter(|p| p.front).collect();
    front.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let mut stairs = Vec::new();
    for (i, p) in front.iter().enumerate() {
        if i > 0 {
            stairs.push((p.cost, front[i - 1].psnr));
        }
        stairs.push((p.cost, p.psnr));
    }
    chart
        .draw_series(
            points
                .iter()
                .filter(|p| !p.front)
                .map(|p| Circle::new((p.cost, p.psnr), 4, grey.filled())),
        )
        .map_err(e)?
        .label("other configurations (dominated: named in bench.md)")
        .legend(move |(x, y)| Circle::new((x + 10, y), 4, grey.filled()));
    chart
        .draw_series(std::iter::once(PathElement::new(
            stairs,
            blue.stroke_width(2),
        )))
        .map_err(e)?;
    chart
        .draw_series(
            front
                .iter()
                .map(|p| Circle::new((p.cost, p.psnr), 5, blue.filled())),
        )
        .map_err(e)?
        .label("Pareto front (no other point is cheaper and better)")
        .legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(0, 0), (20, 0)], blue.stroke_width(2))
                + Circle::new((10, 0), 5, blue.filled())
        });
    let default_name = points
        .iter()
        .find(|p| p.is_default)
        .map_or(String::new(), |p| format!(" ({})", p.config));
    chart
        .draw_series(
            points
                .iter()
                .filter(|p| p.is_default)
                .map(|p| Circle::new((p.cost, p.psnr), 10, red.stroke_width(3))),
        )
        .map_err(e)?
        .label(format!("the product's default configuration{default_name}"))
        .legend(move |(x, y)| Circle::new((x + 10, y), 7, red.stroke_width(3)));
    let legend_font = TextStyle::from((FONT, 16).into_font());
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .margin(12)
        .legend_area_size(30)
        .label_font(legend_font.clone())
        .background_style(WHITE.mix(0.92))
        .border_style(RGBColor(120, 120, 120))
        .draw()
        .map_err(e)?;

    // The names of the front's and the default's points.
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let area = Boxed {
        x0: xs.start + 2,
        y0: ys.start + 2,
        x1: xs.end - 2,
        y1: ys.end - 2,
    };
    // Every marker is an obstacle, and so is the legend (its size estimated as plotters
    // lays it out: three rows of the legend font, the widest label, a margin).
    let mut taken: Vec<Boxed> = points
        .iter()
        .map(|p| {
            let (x, y) = chart.backend_coord(&(p.cost, p.psnr));
            let r = if p.is_default { 12 } else { 6 };
            Boxed {
                x0: x - r,
                y0: y - r,
                x1: x + r + 1,
                y1: y + r + 1,
            }
        })
        .collect();
    let legend_w = [
        "other configurations (dominated: named in bench.md)".to_string(),
        "Pareto front (no other point is cheaper and better)".to_string(),
        format!("the product's default configuration{default_name}"),
    ]
    .iter()
    .map(|t| {
        root.estimate_text_size(t, &legend_font)
            .map_or(400, |s| s.0 as i32)
    })
    .max()
    .unwrap_or(400);
    taken.push(Boxed {
        x0: xs.start,
        y0: ys.start,
        x1: xs.start + 12 + 30 + legend_w + 24,
        y1: ys.start + 12 + 3 * 24 + 16,
    });
    // Font sizes are even: plotters' ab_glyph backend places each glyph at size / 2 plus
    // its top, truncated toward zero, which at odd sizes lifts small glyphs (a full stop
    // floats at mid-height).
    let name_font = TextStyle::from((FONT, 14).into_font());
    let mut named: Vec<(i32, i32, bool, Vec<&str>)> = Vec::new();
    for p in points.iter().filter(|p| p.front || p.is_default) {
        let (x, y) = chart.backend_coord(&(p.cost, p.psnr));
        match named
            .iter_mut()
            .find(|(nx, ny, _, _)| (nx - x).abs() <= 3 && (ny - y).abs() <= 3)
        {
            Some(n) => {
                n.2 |= p.is_default;
                n.3.push(&p.config);
            }
            None => named.push((x, y, p.is_default, vec![&p.config])),
        }
    }
    named.sort_by_key(|n| (n.0, n.1));
    for (x, y, is_default, configs) in named {
        let text = configs.join(", ");
        let (tw, th) = root
            .estimate_text_size(&text, &name_font)
            .map(|(w, _)| (w as i32, 14))
            .map_err(e)?;
        let r = if is_default { 12 } else { 6 };
        let b = place_name((x, y), r, (tw, th), &taken, &area).unwrap_or(Boxed {
            x0: x - r - 4 - tw,
            y0: y - th / 2,
            x1: x - r - 4,
            y1: y + th - th / 2,
        });
        taken.push(b);
        // A leader line from the marker's edge to the name, unless the name sits level
        // with its point (beside it): in a cluster, the line says which point it names.
        let (cx, cy) = (x.clamp(b.x0, b.x1), y.clamp(b.y0, b.y1));
        if cy != y {
            let (dx, dy) = (f64::from(cx - x), f64::from(cy - y));
            let len = dx.hypot(dy).max(1.0);
            let edge = f64::from(r - 2);
            let from = (
                x + (dx / len * edge).round() as i32,
                y + (dy / len * edge).round() as i32,
            );
            root.draw(&PathElement::new(
                vec![from, (cx, cy)],
                RGBColor(140, 140, 140),
            ))
            .map_err(e)?;
        }
        let colour = if is_default { red } else { ink };
        // ab_glyph draws a line's capitals from ~0.13 em above the anchor: nudge it down
        // so that the letters sit in the box
        let style = name_font
            .color(&colour)
            .pos(Pos::new(HPos::Left, VPos::Top));
        root.draw(&Text::new(text, (b.x0, b.y0 + 2), style))
            .map_err(e)?;
    }
    root.present().map_err(e)?;
    Ok(())
}

/// Draws a Pareto plot ([`PLOT_SIZE`], see `draw_plot` for what it shows) to a PNG.
pub fn plot(points: &[Point], path: &Path) -> Result<(), BenchError> {
    let werr = |message: String| BenchError::Write {
        path: path.display().to_string(),
        message,
    };
    let (w, h) = PLOT_SIZE;
    let mut buf = vec![0u8; (w * h * 3) as usize];
    draw_plot(points, &mut buf).map_err(werr)?;
    image::save_buffer(path, &buf, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| werr(e.to_string()))
}

/// Writes bench.csv, bench.md, pareto-rt.png and pareto-raster.png into `dir`.
pub fn write(r: &Report, dir: &Path) -> Result<(), BenchError> {
    let werr = |p: &Path, e: std::io::Error| BenchError::Write {
        path: p.display().to_string(),
        message: e.to_string(),
    };
    std::fs::create_dir_all(dir).map_err(|e| werr(dir, e))?;
    let csv = dir.join("bench.csv");
    std::fs::write(&csv, to_csv(r)).map_err(|e| werr(&csv, e))?;
    let md = dir.join("bench.md");
    std::fs::write(&md, to_markdown(r)).map_err(|e| werr(&md, e))?;
    plot(&r.rt, &dir.join("pareto-rt.png"))?;
    plot(&r.raster, &dir.join("pareto-raster.png"))?;
    Ok(())
}
