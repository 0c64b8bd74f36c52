//! The ray-trace block (ViRAY, seed 002) as a golden model generic over number formats.
//!
//! Entry point: [`render`]. The scene ([`Scene`], or a TOML file through
//! `jobs::scene::parse`) is compiled once into a [`Plan`] and a format-specific
//! `Prepared` scene. The plan's feature set (shadows, textures, specular, reflection depth,
//! spheres only) selects one of 32 monomorphised kernels (const generics), so a kernel's
//! hot loop contains no test of a feature the scene does not use; the general kernel
//! (everything compiled in, runtime checks) stays selectable through
//! [`RenderOptions::kernel`] for comparison. Rows are rendered in parallel with rayon.
//!
//! Only the two formats the block is built in, f32 and Q16.16, get all 32 kernels. Each
//! kernel is a whole inlined ray tracer, and 32 of them for each of seven formats (and
//! again for every instrumented wrapper type) was most of a cold build. The other formats
//! and the wrappers get four (`Prepared::compact_kernel`: reflection and spheres-only
//! specialised, which change the operations that run; shadows, textures and specular
//! tested at run time, which changes no arithmetic), so their images and operation counts
//! are the same bits as the full set's.
//!
//! The scene model, the vectors, the output packers, the feature subsets and the wire
//! cost are private modules re-exported here. The kernel's stages ([`cull`], [`shade`],
//! [`shapes`], [`texture`]) are public as namespaces: each is tested on its own against
//! an f64 reference (the integration tests) and benched (`benches/rt.rs`), and their
//! functions read right only qualified (`shapes::sphere`, `shade::fresnel`,
//! `texture::texel`, `cull::bounds`). The scene file format is one too:
//! `jobs::scene::parse`.

pub mod cull;
pub mod shade;
pub mod shapes;
pub mod texture;

mod output;
mod pretest;
mod scene;
mod subset;
mod vec;

/// PSNR for comparing formats: the comparison crate's, so that `fpgfx compare` and the
/// numerics study measure with one definition.
pub use compare::psnr;
pub use output::{
    pack_kcu116, pack_rgb888, read_pfm, unpack_kcu116, unpack_rgb888, write_pfm, Pfm, PfmError,
};
pub use protocol::frame::Numeric;
pub use scene::{
    Camera, DiffuseModel, Filter, Light, Mapping, Material, Object, Reflection, Scene, Shape,
    Specular, SpecularModel, Spot, Term, Texture, TextureKind,
};
pub use shapes::Quadratic;
pub use subset::Subset;
pub use vec::{f, V3};

use crate::num::{AcosKind, AtanKind, Scalar, SqrtKind, Q16_16, Q24_8, Q32_32, Q8_24};
use pretest::RayF32;
use rayon::prelude::*;
use shade::{DiffuseParams, SpecParams};
use shapes::IntersectFn;
use std::time::Instant;
use texture::TexSlot;
use vec::M3;

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

/// Which compiled kernel renders a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kernel {
    /// The kernel monomorphised for the plan's [`Features`]: code for unused features is
    /// not compiled into it.
    #[default]
    Planned,
    /// Every feature compiled in, each tested at run time against the scene (what one
    /// fixed-function pipeline for all scenes would do).
    General,
}

/// The feature set a kernel is compiled for, decided by the plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Features {
    /// Shadow rays (point/spot lights present and SHADOW_ENABLE).
    pub shadows: bool,
    /// Texture lookups: some material has a texture.
    pub textures: bool,
    /// Specular BRDF terms: some material has one.
    pub specular: bool,
    /// Secondary (reflected/refracted) rays: traced depth > 1.
    pub reflect: bool,
    /// Only spheres: no shape dispatch, sphere normal = object-space hit point, and the
    /// primary rays' c = |o′|² − 1 precomputed per object.
    pub spheres_only: bool,
}

impl Features {
    /// Everything on: the general kernel's set.
    pub const ALL: Features = Features {
        shadows: true,
        textures: true,
        specular: true,
        reflect: true,
        spheres_only: false,
    };
}

impl std::fmt::Display for Features {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let b = |v: bool| if v { '1' } else { '0' };
        write!(
            f,
            "sh{}-tx{}-sp{}-rf{}-so{}",
            b(self.shadows),
            b(self.textures),
            b(self.specular),
            b(self.reflect),
            b(self.spheres_only)
        )
    }
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
    /// Results the frame's fixed-point format clipped to its range, set-up included
    /// ([`crate::num::saturation`]); always 0 in the float formats, which do not
    /// saturate. Nonzero means the frame differs from what an unclipped datapath draws.
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
    /// Rays traced, wall time and the board-time estimate.
    pub stats: Stats,
    /// The plan the scene compiled to.
    pub plan: Plan,
}

/// Errors of [`render`].
#[derive(Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum RtError {
    /// The scene cannot be rendered as given.
    #[error("invalid scene: {0}")]
    InvalidScene(String),
}

/// What a scene needs, decided once before rendering.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Plan {
    /// Distinct shapes present.
    pub shapes: Vec<Shape>,
    /// Point/spot lights (so shadow rays exist).
    pub lights: usize,
    /// Any spot light.
    pub spot: bool,
    /// Number of textures in memory.
    pub textures: usize,
    /// Texture side in texels.
    pub texture_side: usize,
    /// Any material with a specular term.
    pub specular: bool,
    /// Depth actually traced (1 if no material reflects).
    pub depth: u32,
    /// Shadow rays are traced (lights present and the scene's SHADOW_ENABLE).
    pub shadows: bool,
    /// Every object is a sphere.
    pub spheres_only: bool,
}

impl Plan {
    /// The kernel feature set this plan compiles to.
    pub fn features(&self) -> Features {
        Features {
            shadows: self.shadows,
            textures: self.textures > 0,
            specular: self.specular,
            reflect: self.depth > 1,
            spheres_only: self.spheres_only,
        }
    }
}

struct PObj<S> {
    /// M⁻¹'s diagonal when the object is not rotated: 3 products instead of 9 + 6 sums.
    diag: Option<V3<S>>,
    shape: Shape,
    intersect: IntersectFn<S>,
    minv: M3<S>,
    nmat: M3<S>,
    translate: V3<S>,
    /// The camera position in object space: every primary ray starts there, so its
    /// transform is done once per object instead of once per pixel (same operations, same
    /// bits).
    eye: V3<S>,
    /// |eye′|² − 1: a sphere's c for every primary ray (the spheres-only kernel's hoist).
    eye_c: S,
    material: usize,
}

struct PLight<S> {
    pos: V3<S>,
    color: V3<S>,
    spot: Option<(V3<S>, S, S)>,
}

enum PRefl<S> {
    None,
    Constant(S),
    Fresnel(S, S),
    Glass(S),
}

struct PMat<S> {
    ambient: Option<(S, V3<S>)>,
    kd: S,
    cd: V3<S>,
    /// Oren–Nayar (else Lambert): a `match` at the call, so that the term is inlined
    /// into the light loop (a function pointer cost a call with three vectors by value
    /// and the spills around it, twice per light).
    oren_nayar: bool,
    dparams: DiffuseParams<S>,
    /// k_s·c_s, Torrance–Sparrow (else Blinn–Phong), constants.
    spec: Option<(V3<S>, bool, SpecParams<S>)>,
    refl: PRefl<S>,
    tex: Option<(TexSlot<S>, V3<S>)>,
}

struct Prepared<S> {
    objs: Vec<PObj<S>>,
    /// The objects' culling spheres, for the secondary rays' pretest.
    spheres: pretest::Spheres,
    /// World-space camera position (primary rays' origin).
    eye: V3<S>,
    lights: Vec<PLight<S>>,
    mats: Vec<PMat<S>>,
    ambient: V3<S>,
    background: V3<S>,
    texmem: Vec<u32>,
    bias: S,
    maxd: S,
    depth: u32,
    /// The scene's SHADOW_ENABLE, tested at run time by the general kernel only.
    shadows: bool,
    m: Math,
    by_match: bool,
}

/// One monomorphised kernel: a row of the frame (see `Prepared::row`).
///
/// Why a row and not a ray: behind a function pointer, `trace` returned its colour and
/// hit through the stack, and the per-pixel loop's wide reload of fields stored one by
/// one stalled on store forwarding (perf: ≈ 2.5 % of an f32 frame). With the pixel loop
/// inside the kernel, `trace` inlines into it and the result stays in registers.
type RowFn<S> = fn(&Prepared<S>, &FrameCtx<S>, u32) -> Rendered<Vec<f32>>;

/// What every row of a frame shares, computed once per frame.
struct FrameCtx<S> {
    /// u·x of every column and sub-pixel column.
    cols: Vec<V3<S>>,
    cv: V3<S>,
    cw: V3<S>,
    eye: V3<S>,
    /// The plan's per-tile candidates of primary rays (None: every object, `all`).
    tiles: Option<cull::Tiles>,
    all: Vec<u16>,
    width: u32,
    /// Sub-pixel grid side, samples per pixel and 1/spp.
    grid: u32,
    spp: u32,
    inv_spp: S,
    hf: f64,
    /// tan(fov/2).
    s: f64,
    aovs: bool,
    tone_map: ToneMap,
    sqrt: SqrtKind,
}

impl<S> FrameCtx<S> {
    /// Sub-pixel offset of grid cell k along one axis.
    fn offset(&self, k: u32) -> f64 {
        if self.spp == 1 {
            0.5
        } else {
            (k as f64 + 0.5) / self.grid as f64
        }
    }
}

fn validate(scene: &Scene) -> Result<(), RtError> {
    let bad = |s: String| Err(RtError::InvalidScene(s));
    if scene.width == 0 || scene.height == 0 {
        return bad(format!("frame size {}x{}", scene.width, scene.height));
    }
    if scene.depth == 0 {
        return bad("depth must be at least 1".into());
    }
    for (i, o) in scene.objects.iter().enumerate() {
        if o.material >= scene.materials.len() {
            return bad(format!(
                "object {i}: material index {} out of range",
                o.material
            ));
        }
        if o.scale
            .iter()
            .any(|s| s.is_nan() || *s <= 0.0 || !s.is_finite())
        {
            return bad(format!("object {i}: non-positive scale"));
        }
    }
    let c = &scene.camera;
    let w = f::normalize(f::sub(c.position, c.look_at));
    let u = f::cross(c.up, w);
    if u.iter().all(|v| v.abs() < 1e-12) {
        return bad("camera up is parallel to the view direction".into());
    }
    if !(c.fov_y > 0.0 && c.fov_y < 180.0) {
        return bad(format!("fov_y {} not in (0, 180)", c.fov_y));
    }
    Ok(())
}

/// Compile the plan of a scene.
pub fn plan(scene: &Scene) -> Plan {
    let mut shapes: Vec<Shape> = Vec::new();
    for o in &scene.objects {
        if !shapes.contains(&o.shape) {
            shapes.push(o.shape);
        }
    }
    let textures = scene
        .materials
        .iter()
        .filter(|m| m.texture.is_some())
        .count();
    let reflects = scene
        .materials
        .iter()
        .any(|m| !matches!(m.reflection, Reflection::None));
    Plan {
        shapes,
        lights: scene.lights.len(),
        spot: scene.lights.iter().any(|l| l.spot.is_some()),
        textures,
        texture_side: texture::side_for(textures),
        specular: scene.materials.iter().any(|m| m.specular.is_some()),
        depth: if reflects { scene.depth } else { 1 },
        shadows: scene.shadows && !scene.lights.is_empty(),
        spheres_only: !scene.objects.is_empty()
            && scene.objects.iter().all(|o| o.shape == Shape::Sphere),
    }
}

fn prepare<S: Scalar>(
    scene: &Scene,
    plan: &Plan,
    m: Math,
    dispatch: Dispatch,
    kernel: Kernel,
    bounds: &[Option<cull::Bound>],
    cull: bool,
) -> Prepared<S> {
    let eye = V3::<S>::from_f64(scene.camera.position);
    let objs: Vec<PObj<S>> = scene
        .objects
        .iter()
        .map(|o| {
            // M = T·R·S, M⁻¹ = S⁻¹·Rᵀ (on the linear part)
            let r = f::rotation(o.rotate);
            let sinv = f::diag(o.scale.map(|s| 1.0 / s));
            let minv = f::mul(sinv, f::transpose(r));
            let rotated = o.rotate.iter().any(|a| *a != 0.0);
            let mut ob = PObj {
                diag: (!rotated).then(|| V3::from_f64([minv[0][0], minv[1][1], minv[2][2]])),
                shape: o.shape,
                intersect: shapes::intersect_fn::<S>(o.shape),
                minv: M3::from_f64(minv),
                nmat: M3::from_f64(f::transpose(minv)),
                translate: V3::from_f64(o.translate),
                eye: V3::zero(),
                eye_c: S::zero(),
                material: o.material,
            };
            ob.eye = ob.to_object(eye, V3::zero()).0;
            ob.eye_c = ob.eye.dot(ob.eye) - S::one();
            ob
        })
        .collect();
    let lights = scene
        .lights
        .iter()
        .map(|l| PLight {
            pos: V3::from_f64(l.position),
            color: V3::from_f64(l.color),
            spot: l.spot.as_ref().map(|s| {
                let w = s.cos_inner - s.cos_outer;
                let inv = if w > 1e-9 { 1.0 / w } else { 1e6 };
                (
                    V3::from_f64(f::normalize(s.direction)),
                    S::from_f64(s.cos_outer),
                    S::from_f64(inv),
                )
            }),
        })
        .collect();
    let side = plan.texture_side;
    let texmem = texture::memory(scene);
    let mut next_slot = 0usize;
    let mats = scene
        .materials
        .iter()
        .map(|mat| {
            let (oren_nayar, sigma2) = match mat.diffuse_model {
                DiffuseModel::Lambert => (false, 0.0),
                DiffuseModel::OrenNayar { sigma2 } => (true, sigma2),
            };
            let spec = mat.specular.as_ref().map(|s| {
                let kc = V3::from_f64(s.color).scale(S::from_f64(s.k));
                match s.model {
                    SpecularModel::BlinnPhong => {
                        (kc, false, SpecParams::new(s.exponent, 1.0, 0.0, m.sqrt))
                    }
                    SpecularModel::TorranceSparrow { eta, k } => {
                        (kc, true, SpecParams::new(s.exponent, eta, k, m.sqrt))
                    }
                }
            });
            let refl = match mat.reflection {
                Reflection::None => PRefl::None,
                Reflection::Constant(r) => PRefl::Constant(S::from_f64(r)),
                Reflection::Fresnel { eta, k } => PRefl::Fresnel(S::from_f64(eta), S::from_f64(k)),
                Reflection::Glass { eta } => PRefl::Glass(S::from_f64(eta)),
            };
            let tex = mat.texture.as_ref().map(|t| {
                let base = texture::slot_base(next_slot, side);
                next_slot += 1;
                (
                    TexSlot::new(
                        base,
                        side,
                        t.mapping,
                        t.filter,
                        (S::from_f64(t.scale[0]), S::from_f64(t.scale[1])),
                        (S::from_f64(t.offset[0]), S::from_f64(t.offset[1])),
                        texture::is_grey(t.kind),
                    ),
                    V3::from_f64(t.color2),
                )
            });
            PMat {
                ambient: mat
                    .ambient
                    .as_ref()
                    .map(|a| (S::from_f64(a.k), V3::from_f64(a.color))),
                kd: S::from_f64(mat.diffuse.k),
                cd: V3::from_f64(mat.diffuse.color),
                oren_nayar,
                dparams: DiffuseParams::oren_nayar(sigma2, m.sqrt),
                spec,
                refl,
                tex,
            }
        })
        .collect();
    // the flat objects' side test (`pretest::Flat`): only where culling is on (the planned
    // kernel with `RenderOptions::cull`; a count of every operation turns it off), for
    // formats that declare their rounding (all do; the instrumented wrappers declare their
    // format's), and only with a positive CORE_BIAS
    let bias = S::from_f64(scene.bias);
    let side_test = cull && S::rounding().is_some() && bias > S::zero();
    let flats: Vec<pretest::Flat> = objs
        .iter()
        .map(|ob| {
            let flat = matches!(ob.shape, Shape::Plane | Shape::Disk | Shape::Square);
            // unrotated: the object transforms rays by M⁻¹'s diagonal
            (side_test && flat && ob.diag.is_some()).then(|| ob.translate.y.to_f64() as f32)
        })
        .collect();
    Prepared {
        objs,
        spheres: pretest::Spheres::new(bounds, &flats),
        eye,
        lights,
        mats,
        ambient: V3::from_f64(scene.ambient),
        background: V3::from_f64(scene.background),
        texmem,
        bias: S::from_f64(scene.bias),
        // MAX_DISTANCE is "infinity": in a format whose range ends below it (f16: 65504 <
        // 1e6) it would round to ∞ and let a root at t = ∞ count as a hit; the format's
        // largest finite value is the same "infinity" without that.
        maxd: S::from_f64(scene.max_distance.min(S::max_value().to_f64())),
        // the general kernel does not use the plan's depth: a non-reflecting hit ends the
        // ray by its own test, with the same result
        depth: match kernel {
            Kernel::Planned => plan.depth,
            Kernel::General => scene.depth,
        },
        shadows: scene.shadows,
        m,
        by_match: dispatch == Dispatch::Match,
    }
}

#[derive(Default, Clone, Copy)]
struct Counts {
    primary: u64,
    shadow: u64,
    reflected: u64,
    refracted: u64,
    /// Results clipped while rendering the row (set by `render_generic` around the row).
    saturations: u64,
    /// Index of the object that blocked the last shadow ray of this row: tried first by
    /// the next one (neighbouring pixels share occluders). `occluded` is an any(), so the
    /// order cannot change the result.
    occluder: usize,
}

struct Hit<S> {
    t: S,
    n: V3<S>,
}

impl<S: Scalar> PObj<S> {
    /// The ray in object space.
    #[inline(always)]
    fn to_object(&self, o: V3<S>, d: V3<S>) -> (V3<S>, V3<S>) {
        match self.diag {
            Some(g) => ((o - self.translate).hadamard(g), d.hadamard(g)),
            None => (self.minv.mul_v(o - self.translate), self.minv.mul_v(d)),
        }
    }
}

impl<S: Scalar> Prepared<S> {
    #[inline(always)]
    fn hit_object(&self, ob: &PObj<S>, o: V3<S>, d: V3<S>, tmax: S) -> Option<S> {
        if self.by_match {
            shapes::intersect(ob.shape, o, d, self.bias, tmax, &self.m)
        } else {
            (ob.intersect)(o, d, self.bias, tmax, &self.m)
        }
    }

    /// One object's intersection: the sphere directly in the spheres-only kernel (`c` is
    /// |o′|² − 1 when the caller has it precomputed), otherwise the shape dispatch.
    #[inline(always)]
    fn hit<const SO: bool>(
        &self,
        ob: &PObj<S>,
        o: V3<S>,
        d: V3<S>,
        c: Option<S>,
        tmax: S,
    ) -> Option<S> {
        if SO {
            let c = match c {
                Some(c) => c,
                None => o.dot(o) - S::one(),
            };
            shapes::sphere_c(o, d, c, self.bias, tmax, &self.m)
        } else {
            self.hit_object(ob, o, d, tmax)
        }
    }

    /// Nearest hit and the ray in that object's space. `eye_objs` is Some for a ray from
    /// the camera position (whose object-space image each object has precomputed) and
    /// lists, in object order, the only objects it can hit (the plan's culling, or all).
    /// Inlined into `trace`: as a call, its result (t, index, the object-space ray) went
    /// back through the stack, and `trace`'s wide reload of fields stored one by one
    /// stalled on store forwarding (perf: 4.6 % of an f32 frame on that one load).
    #[inline(always)]
    fn closest<const SO: bool>(
        &self,
        o: V3<S>,
        d: V3<S>,
        eye_objs: Option<&[u16]>,
    ) -> Option<(S, usize, V3<S>, V3<S>)> {
        let mut best = self.maxd;
        let mut found = None;
        match eye_objs {
            Some(list) => {
                for &k in list {
                    let i = k as usize;
                    let Some(ob) = self.objs.get(i) else { continue };
                    let (lo, ld) = (ob.eye, ob.to_object(V3::zero(), d).1);
                    if let Some(t) = self.hit::<SO>(ob, lo, ld, Some(ob.eye_c), best) {
                        best = t;
                        found = Some((i, lo, ld));
                    }
                }
            }
            None => {
                let rf = RayF32::new(o, d);
                for c in 0..self.spheres.chunks() {
                    let mut may = self.spheres.may_hit(c, &rf);
                    while may != 0 {
                        let i = c * pretest::CHUNK + may.trailing_zeros() as usize;
                        may &= may - 1;
                        let Some(ob) = self.objs.get(i) else { break };
                        let (lo, ld) = ob.to_object(o, d);
                        if let Some(t) = self.hit::<SO>(ob, lo, ld, None, best) {
                            best = t;
                            found = Some((i, lo, ld));
                        }
                    }
                }
            }
        }
        found.map(|(i, lo, ld)| (best, i, lo, ld))
    }

    /// Whether object `i` blocks the shadow ray (inlined: it runs for nearly every
    /// candidate of every shadow ray).
    #[inline(always)]
    fn blocks<const SO: bool>(&self, i: usize, o: V3<S>, d: V3<S>, tmax: S) -> bool {
        self.objs.get(i).is_some_and(|ob| {
            let (lo, ld) = ob.to_object(o, d);
            self.hit::<SO>(ob, lo, ld, None, tmax).is_some()
        })
    }

    /// Whether a shadow ray o + t·d, t ∈ [bias, tmax], hits any object. The pretest's
    /// mask says which objects to test; the object that blocked this row's previous
    /// shadow ray (`cache`) goes first, since neighbouring pixels share occluders (an
    /// any(): the order cannot change the answer).
    /// Inlined for the same reason as `closest` (Q16.16: −1.4 % instructions).
    #[inline(always)]
    fn occluded<const SO: bool>(&self, o: V3<S>, d: V3<S>, tmax: S, cache: &mut usize) -> bool {
        let rf = RayF32::new(o, d);
        let blocks = |i: usize| self.blocks::<SO>(i, o, d, tmax);
        let first = *cache;
        for c in 0..self.spheres.chunks() {
            let mut may = self.spheres.may_hit(c, &rf);
            let base = c * pretest::CHUNK;
            if first >= base && first - base < pretest::CHUNK {
                let bit = 1u64 << (first - base);
                if may & bit != 0 {
                    if blocks(first) {
                        return true;
                    }
                    may &= !bit;
                }
            }
            while may != 0 {
                let i = base + may.trailing_zeros() as usize;
                may &= may - 1;
                if blocks(i) {
                    *cache = i;
                    return true;
                }
            }
        }
        false
    }

    /// The kernel for a feature set, picked once per frame.
    fn kernel(f: Features) -> RowFn<S> {
        fn so<S: Scalar, const SH: bool, const TX: bool, const SP: bool, const RF: bool>(
            f: Features,
        ) -> RowFn<S> {
            if f.spheres_only {
                Prepared::<S>::row::<SH, TX, SP, RF, true>
            } else {
                Prepared::<S>::row::<SH, TX, SP, RF, false>
            }
        }
        fn rf<S: Scalar, const SH: bool, const TX: bool, const SP: bool>(f: Features) -> RowFn<S> {
            if f.reflect {
                so::<S, SH, TX, SP, true>(f)
            } else {
                so::<S, SH, TX, SP, false>(f)
            }
        }
        fn sp<S: Scalar, const SH: bool, const TX: bool>(f: Features) -> RowFn<S> {
            if f.specular {
                rf::<S, SH, TX, true>(f)
            } else {
                rf::<S, SH, TX, false>(f)
            }
        }
        fn tx<S: Scalar, const SH: bool>(f: Features) -> RowFn<S> {
            if f.textures {
                sp::<S, SH, true>(f)
            } else {
                sp::<S, SH, false>(f)
            }
        }
        if f.shadows {
            tx::<S, true>(f)
        } else {
            tx::<S, false>(f)
        }
    }

    /// The four kernels that the secondary formats and the instrumented number types
    /// render with: shadows, textures and specular compiled in and tested at run time
    /// (those tests do no arithmetic, so the operation stream and every bit equal the
    /// planned kernel's), reflection and spheres-only as the plan says (they change which
    /// operations run).
    ///
    /// Why not [`Self::kernel`]: each of its 32 kernels is a whole inlined ray tracer, and
    /// a wrapper type such as an operation counter instantiated all 32 again in the crate
    /// that names it. Four keep counts exact.
    fn compact_kernel(f: Features) -> RowFn<S> {
        match (f.reflect, f.spheres_only) {
            (true, true) => Prepared::<S>::row::<true, true, true, true, true>,
            (true, false) => Prepared::<S>::row::<true, true, true, true, false>,
            (false, true) => Prepared::<S>::row::<true, true, true, false, true>,
            (false, false) => Prepared::<S>::row::<true, true, true, false, false>,
        }
    }

    /// Radiance along a ray (d unit) that starts at recursion level `start` (0 for a
    /// primary ray, which `refracted` = false counts as primary); returns colour and the
    /// first hit. `eye_objs` lists the objects a primary ray from the eye can hit. The const parameters are the kernel's [`Features`] (shadows, textures,
    /// specular, reflection, spheres only): a `false` removes the feature's code, a `true`
    /// keeps it together with the per-material/per-scene runtime test.
    #[allow(clippy::too_many_lines)]
    #[inline(always)]
    fn trace<const SH: bool, const TX: bool, const SP: bool, const RF: bool, const SO: bool>(
        &self,
        o: V3<S>,
        d: V3<S>,
        start: u32,
        refracted: bool,
        eye_objs: &[u16],
        cnt: &mut Counts,
    ) -> (V3<S>, Option<Hit<S>>) {
        let zero = S::zero();
        let one = S::one();
        let sq = self.m.sqrt;
        let mut color = V3::zero();
        let mut weight = one;
        let mut first = None;
        let (mut o, mut d) = (o, d);
        for level in start..self.depth {
            if level == start && refracted {
                cnt.refracted += 1;
            } else if level == 0 {
                cnt.primary += 1;
            } else {
                cnt.reflected += 1;
            }
            let from_eye = level == 0 && !refracted && o == self.eye;
            let Some((t, i, lo, ld)) = self.closest::<SO>(o, d, from_eye.then_some(eye_objs))
            else {
                color = color + self.background.scale(weight);
                break;
            };
            let ob = &self.objs[i];
            let lp = lo + ld.scale(t);
            let p = o + d.scale(t);
            let on = if SO { lp } else { shapes::normal(ob.shape, lp) };
            let mut n = ob.nmat.mul_v(on).normalize(sq);
            let inside = n.dot(d) >= zero;
            if inside {
                n = -n; // INTERNAL_SHADING: both sides shade
            }
            if level == 0 {
                first = Some(Hit { t, n });
            }
            let mat = &self.mats[ob.material];
            let wo = -d;
            // texture replaces the diffuse (and ambient) colour
            let (cd, ca) = match (TX, &mat.tex) {
                (true, Some((slot, c2))) => {
                    let (u, v) = texture::map_uv(slot.mapping, lp, &self.m);
                    let c = if slot.grey {
                        let mix = texture::sample_grey(&self.texmem, slot, u, v);
                        mat.cd.scale(mix) + c2.scale(one - mix)
                    } else {
                        texture::sample(&self.texmem, slot, u, v)
                    };
                    (c, mat.ambient.as_ref().map(|_| c))
                }
                _ => (mat.cd, mat.ambient.as_ref().map(|a| a.1)),
            };
            let mut lk = V3::zero();
            if let (Some((ka, _)), Some(ca)) = (&mat.ambient, ca) {
                lk = ca.hadamard(self.ambient).scale(*ka);
            }
            let kdcd = cd.scale(mat.kd);
            // Secondary rays start one CORE_BIAS off the surface along the shading normal:
            // the hit point carries the error of t·d (≈ 2⁻¹⁶·t per axis in Q16.16, 1.6·10⁻⁴
            // at t = 10), which tmin = CORE_BIAS alone does not cover (shadow acne).
            let p_off = p + n.scale(self.bias);
            for l in &self.lights {
                let to_l = l.pos - p;
                let dist2 = to_l.dot(to_l);
                if dist2 <= zero {
                    continue;
                }
                let inv_dist = crate::num::rsqrt(dist2, sq);
                let wi = to_l.scale(inv_dist);
                let ndl = n.dot(wi);
                if ndl <= zero {
                    continue;
                }
                let scf = match &l.spot {
                    None => one,
                    Some((dir, cos_o, inv_w)) => shade::spot_factor(*dir, wi, *cos_o, *inv_w),
                };
                if scf <= zero {
                    continue;
                }
                if SH && self.shadows {
                    cnt.shadow += 1;
                    let dist = dist2 * inv_dist;
                    if self.occluded::<SO>(p_off, wi, dist, &mut cnt.occluder) {
                        continue;
                    }
                }
                let g = ndl / dist2 * scf;
                let fd = if mat.oren_nayar {
                    shade::oren_nayar(n, wi, wo, &mat.dparams)
                } else {
                    shade::lambert(n, wi, wo, &mat.dparams)
                };
                let mut brdf = kdcd.scale(fd);
                if SP {
                    if let Some((kscs, ts, sp)) = &mat.spec {
                        let fs = if *ts {
                            shade::torrance_sparrow(n, wi, wo, sp)
                        } else {
                            shade::blinn_phong(n, wi, wo, sp)
                        };
                        brdf = brdf + kscs.scale(fs);
                    }
                }
                lk = lk + brdf.hadamard(l.color).scale(g);
            }
            color = color + lk.scale(weight);
            if !RF {
                break;
            }
            let r = match mat.refl {
                PRefl::None => break,
                PRefl::Constant(r) => r,
                PRefl::Fresnel(eta, k) => shade::fresnel(n.dot(wo), eta, k, sq),
                PRefl::Glass(eta) => {
                    // (beyond) refraction: relative index by the side the ray arrives from
                    let eta_rel = if inside { one / eta } else { eta };
                    let cos_i = n.dot(wo).clamp(zero, one);
                    let r = shade::fresnel(cos_i, eta_rel, zero, sq);
                    if r < one && level + 1 < self.depth {
                        let ratio = one / eta_rel;
                        let sin2_t = ratio * ratio * (one - cos_i * cos_i);
                        let cos_t = crate::num::sqrt(one - sin2_t, sq);
                        let t_dir = (d.scale(ratio) + n.scale(ratio * cos_i - cos_t)).normalize(sq);
                        let lt = self.trace_refracted::<SH, TX, SP, RF, SO>(
                            p - n.scale(self.bias),
                            t_dir,
                            level + 1,
                            cnt,
                        );
                        color = color + lt.scale(weight * (one - r));
                    }
                    r
                }
            };
            if r <= zero {
                break;
            }
            weight = weight * r;
            // mirror reflection of d about n
            let two = S::from_f64(2.0);
            d = (d - n.scale(two * d.dot(n))).normalize(sq);
            o = p_off;
        }
        (color, first)
    }

    /// The refracted ray's radiance (out of line: `trace` inlines everywhere else, and
    /// this is where it recurses).
    #[inline(never)]
    fn trace_refracted<
        const SH: bool,
        const TX: bool,
        const SP: bool,
        const RF: bool,
        const SO: bool,
    >(
        &self,
        o: V3<S>,
        d: V3<S>,
        level: u32,
        cnt: &mut Counts,
    ) -> V3<S> {
        self.trace::<SH, TX, SP, RF, SO>(o, d, level, true, &[], cnt)
            .0
    }

    /// Row `j` of the frame: colour bytes, the AOVs when asked for, and the ray counts.
    fn row<const SH: bool, const TX: bool, const SP: bool, const RF: bool, const SO: bool>(
        &self,
        f: &FrameCtx<S>,
        j: u32,
    ) -> Rendered<Vec<f32>> {
        let row: Vec<V3<S>> = (0..f.grid)
            .map(|k| {
                let y = (1.0 - 2.0 * (j as f64 + f.offset(k)) / f.hf) * f.s;
                f.cv.scale(S::from_f64(y))
            })
            .collect();
        let mut cnt = Counts::default();
        let mut rgb = Vec::with_capacity(f.width as usize * 3);
        let mut depth = Vec::new();
        let mut normal = Vec::new();
        for i in 0..f.width {
            let eye_objs = match &f.tiles {
                Some(t) => t.at(i, j),
                None => &f.all,
            };
            let mut acc = V3::<S>::zero();
            for s in 0..f.spp {
                let (Some(&ux), Some(&vy)) = (
                    f.cols.get((i * f.grid + s % f.grid) as usize),
                    row.get((s / f.grid) as usize),
                ) else {
                    continue;
                };
                let (c, hit) = if eye_objs.is_empty() {
                    // the plan proved the tile's rays hit nothing: what `trace` returns
                    // for a miss, without the direction or the object loop
                    cnt.primary += 1;
                    (V3::zero() + self.background.scale(S::one()), None)
                } else {
                    let d = (ux + vy - f.cw).normalize(f.sqrt);
                    self.trace::<SH, TX, SP, RF, SO>(f.eye, d, 0, false, eye_objs, &mut cnt)
                };
                acc = acc + c;
                if f.aovs && s == 0 {
                    match hit {
                        Some(h) => {
                            depth.push(h.t.to_f64() as f32);
                            normal.extend(h.n.to_f64().map(|v| v as f32));
                        }
                        None => {
                            depth.push(f32::INFINITY);
                            normal.extend([0.0f32; 3]);
                        }
                    }
                }
            }
            let c = if f.spp == 1 {
                acc
            } else {
                acc.scale(f.inv_spp)
            };
            let c = match f.tone_map {
                ToneMap::Clamp => c,
                ToneMap::Reinhard => {
                    let one = S::one();
                    let r = |v: S| {
                        let v = v.max(S::zero());
                        v / (one + v)
                    };
                    V3::new(r(c.x), r(c.y), r(c.z))
                }
            };
            // ⌊255·c⌋: the product is ≥ 0 (or NaN → 0), where `as` truncation is the
            // floor; cheaper than the format's floor and the same bits
            let q = |v: S| (v.clamp(S::zero(), S::one()) * S::from_f64(255.0)).to_f64() as u8;
            rgb.extend([q(c.x), q(c.y), q(c.z)]);
        }
        (rgb, depth, normal, cnt)
    }
}

/// rgb8, depth, normal, ray counts of a frame or a row.
type Rendered<A = Option<Vec<f32>>> = (Vec<u8>, A, A, Counts);

struct Cam {
    eye: [f64; 3],
    u: [f64; 3],
    v: [f64; 3],
    w: [f64; 3],
    s: f64,
    a: f64,
}

fn camera(c: &Camera, width: u32, height: u32) -> Cam {
    let w = f::normalize(f::sub(c.position, c.look_at));
    let u = f::normalize(f::cross(c.up, w));
    let v = f::cross(w, u);
    Cam {
        eye: c.position,
        u,
        v,
        w,
        s: (c.fov_y.to_radians() / 2.0).tan(),
        a: width as f64 / height as f64,
    }
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
}

impl<S: Scalar> Build<S> {
    /// The plan's monomorphised kernel, rows in parallel: the model as users run it.
    fn production() -> Self {
        Self {
            kernel: Prepared::<S>::kernel,
            parallel: true,
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
        }
    }

    /// [`Prepared::compact_kernel`], rows on the calling thread.
    fn instrumented() -> Self {
        Self {
            kernel: Prepared::<S>::compact_kernel,
            parallel: false,
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
    let setup_start = crate::num::saturation::total();
    // culling is exact only where a ray missing an object's bound makes the datapath
    // answer "no hit" too: not with a coarse √ (see `SqrtKind::max_rel_error`)
    let bounds = if opts.cull
        && opts.kernel == Kernel::Planned
        && opts.math.sqrt.max_rel_error() <= cull::MAX_SQRT_ERROR
    {
        cull::bounds::<S>(scene, &opts.math)
    } else {
        vec![None; scene.objects.len()]
    };
    let cull = opts.cull && opts.kernel == Kernel::Planned;
    let prep = prepare::<S>(
        scene,
        plan,
        opts.math,
        opts.dispatch,
        opts.kernel,
        &bounds,
        cull,
    );
    let features = match opts.kernel {
        Kernel::Planned => plan.features(),
        Kernel::General => Features::ALL,
    };
    let row_fn = (build.kernel)(features);
    let cam = camera(&scene.camera, width, height);
    let (cu, cv, cw) = (
        V3::<S>::from_f64(cam.u),
        V3::<S>::from_f64(cam.v),
        V3::<S>::from_f64(cam.w),
    );
    let grid = (spp as f64).sqrt().ceil() as u32;
    let mut ctx = FrameCtx {
        cols: Vec::new(),
        cv,
        cw,
        eye: V3::<S>::from_f64(cam.eye),
        tiles: bounds
            .iter()
            .any(Option::is_some)
            .then(|| cull::Tiles::new(&bounds, &cam, width, height)),
        all: (0..scene.objects.len().min(u16::MAX as usize) as u16).collect(),
        width,
        grid,
        spp,
        inv_spp: S::from_f64(1.0 / spp as f64),
        hf: height as f64,
        s: cam.s,
        aovs: opts.aovs,
        tone_map: opts.tone_map,
        sqrt: opts.math.sqrt,
    };
    // u·x of every column and sub-pixel column, computed once per frame instead of once
    // per pixel (same operations, same bits)
    let wf = width as f64;
    ctx.cols = (0..width)
        .flat_map(|i| {
            let ctx = &ctx;
            (0..grid).map(move |k| {
                let x = (2.0 * (i as f64 + ctx.offset(k)) / wf - 1.0) * cam.s * cam.a;
                cu.scale(S::from_f64(x))
            })
        })
        .collect();
    let aovs = opts.aovs;
    let setup_saturations = crate::num::saturation::total().wrapping_sub(setup_start);
    let one_row = |j: u32| {
        let (mut r, saturations) = crate::num::saturation::count(|| row_fn(&prep, &ctx, j));
        r.3.saturations = saturations;
        let done = rows_done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        progress(done, height);
        r
    };
    let rows: Vec<Rendered<Vec<f32>>> = if build.parallel {
        (0..height).into_par_iter().map(one_row).collect()
    } else {
        (0..height).map(one_row).collect()
    };
    let mut rgb8 = Vec::with_capacity(width as usize * height as usize * 3);
    let mut depth = Vec::new();
    let mut normal = Vec::new();
    let mut total = Counts {
        saturations: setup_saturations,
        ..Counts::default()
    };
    for (r, d, n, c) in rows {
        rgb8.extend(r);
        depth.extend(d);
        normal.extend(n);
        total.primary += c.primary;
        total.shadow += c.shadow;
        total.reflected += c.reflected;
        total.refracted += c.refracted;
        total.saturations += c.saturations;
    }
    let (depth, normal) = if aovs {
        (Some(depth), Some(normal))
    } else {
        (None, None)
    };
    (rgb8, depth, normal, total)
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
    let cam = camera(&scene.camera, width, height);
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
        Numeric::F32 => render_generic::<f32>(job, Build::production()),
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
    let (rgb8, depth, normal, c) = r;
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
        stats,
        plan,
    }
}
