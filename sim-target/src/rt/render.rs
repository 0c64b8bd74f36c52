//! Rendering a frame: the entry points ([`render`], [`render_with_progress`],
//! [`render_instrumented`]), what they take ([`RenderOptions`] and its choices: [`Math`],
//! [`Kernel`], [`ToneMap`], [`Dispatch`]), what they return ([`Frame`] with its [`Stats`],
//! or [`RtError`]), the board constants the stats estimate board time with, and the frame
//! loop that runs a kernel over the rows.

use super::kernel::{Counts, FrameCtx, Rendered, RowFn};
use super::plan::validate;
use super::prepare::{camera, prepare, Prepared};
use super::{cull, plan, Features, Numeric, Plan, Quadratic, Scene};
use crate::num::{saturation, AcosKind, AtanKind, Scalar, SqrtKind, Q16_16, Q24_8, Q32_32, Q8_24};
use rayon::prelude::*;
use std::time::Instant;

/// Which approximation the kernel uses for each non-trivial function.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Math {
    /// √ and 1/√ (normalisation, discriminant, distances).
    pub sqrt: SqrtKind,
    /// Root formula of the quadratics.
    pub quadratic: Quadratic,
    /// arctangent (cylindrical/spherical mapping).
    pub atan: AtanKind,
    /// arccosine (spherical mapping).
    pub acos: AcosKind,
}

impl Math {
    /// The seed's choices: PRE_S + 2 Newton–Raphson steps, textbook quadratic, seed
    /// atan polynomial and 33-entry acos table.
    pub const SEED: Math = Math {
        sqrt: SqrtKind::PreS { iters: 2 },
        quadratic: Quadratic::Textbook,
        atan: AtanKind::Seed,
        acos: AcosKind::SeedLut33,
    };

    /// What `Math::default()` is, usable in const context: the format's cores for √, 1/√,
    /// atan and acos and the stable quadratic, i.e. [`Math::EXACT`]. It used to be
    /// [`Math::POLY`]; `fpgfx bench`'s full run showed the polynomials cost more than
    /// CORDIC cores and score lower, so that default was off the Pareto front.
    pub const DEFAULT: Math = Math::EXACT;

    /// Polynomials instead of atan/acos cores: odd minimax degree 11 atan and A&S 4.4.46
    /// acos (the default until the bench put it off the front).
    pub const POLY: Math = Math {
        sqrt: SqrtKind::Exact,
        quadratic: Quadratic::Stable,
        atan: AtanKind::Minimax11,
        acos: AcosKind::Sqrt8,
    };

    /// Correctly rounded cores for every function (√ and 1/√ of the format, atan/acos
    /// through f64): the error floor of a format, `fpgfx bench`'s "exact" set.
    pub const EXACT: Math = Math {
        sqrt: SqrtKind::Exact,
        quadratic: Quadratic::Stable,
        atan: AtanKind::Exact,
        acos: AcosKind::Exact,
    };

    /// The cheap-and-accurate set: at the seed's multiplier count, tables in place of its
    /// constants (docs/bench.md): 16-entry 1/√ start + 2 Newton–Raphson steps, stable
    /// quadratic, 33-entry atan table, binade-indexed acos table.
    pub const BETTER: Math = Math {
        sqrt: SqrtKind::Lut16 { iters: 2 },
        quadratic: Quadratic::Stable,
        atan: AtanKind::Lut33,
        acos: AcosKind::BinadeLut,
    };
}

/// Board clock of the performance reference (Hz).
pub const BOARD_CLOCK_HZ: f64 = 303.0e6;
/// DESIRED_INNER_LOOP_II: cycles per pixel (per sample).
pub const BOARD_II: u64 = 8;
/// Fixed cycles per frame beyond W·H·II, calibrated on the seed's 16 765 083 cycles at
/// 1920×1080 (pipeline fill and control).
pub const BOARD_FRAME_OVERHEAD: u64 = 16_765_083 - 1920 * 1080 * 8;

/// Rendering choices beyond the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderOptions {
    /// Number format the kernel computes in (the scene itself is always f64).
    pub numeric: Numeric,
    /// Override of the scene's samples per pixel.
    pub spp: Option<u32>,
    /// Which approximation each non-trivial function uses.
    pub math: Math,
    /// Also produce the depth and normal AOVs.
    pub aovs: bool,
    /// Override of the frame size (the camera keeps its field of view).
    pub size: Option<(u32, u32)>,
    /// How the kernel picks each object's intersector.
    pub dispatch: Dispatch,
    /// How radiance becomes an 8-bit value.
    pub tone_map: ToneMap,
    /// The plan's specialised kernel or the general one (bit-identical images; kept so
    /// that the specialisation can be measured, `benches/rt.rs` group `plan`).
    pub kernel: Kernel,
    /// Let the planned kernel skip objects a tile of primary rays cannot hit ([`cull`]):
    /// bit-identical images, applied only where [`cull::bounds`] admits the format and
    /// object; `false` tests every object with every ray, as the board does.
    pub cull: bool,
}

/// The formats whose [`Kernel::Planned`] traces its primary rays in SIMD packets (the
/// others' is the scalar kernel; the `packet` module says why only these).
pub const PACKET_FORMATS: &[Numeric] = &[Numeric::F32];

/// Which compiled kernel renders a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernel {
    /// The kernel monomorphised for the plan's [`Features`]: code for unused features is
    /// not compiled into it. In f32 its primary rays are searched in packets of eight
    /// (SIMD lanes); the same image as [`Kernel::Scalar`], bit for bit.
    #[default]
    Planned,
    /// [`Kernel::Planned`] one ray at a time in every format: the oracle the packets are
    /// held to, and their speed measured against.
    Scalar,
    /// Every feature compiled in, each tested at run time against the scene (what one
    /// fixed-function pipeline for all scenes would do).
    General,
}

/// Radiance → [0, 1] before ⌊255·c⌋.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ToneMap {
    /// Clamp to 1, as the seed (blown-out highlights).
    #[default]
    Clamp,
    /// (beyond) Reinhard c/(1 + c) per channel: the seed's own suggestion for its
    /// blown-out highlights; never saturates.
    Reinhard,
}

/// Intersector dispatch, selectable so that the two can be measured against each other
/// (`benches/rt.rs`, docs/rt.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dispatch {
    /// A function pointer per object, chosen by the plan.
    FnPointer,
    /// A `match` on the object's shape at every test (inlined): measured no slower than
    /// the function pointer in every run (docs/rt.md), so it is the default.
    #[default]
    Match,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            numeric: Numeric::F32,
            spp: None,
            math: Math::default(),
            aovs: false,
            size: None,
            dispatch: Dispatch::Match,
            tone_map: ToneMap::Clamp,
            kernel: Kernel::Planned,
            cull: true,
        }
    }
}

/// What a render did and what it would cost on the board.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Stats {
    /// Primary rays (pixels × spp).
    pub primary_rays: u64,
    /// Shadow rays traced (one per light a hit point faces, when shadows are on).
    pub shadow_rays: u64,
    /// Mirror-reflected rays traced (depth > 1, reflective materials).
    pub reflected_rays: u64,
    /// Refracted rays (beyond: transmissive dielectrics).
    pub refracted_rays: u64,
    /// Rays as docs/requirements.md §4.10 (and the seed's Mrays/s) counts them: every pixel sample costs
    /// DEPTH levels of (one ray + one shadow ray per light), whether or not the ray hits;
    /// that is what the board's fixed pipeline spends its cycles on. 4 per pixel for the
    /// reference scene (depth 2, one light), against ≈ 2.3 actually traced.
    pub nominal_rays: u64,
    /// Wall-clock seconds of the sim-target render.
    pub seconds: f64,
    /// Board-time estimate in cycles: pixels·spp·II + overhead.
    pub board_cycles: u64,
    /// Results the frame's fixed-point format clipped to its range, set-up included (the
    /// formats count each clip on the thread computing it); always 0 in the float formats,
    /// which do not saturate. Nonzero means the frame differs from what an unclipped
    /// datapath draws.
    pub saturations: u64,
}

impl Stats {
    /// Every ray actually traced (primary, shadow, reflected, refracted);
    /// [`Stats::nominal_rays`] is the count of docs/requirements.md §4.10.
    pub fn rays(&self) -> u64 {
        self.primary_rays + self.shadow_rays + self.reflected_rays + self.refracted_rays
    }
    /// Millions of traced rays per second of wall time.
    pub fn mrays_per_s(&self) -> f64 {
        if self.seconds > 0.0 {
            self.rays() as f64 / self.seconds / 1e6
        } else {
            0.0
        }
    }
    /// Millions of rays per second counted as docs/requirements.md §4.10 counts them
    /// ([`Stats::nominal_rays`]): the figure comparable with the seed's 158.29 Mrays/s and
    /// the f32 target of §7.3.
    pub fn nominal_mrays_per_s(&self) -> f64 {
        if self.seconds > 0.0 {
            self.nominal_rays as f64 / self.seconds / 1e6
        } else {
            0.0
        }
    }
    /// Board-time estimate in seconds at [`BOARD_CLOCK_HZ`].
    pub fn board_seconds(&self) -> f64 {
        self.board_cycles as f64 / BOARD_CLOCK_HZ
    }
}

/// A rendered frame: the image, its optional AOVs, and what producing it cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Width in pixels (the scene's, or [`RenderOptions::size`]).
    pub width: u32,
    /// Height in pixels (the scene's, or [`RenderOptions::size`]).
    pub height: u32,
    /// RGB888, row-major, ⌊255·clamp(c)⌋ per channel.
    pub rgb8: Vec<u8>,
    /// Distance to the first hit of the centre primary ray (+∞ for a miss).
    pub depth: Option<Vec<f32>>,
    /// World-space unit normal after the shading flip, 3 floats per pixel (0 for a miss).
    pub normal: Option<Vec<f32>>,
    /// Index of the object the centre primary ray hits first ([`NO_OBJECT`] for a miss):
    /// which object a pixel shows, the plane an RTL core's nearest-hit reduction is held
    /// to.
    pub object: Option<Vec<u16>>,
    /// Rays traced, wall time and the board-time estimate.
    pub stats: Stats,
    /// The plan the scene compiled to.
    pub plan: Plan,
}

/// The object-index plane's value for a pixel whose primary ray hits nothing.
pub const NO_OBJECT: u16 = u16::MAX;

/// Errors of [`render`].
#[derive(Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum RtError {
    /// The scene cannot be rendered as given.
    #[error("invalid scene: {0}")]
    InvalidScene(String),
}

/// How [`render_generic`] picks its kernel and runs its rows. The kernel chooser is a
/// function pointer, not a flag, so that a format only instantiates the kernels its entry
/// point names (a `match` on a flag would instantiate both sets for every format).
#[derive(Clone, Copy)]
struct Build<S: Scalar> {
    kernel: fn(Features) -> RowFn<S>,
    /// Rows on rayon's pool; `false`: on the calling thread, so that a wrapper type's
    /// thread-local counters see every operation of the frame and nothing else.
    parallel: bool,
    /// The kernel shades plain materials in packet lanes ([`Prepared::find_plain`]):
    /// only f32's packets, so that no other format or wrapper counts the set-up's
    /// products or clips.
    lanes: bool,
}

impl<S: Scalar> Build<S> {
    /// The plan's monomorphised kernel, rows in parallel: the model as users run it.
    fn production() -> Self {
        Self {
            kernel: Prepared::<S>::kernel,
            parallel: true,
            lanes: false,
        }
    }

    /// [`Prepared::compact_kernel`]'s four kernels, rows in parallel: the formats
    /// the block is not built in (f64, f16, Q8.24, Q24.8, Q32.32 serve as references and
    /// in `fpgfx bench`'s sweeps). Same bits as [`Self::production`]; the cost is the
    /// per-material tests for shadows, textures and specular in the hot loop, and the
    /// gain is 140 fewer whole-ray-tracer instantiations in every cold build.
    fn compact() -> Self {
        Self {
            kernel: Prepared::<S>::compact_kernel,
            parallel: true,
            lanes: false,
        }
    }

    /// [`Prepared::compact_kernel`], rows on the calling thread.
    fn instrumented() -> Self {
        Self {
            kernel: Prepared::<S>::compact_kernel,
            parallel: false,
            lanes: false,
        }
    }
}

impl Build<f32> {
    /// f32's kernels: [`Self::production`] with the primary rays in packets unless the
    /// options ask for the scalar or the general kernel.
    fn packets(kernel: Kernel) -> Self {
        Self {
            kernel: match kernel {
                Kernel::Planned => Prepared::<f32>::packet_kernel,
                Kernel::Scalar | Kernel::General => Prepared::<f32>::kernel,
            },
            parallel: true,
            lanes: kernel == Kernel::Planned,
        }
    }
}

/// One frame's inputs as the entry points resolved them (size and spp after overrides).
#[derive(Clone, Copy)]
struct Job<'a> {
    scene: &'a Scene,
    opts: &'a RenderOptions,
    width: u32,
    height: u32,
    spp: u32,
    plan: &'a Plan,
    progress: &'a (dyn Fn(u32, u32) + Sync),
}

/// One frame in format `S`: prepares the scene, picks the kernel `build` names, runs it
/// over the rows and joins them.
fn render_generic<S: Scalar>(job: Job<'_>, build: Build<S>) -> Rendered {
    let Job {
        scene,
        opts,
        width,
        height,
        spp,
        plan,
        progress,
    } = job;
    let rows_done = std::sync::atomic::AtomicU32::new(0);
    // the set-up's clips (scene constants beyond the format) count on this thread; each
    // row counts its own below, on whichever thread runs it
    let setup_start = saturation::total();
    // culling is exact only where a ray missing an object's bound makes the datapath
    // answer "no hit" too: not with a coarse √ (see `SqrtKind::max_rel_error`)
    let bounds = if opts.cull
        && opts.kernel != Kernel::General
        && opts.math.sqrt.max_rel_error() <= cull::MAX_SQRT_ERROR
    {
        cull::bounds::<S>(scene, &opts.math)
    } else {
        vec![None; scene.objects.len()]
    };
    let cull = opts.cull && opts.kernel != Kernel::General;
    let mut prep = prepare::<S>(
        scene,
        plan,
        opts.math,
        opts.dispatch,
        opts.kernel,
        &bounds,
        cull,
    );
    if build.lanes {
        prep.find_plain();
    }
    let features = match opts.kernel {
        Kernel::Planned | Kernel::Scalar => plan.features(),
        Kernel::General => Features::ALL,
    };
    let row_fn = (build.kernel)(features);
    let cam = camera(&scene.camera, width, height, spp);
    let tiles = bounds
        .iter()
        .any(Option::is_some)
        .then(|| cull::Tiles::new(&bounds, &cam, width, height));
    let ctx = FrameCtx::<S>::new(&cam, tiles, scene.objects.len(), (width, height, spp), opts);
    let aovs = opts.aovs;
    let setup_saturations = saturation::total().wrapping_sub(setup_start);
    let one_row = |j: u32| {
        let (mut r, saturations) = saturation::count(|| row_fn(&prep, &ctx, j));
        r.4.saturations = saturations;
        let done = rows_done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        progress(done, height);
        r
    };
    let rows: Vec<Rendered<Vec<f32>, Vec<u16>>> = if build.parallel {
        (0..height).into_par_iter().map(one_row).collect()
    } else {
        (0..height).map(one_row).collect()
    };
    let mut rgb8 = Vec::with_capacity(width as usize * height as usize * 3);
    let mut depth = Vec::new();
    let mut normal = Vec::new();
    let mut object = Vec::new();
    let mut total = Counts::default();
    total.saturations = setup_saturations;
    for (r, d, n, o, c) in rows {
        rgb8.extend(r);
        depth.extend(d);
        normal.extend(n);
        object.extend(o);
        total.primary += c.primary;
        total.shadow += c.shadow;
        total.reflected += c.reflected;
        total.refracted += c.refracted;
        total.saturations += c.saturations;
    }
    let (depth, normal, object) = if aovs {
        (Some(depth), Some(normal), Some(object))
    } else {
        (None, None, None)
    };
    (rgb8, depth, normal, object, total)
}

/// Mean number of objects per 16×16 tile that the planned kernel's primary rays test in
/// format `S` at `width`×`height` (the scene's object count when nothing can be culled):
/// how much the plan's culling saves, for `--stats`, docs and tests.
pub fn primary_candidates<S: Scalar>(scene: &Scene, width: u32, height: u32, math: &Math) -> f64 {
    if math.sqrt.max_rel_error() > cull::MAX_SQRT_ERROR {
        return scene.objects.len() as f64;
    }
    let bounds = cull::bounds::<S>(scene, math);
    if bounds.iter().all(Option::is_none) || width == 0 || height == 0 {
        return scene.objects.len() as f64;
    }
    let cam = camera(&scene.camera, width, height, 1);
    cull::Tiles::new(&bounds, &cam, width, height).mean_candidates()
}

/// Rays of a frame as docs/requirements.md §4.10 counts them: pixels × spp × DEPTH × (1 + shadow-casting
/// lights). "Rays per pixel at DEPTH = 2 with one point light: 4 (primary, its shadow ray,
/// reflected, its shadow ray) — the seed's Mrays/s counts these."
pub fn nominal_rays(scene: &Scene, width: u32, height: u32, spp: u32) -> u64 {
    let lights = if scene.shadows {
        scene.lights.len() as u64
    } else {
        0
    };
    width as u64 * height as u64 * spp.max(1) as u64 * scene.depth as u64 * (1 + lights)
}

/// Render a scene in the chosen number format.
pub fn render(scene: &Scene, opts: &RenderOptions) -> Result<Frame, RtError> {
    render_with_progress(scene, opts, &|_, _| {})
}

/// [`render`], calling `progress(rows_done, rows_total)` after each row (from the worker
/// threads, in completion order) so that a CLI can draw a progress bar.
pub fn render_with_progress(
    scene: &Scene,
    opts: &RenderOptions,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> Result<Frame, RtError> {
    frame_with(scene, opts, progress, |job| match opts.numeric {
        Numeric::F32 => render_generic::<f32>(job, Build::packets(opts.kernel)),
        Numeric::Q16_16 => render_generic::<Q16_16>(job, Build::production()),
        Numeric::F64 => render_generic::<f64>(job, Build::compact()),
        Numeric::F16 => render_generic::<half::f16>(job, Build::compact()),
        Numeric::Q8_24 => render_generic::<Q8_24>(job, Build::compact()),
        Numeric::Q24_8 => render_generic::<Q24_8>(job, Build::compact()),
        Numeric::Q32_32 => render_generic::<Q32_32>(job, Build::compact()),
    })
}

/// [`render`] in an instrumented [`Scalar`] (`opts.numeric` is ignored): a wrapper
/// that counts operations (`fpgfx bench`'s hardware cost model) or saturations and NaNs
/// (`fpgfx stress`), see [`crate::num::instrumented`].
///
/// Same image, same operations in the same order as [`render`] in the wrapped format,
/// but rows run one after another on the calling thread, so thread-local counters see
/// exactly this frame, and only four kernels are instantiated per wrapper type (see
/// `Prepared::compact_kernel`), which keeps the crates that name such types quick
/// to compile.
pub fn render_instrumented<S: Scalar>(
    scene: &Scene,
    opts: &RenderOptions,
) -> Result<Frame, RtError> {
    frame_with(scene, opts, &|_, _| {}, |job| {
        render_generic::<S>(job, Build::instrumented())
    })
}

/// What both entry points share: validate the scene, resolve size and spp, plan, time the
/// render `kernel` does, and assemble the [`Frame`].
fn frame_with(
    scene: &Scene,
    opts: &RenderOptions,
    progress: &(dyn Fn(u32, u32) + Sync),
    kernel: impl FnOnce(Job<'_>) -> Rendered,
) -> Result<Frame, RtError> {
    validate(scene)?;
    let (width, height) = opts.size.unwrap_or((scene.width, scene.height));
    if width == 0 || height == 0 {
        return Err(RtError::InvalidScene(format!(
            "frame size {width}x{height}"
        )));
    }
    let spp = opts.spp.unwrap_or(scene.spp).max(1);
    let plan = plan(scene);
    let start = Instant::now();
    let job = Job {
        scene,
        opts,
        width,
        height,
        spp,
        plan: &plan,
        progress,
    };
    let r = kernel(job);
    Ok(finish(scene, (width, height, spp), start, plan, r))
}

fn finish(
    scene: &Scene,
    (width, height, spp): (u32, u32, u32),
    start: Instant,
    plan: Plan,
    r: Rendered,
) -> Frame {
    let (rgb8, depth, normal, object, c) = r;
    let seconds = start.elapsed().as_secs_f64();
    let stats = Stats {
        primary_rays: c.primary,
        shadow_rays: c.shadow,
        reflected_rays: c.reflected,
        refracted_rays: c.refracted,
        nominal_rays: nominal_rays(scene, width, height, spp),
        seconds,
        board_cycles: width as u64 * height as u64 * spp as u64 * BOARD_II + BOARD_FRAME_OVERHEAD,
        saturations: c.saturations,
    };
    Frame {
        width,
        height,
        rgb8,
        depth,
        normal,
        object,
        stats,
        plan,
    }
}
