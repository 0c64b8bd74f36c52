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

use protocol::frame::{Aa, AaPattern, RasterSetup};
use protocol::names::Named;
use sim_target::num::instrumented::{self, Counted, OpKind};
use sim_target::raster::Raster;
use sim_target::rt::{self, scene_file, Math, Numeric, RenderOptions, Scene};

use crate::raster_file;

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
    Scene(#[from] scene_file::SceneFileError),
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
    let opts = |numeric, math| RenderOptions {
        numeric,
        math,
        aovs: true,
        size: Some(size),
        ..Default::default()
    };
    let mut scenes = Vec::new();
    for Workload { name, text } in files {
        let scene = scene_file::parse(&text, &name)?;
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

fn pattern_name(p: AaPattern) -> &'static str {
    match p {
        AaPattern::None => "none",
        AaPattern::Regular => "regular",
        AaPattern::Jitter => "jitter",
        AaPattern::Rotated => "rotated",
        AaPattern::Poisson => "poisson",
        AaPattern::Coverage => "coverage",
    }
}

/// Re-snaps a raster command file at another precision and AA setting: the file's
/// geometry is in pixels and snapped by the parser, so the TOML is edited and re-parsed.
fn raster_job(
    text: &str,
    file: &str,
    bits: u8,
    aa: Aa,
) -> Result<raster_file::RasterJob, BenchError> {
    let err = |message: String| BenchError::Raster {
        file: file.into(),
        message,
    };
    let mut v: toml::Table = toml::from_str(text).map_err(|e| err(e.to_string()))?;
    v.insert("subpixel_bits".into(), toml::Value::Integer(bits as i64));
    let mut a = toml::Table::new();
    a.insert(
        "pattern".into(),
        toml::Value::String(pattern_name(aa.pattern).into()),
    );
    if aa.pattern != AaPattern::None {
        a.insert("samples".into(), toml::Value::Integer(aa.samples as i64));
    }
    v.insert("aa".into(), toml::Value::Table(a));
    let edited = toml::to_string(&v).map_err(|e| err(e.to_string()))?;
    raster_file::parse(&edited, file).map_err(|e| err(e.to_string()))
}

/// Draws a job on the golden model; returns RGB and per-pixel write counts.
fn raster_draw(job: &raster_file::RasterJob, file: &str) -> Result<(Vec<u8>, Vec<u8>), BenchError> {
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
            config: format!("{b}bit/{}x{}", pattern_name(*p), effective_samples(*p, *n)),
            cost: raster_cost(*b, *p, *n),
            host_ms: 0.0,
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
        "block,config,cost,host_ms,psnr_db,max_channel_err,depth_rmse,mismatched_px,coverage_mismatch_px,aa_area_err,default,front\n",
    );
    for p in r.rt.iter().chain(&r.raster) {
        let _ = writeln!(
            s,
            "{},{},{:.1},{:.3},{:.2},{},{:.6},{},{},{:.6},{},{}",
            p.block,
            p.config,
            p.cost,
            p.host_ms,
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
            "| config | cost ({unit}) | host ms | PSNR dB | max err | depth RMSE | mismatched px | coverage mism. | AA area err | front |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
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
                "| {name} | {:.0} | {:.2} | {psnr} | {} | {:.2e} | {} | {} | {:.2e} | {} |",
                p.cost,
                p.host_ms,
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

/// Draws a Pareto plot (log cost → right, PSNR ↑): grey dots for all points, the front as
/// a blue staircase with blue dots, the default as a red ring. No text (no font
/// dependency); axes and labels are in the Markdown table next to it.
pub fn plot(points: &[Point], path: &Path) -> Result<(), BenchError> {
    use plotters::prelude::*;
    let (w, h) = (800u32, 500u32);
    let werr = |message: String| BenchError::Write {
        path: path.display().to_string(),
        message,
    };
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| werr(e.to_string()))?;
        let (cmin, cmax) = points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
            (a.min(p.cost.max(1.0)), b.max(p.cost.max(1.0)))
        });
        let (qmin, qmax) = points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
            (a.min(p.psnr), b.max(p.psnr))
        });
        let (lc0, lc1) = (cmin.ln() - 0.05, cmax.ln() + 0.05);
        let (q0, q1) = (qmin - 2.0, qmax + 2.0);
        let m = 40.0;
        let x = |c: f64| {
            (m + (c.max(1.0).ln() - lc0) / (lc1 - lc0).max(1e-9) * (w as f64 - 2.0 * m)) as i32
        };
        let y =
            |q: f64| (h as f64 - m - (q - q0) / (q1 - q0).max(1e-9) * (h as f64 - 2.0 * m)) as i32;
        // frame and a grid line every 10 dB and every decade of cost
        let grey = RGBColor(220, 220, 220);
        let mut db = (q0 / 10.0).ceil() * 10.0;
        while db <= q1 {
            root.draw(&PathElement::new(
                vec![(m as i32, y(db)), (w as i32 - m as i32, y(db))],
                grey,
            ))
            .map_err(|e| werr(e.to_string()))?;
            db += 10.0;
        }
        let mut dec = 10f64.powf((lc0 / 10f64.ln()).ceil());
        while dec.ln() <= lc1 {
            root.draw(&PathElement::new(
                vec![(x(dec), m as i32), (x(dec), h as i32 - m as i32)],
                grey,
            ))
            .map_err(|e| werr(e.to_string()))?;
            dec *= 10.0;
        }
        root.draw(&Rectangle::new(
            [
                (m as i32, m as i32),
                (w as i32 - m as i32, h as i32 - m as i32),
            ],
            BLACK,
        ))
        .map_err(|e| werr(e.to_string()))?;
        let mut front: Vec<&Point> = points.iter().filter(|p| p.front).collect();
        front.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        let mut stairs = Vec::new();
        for (i, p) in front.iter().enumerate() {
            if i > 0 {
                stairs.push((x(p.cost), y(front[i - 1].psnr)));
            }
            stairs.push((x(p.cost), y(p.psnr)));
        }
        root.draw(&PathElement::new(stairs, BLUE.stroke_width(2)))
            .map_err(|e| werr(e.to_string()))?;
        for p in points {
            let c = if p.front {
                BLUE.filled()
            } else {
                RGBColor(140, 140, 140).filled()
            };
            root.draw(&Circle::new((x(p.cost), y(p.psnr)), 4, c))
                .map_err(|e| werr(e.to_string()))?;
        }
        for p in points.iter().filter(|p| p.is_default) {
            root.draw(&Circle::new((x(p.cost), y(p.psnr)), 9, RED.stroke_width(3)))
                .map_err(|e| werr(e.to_string()))?;
        }
        root.present().map_err(|e| werr(e.to_string()))?;
    }
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
