//! The plan's primary-ray culling: which objects a tile of primary rays can hit at all.
//!
//! The board tests every object for every ray; the golden model may skip an object only
//! where the exhaustive test would certainly have answered "no hit", so that images stay
//! bit-identical with the unculled kernel ([`super::Kernel::General`], or
//! `RenderOptions::cull = false`). The test is a cone–sphere test in f64 on the directions
//! of a tile's rays against each bounded object's world-space bounding sphere, widened by
//! a margin that covers the kernel's rounding of the ray direction; it is used only for
//! formats and scenes where the format's intersection arithmetic stays far from
//! saturation ([`bounds`]). Secondary (shadow and reflected) rays use the same spheres
//! through a cheap f32 pretest in the kernel, with a rounding allowance (and, for the
//! fixed-point cylinder and cone, a per-ray gate on the quadratic's leading coefficient:
//! [`Secondary`]). `fpgfx stress`
//! renders random scenes both ways and fails on any difference.

use super::prepare::Cam;
use super::scene::{Object, Scene, Shape};
use super::shapes::Quadratic;
use super::vec::f;
use super::Math;
use crate::num::Scalar;

/// Side of a culling tile in pixels: small enough that a tile's rays stay within a
/// narrow cone, large enough that the lists cost nothing next to the frame.
pub const TILE: u32 = 16;

/// Angular slack (radians) on top of a bound's angular radius: far above the direction
/// error of any admitted format (2⁻¹⁶ per component in Q16.16 is 1.5·10⁻⁵ rad).
const ANGLE_SLACK: f64 = 2e-3;
/// Relative widening of every bounding sphere.
const RADIUS_SLACK: f64 = 0.02;
/// Largest relative error of the kernel's √ for which culling stays exact (the seed's
/// PRE_S + 2 Newton–Raphson steps, ≈ 10 %, is tested exhaustively).
pub const MAX_SQRT_ERROR: f64 = 1e-3;

/// Radius of the object-space bounding sphere about the origin, None for unbounded shapes.
fn object_radius(shape: Shape) -> Option<f64> {
    match shape {
        Shape::Plane => None,
        // x² + z² = (y − 1)², y ∈ [0, 1]: the apex and the base rim are both at distance 1
        Shape::Sphere | Shape::Disk | Shape::Cone => Some(1.0),
        Shape::Square | Shape::Cylinder => Some(std::f64::consts::SQRT_2),
        Shape::Cube => Some(3f64.sqrt()),
    }
}

/// World-space bounding sphere (centre, radius) of an object: M = T·R·S maps the
/// origin-centred object bound to a sphere about the translation whose radius is scaled
/// by the largest scale factor (rotation keeps it).
pub fn world_bound(o: &Object) -> Option<([f64; 3], f64)> {
    let r = object_radius(o.shape)?;
    let s = o.scale.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    Some((o.translate, r * s))
}

/// A bounded object's culling sphere, for a format the culling admits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    /// Centre of the culling sphere in world units (after the object's transform).
    pub centre: [f64; 3],
    /// Radius, widened by `RADIUS_SLACK`.
    pub radius: f64,
    /// Secondary (shadow and reflected) rays: distance from the centre within which a ray
    /// origin keeps the error model's guarantee for any ray direction; rays from farther
    /// away are tested exhaustively, since a badly rounded or saturated term could invent
    /// a hit the geometry does not have. 0 when no origin qualifies (the cylinder and cone
    /// in fixed point, whose error grows without bound for rays along the axis or a
    /// generator, which the sphere test alone cannot see: they have [`Secondary`]).
    pub safe_distance: f64,
    /// Primary rays: the gate evaluated at the camera position, None when the tiles must
    /// always list the object.
    pub primary: Option<Primary>,
    /// Secondary rays against a fixed-point cylinder or cone: the per-ray gate on |a|
    /// under which they are culled after all (within its own safe distance); None for
    /// every other object and format.
    pub secondary: Option<Secondary>,
}

/// The secondary-ray gate of a fixed-point cylinder or cone.
///
/// **Why a gate.** The Stable quadratic's error grows as 1/|a| (a = d′ₓ² + d′z² for the
/// cylinder, d′ₓ² − d′ᵧ² + d′z² for the cone, d′ the object-space direction), and fixed
/// point's absolute step gives no floor to |a| (a ray along the axis or a generator makes
/// it ≈ 0: `tests/rt_cull.rs` pins a real Q16.16 false hit there). The sphere pretest
/// cannot see the direction, so without a gate these objects are never culled for
/// shadow and reflected rays. The gate lets a ray through to the sphere test only where
/// its own |a| is large enough for the error model: a ray is culled when it misses the
/// sphere from within `safe_distance` **and** the pretest's f32 value of |dᵀFd| is at
/// least `a_min` **and** its f32 |d|² is within [`GATE_DD`] (|d| ∈ (0.9, 1.1)).
///
/// **The threshold.** `bounds` picks the smallest |a| (`a_model`) at which `Model`
/// admits every origin within a distance that covers the scene's other objects and the
/// eye (`reach`; shortened where the model cannot reach it), for any direction in the
/// window, with |a| taken as an absolute lower bound as in the primary gate's model.
/// `safe_distance` is then the farthest origin that `a_model` admits. The pretest
/// compares a different number with `a_model`, so `a_min` is `a_model` plus two margins:
///
/// - the datapath's object-space direction d̂′ = M̂⁻¹d is M⁻¹d off by
///   ε ≤ 3e(1/smin)|d| (M⁻¹ rounded entry by entry, ‖ΔM⁻¹‖₂ ≤ ‖ΔM⁻¹‖_F ≤ 3e) plus
///   √3·e(3|d|/smin) (each component rounded once), so with |d′| ≤ |d|/smin and ‖J‖ = 1,
///   |a(d̂′) − dᵀFd| ≤ 2ε|d|/smin + ε²;
/// - the pretest's value: d rounded to f32 (relative 2⁻²⁴ per component, two factors),
///   F rounded to f32 (one), the six products d_i·d_j (one rounding each, formed once per
///   ray by the pretest), six coefficient products and five sums (at most six roundings on
///   any term): at most 10 roundings of u = 2⁻²⁴ on each term, so the error is at most
///   (1 + u)¹⁰ − 1 < 10.01u times Σ|F_ij||d_i||d_j| ≤ ‖F‖_F·|d|² (Cauchy–Schwarz). The
///   model uses 16u (room for the f64 evaluation of F and the f32 threshold's own
///   rounding, which `pretest` rounds up), |d| < 1.1(1 + 2⁻²⁰) (the window, widened by
///   the rounding of d and of the f32 |d|², < 6u), and an absolute 2⁻¹²⁰·(1 + ‖F‖_F) for
///   f32 underflow.
///
/// The first margin is about 1 % of `a_model` in Q16.16 (the format's step against
/// |a| ≈ 0.07), the second 10⁻⁶ of it; they are there because a ray exactly at the gate
/// must not be culled on a rounding.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Secondary {
    /// World-space quadratic form F = M⁻ᵀ·J·M⁻¹ (J = diag(1, 0, 1) for the cylinder,
    /// diag(1, −1, 1) for the cone): a = dᵀFd for a world direction d.
    pub form: [[f64; 3]; 3],
    /// Threshold on the pretest's f32 |dᵀFd|: `a_model` plus both margins.
    pub a_min: f64,
    /// The |a| at which the model admits `safe_distance` (for tests and docs).
    pub a_model: f64,
    /// Distance from the centre within which a gated ray's origin keeps the model's
    /// guarantee (as [`Bound::safe_distance`] for the other objects).
    pub safe_distance: f64,
}

/// The primary-ray gate of a [`Bound`]. Primary rays all start at the eye, so the model
/// is evaluated once at the eye's object-space distance; the cylinder's and cone's error
/// also depends on the ray's leading coefficient `a` (d′ along the axis or a generator
/// makes `a` → 0), which a tile's narrow cone of directions bounds from below.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Primary {
    /// World-space quadratic form Q with a = dᵀQd for a world direction d (cylinder
    /// M⁻ᵀ·diag(1, 0, 1)·M⁻¹, cone M⁻ᵀ·diag(1, −1, 1)·M⁻¹); None when the shape's error
    /// does not depend on `a`.
    pub form: Option<[[f64; 3]; 3]>,
    /// Upper bound of ‖Q‖₂ (its Frobenius norm): |a(d) − a(c)| ≤ 2‖Q‖·∠(d, c) for unit d, c.
    pub form_norm: f64,
    /// Smallest |a| at which the model admits the eye's distance (with an allowance for
    /// the format's rounding of d′ = M⁻¹d: of M⁻¹ and of the products).
    pub a_min: f64,
}

/// The culling spheres of a scene's objects in format `S` with the kernel's `math`:
/// `None` for an unbounded object (never culled) and for every object when the format
/// does not admit culling. The format must declare its rounding ([`Scalar::rounding`])
/// and be fine enough that its errors stay far below the slack: f64, f32, Q16.16, Q8.24
/// and Q32.32 are admitted, f16 (2⁻¹¹) and Q24.8 (2⁻⁸) are always tested exhaustively.
///
/// With [`Quadratic::Stable`] each object is gated by the per-shape error model
/// (`Model`, whose docs derive it); with [`Quadratic::Textbook`] (the seed's b² − 4ac)
/// by the older, shape-blind discriminant model (`textbook_safe_distance`).
pub fn bounds<S: Scalar>(scene: &Scene, math: &Math) -> Vec<Option<Bound>> {
    let rounding = match S::rounding() {
        Some((rel, abs)) if rel <= 2f64.powi(-20) && abs <= 2f64.powi(-14) => Some((rel, abs)),
        _ => None,
    };
    // a negative bias admits hits behind the origin, where the miss argument says nothing
    let rounding = rounding.filter(|_| scene.bias >= 0.0);
    let range = S::max_value().to_f64();
    let eye = scene.camera.position;
    scene
        .objects
        .iter()
        .map(|o| {
            let (rel, abs) = rounding?;
            let (centre, r) = world_bound(o)?;
            let smin = o.scale.iter().fold(f64::INFINITY, |m, v| m.min(v.abs()));
            let smax = o.scale.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if !(smin > 0.0 && smax / smin <= MAX_ANISOTROPY) {
                return None;
            }
            let cmax = centre.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            // origins farther than this would saturate their own world coordinates
            let world_cap = range / 2.0 - cmax;
            let radius = r * (1.0 + RADIUS_SLACK);
            let eye_dist = f::sub(eye, centre);
            let eye_dist = f::dot(eye_dist, eye_dist).sqrt();
            let fixed = rel == 0.0;
            let quadric = matches!(o.shape, Shape::Cylinder | Shape::Cone);
            let bound = match math.quadratic {
                Quadratic::Textbook => {
                    // b² − 4ac in fixed point breaks down for a → 0 as the Stable form
                    // does (see `safe_distance`): no culling of the quadrics there
                    if fixed && quadric {
                        return None;
                    }
                    if abs > 0.0 && smax * smax * abs > BUDGET {
                        return None;
                    }
                    let safe =
                        (textbook_safe_distance(rel, abs, range, smin, smax) * smin).min(world_cap);
                    if !(safe.is_finite() && safe > 0.0) {
                        return None;
                    }
                    Bound {
                        centre,
                        radius,
                        safe_distance: safe,
                        primary: (eye_dist <= safe).then_some(Primary {
                            form: None,
                            form_norm: 0.0,
                            a_min: 0.0,
                        }),
                        secondary: None,
                    }
                }
                Quadratic::Stable => {
                    let f = Fmt {
                        rel,
                        abs,
                        sqrt_rel: math.sqrt.max_rel_error(),
                        range,
                    };
                    let m = Model::new(o, f, smin, smax);
                    let (safe, secondary) = if fixed && quadric {
                        (
                            0.0,
                            m.secondary(world_cap, reach(scene, centre, r, eye_dist)),
                        )
                    } else {
                        (m.safe_distance(world_cap), None)
                    };
                    let primary = if eye_dist <= world_cap {
                        m.primary(eye)
                    } else {
                        None
                    };
                    if safe <= 0.0 && primary.is_none() && secondary.is_none() {
                        return None;
                    }
                    Bound {
                        centre,
                        radius,
                        safe_distance: safe,
                        primary,
                        secondary,
                    }
                }
            };
            Some(bound)
        })
        .collect()
}

/// How far from an object's centre `c` (bound radius `r`) the scene's secondary rays
/// start, as far as the scene says: the far side of every bounded object's bound, and
/// the eye's distance as a stand-in for the visible part of the unbounded planes. This
/// only picks where the secondary gate is set ([`Model::secondary`]); origins beyond the
/// safe distance are tested in full, so a wrong guess costs speed, never an image.
fn reach(scene: &Scene, c: [f64; 3], r: f64, eye_dist: f64) -> f64 {
    scene
        .objects
        .iter()
        .filter_map(world_bound)
        .map(|(cj, rj)| {
            let v = f::sub(cj, c);
            f::dot(v, v).sqrt() + rj * (1.0 + RADIUS_SLACK)
        })
        .fold(eye_dist.max(r), f64::max)
}

/// The discriminant's margin at a miss by the slack (≈ 0.16a) over the error constant
/// (16) and a factor 4 to spare, as a fraction of a = |d′|².
const BUDGET: f64 = 0.16 / 16.0 / 4.0;

/// Largest ratio of an object's scale factors for which it is culled: a strongly
/// anisotropic transform makes the object-space ray ill-conditioned (large |o′| along
/// the thin axis), and the datapath's answer is then no longer the geometry's.
pub const MAX_ANISOTROPY: f64 = 16.0;

/// The Textbook quadratic's model (the seed's b² − 4ac): the largest object-space origin
/// distance |o′| at which a ray (unit direction) that misses the widened bound still gets
/// "no hit" from the format's arithmetic, with a factor 4 to spare.
/// A miss by the slack leaves the unit shape's discriminant at −4a·((1 + slack)² − 1) ≈
/// −0.16a, a = |d′|² ≥ 1/smax²; the discriminant's rounding error is about 16·rel·a·|o′|²
/// in floating point and 16·abs·|d′||o′|(|d′| + |o′|) in fixed point (each of b², 4ac
/// carries the input roundings through two products). Saturation: b² and 4ac must stay
/// below range/2.
fn textbook_safe_distance(rel: f64, abs: f64, range: f64, smin: f64, smax: f64) -> f64 {
    let budget = BUDGET;
    let dmax = 1.0 / smin;
    let by_rel = if rel > 0.0 {
        (budget / rel).sqrt()
    } else {
        f64::INFINITY
    };
    // abs·|o′|(|o′| + dmax) ≤ budget·|d′|min = budget/smax
    let by_abs = if abs > 0.0 {
        let k = budget / (abs * smax);
        (-dmax + (dmax * dmax + 4.0 * k).sqrt()) / 2.0
    } else {
        f64::INFINITY
    };
    let by_range = (range / 8.0).sqrt() / (1.0 + dmax) - 1.0;
    by_rel.min(by_abs).min(by_range)
}

/// Safety factor of the Stable model: every error bound below is multiplied by it before
/// it is compared with the miss margin. The bounds already take each rounding at its
/// worst (a full step for a rounded-to-nearest result, every product at its largest
/// magnitude); the factor covers what the first-order expansions leave out (products of
/// two errors, the hit point's own small offset from the shape in the magnitudes).
pub const SAFETY: f64 = 4.0;

/// The window of the pretest's f32 |d|² within which a ray may pass a [`Secondary`]
/// gate: |d| ∈ (0.9, 1.1). The kernel's shadow and reflected directions are unit to the
/// √'s accuracy (culling requires ≤ 10⁻³) and the format's rounding, so every real ray
/// is inside; the narrow window (against the sphere test's (½, 2)) halves the model's
/// far-hit parameter t ≤ W/|d| and lets the gate reach twice as far.
pub const GATE_DD: (f32, f32) = (0.81, 1.21);

/// Smallest conditioning κ = |a|/|d′|² assumed for secondary rays against a cylinder or
/// cone in floating point (rays within ≈ 2° of the axis, or of a generator, have less).
/// Floating-point errors are relative, so the terms that grow as 1/κ all carry `rel`:
/// at κ = 1/16 they are far below the margin in f32 at the distances admitted, and the
/// near-degenerate rays are covered by the exhaustive probes in `tests/rt_cull.rs`. Fixed
/// point has no such floor (its absolute step makes a ≈ 0 meaningless: a real
/// counter-example is in that test), so its quadrics are culled for secondary rays only
/// behind a per-ray gate on |a| ([`Secondary`]), which the pretest evaluates.
const FLOAT_KAPPA: f64 = 1.0 / 16.0;

/// The format as the model sees it: one operation whose exact result has magnitude m is
/// off by at most rel·m + abs ([`Scalar::rounding`]; for fixed point `abs` is a full step,
/// which covers the truncating `*` as well as the rounded `dot2`/`dot3`).
#[derive(Debug, Clone, Copy)]
struct Fmt {
    rel: f64,
    abs: f64,
    /// Relative error of the kernel's √ on top of the format's rounding.
    sqrt_rel: f64,
    range: f64,
}

impl Fmt {
    fn e(&self, m: f64) -> f64 {
        self.rel * m + self.abs
    }
}

/// What the model knows about a ray in the object's space.
#[derive(Debug, Clone, Copy)]
struct Ray {
    /// |o′| (upper bound).
    l: f64,
    /// Bounds of |d′|.
    dlo: f64,
    dhi: f64,
    /// Lower bound of |a| (cylinder, cone; unused otherwise): absolute, or (`kappa`) as
    /// a fraction κ of |d′|².
    a: f64,
    kappa: bool,
    /// World distance of the origin from the object's translation.
    w: f64,
    /// Bounds of the world direction's length.
    dwlo: f64,
    dw: f64,
}

impl Ray {
    /// Lower bound of |a| over the ray's |d′| range.
    fn a_lo(&self) -> f64 {
        if self.kappa {
            self.a * self.dlo * self.dlo
        } else {
            self.a
        }
    }
    /// Upper bound of the hit's t: the hit point lies within R of the object's origin in
    /// object space and within R·smax of its centre in the world.
    fn t_max(&self, r: f64, smax: f64) -> f64 {
        ((self.l + 2.0 * r) / self.dlo).min((self.w + 2.0 * r * smax) / self.dwlo)
    }
}

const SQRT2: f64 = std::f64::consts::SQRT_2;
const SQRT3: f64 = 1.732_050_807_568_877_2;

/// The Stable quadratic's error model for one object.
///
/// **The argument.** A culled ray's exact line, for every t ≥ 0, stays outside the world
/// bound (radius (1 + slack)·R·smax), hence in object space outside the ball of radius
/// (1 + slack)·R about the origin (M maps the ball of radius (1 + slack)R into the world
/// bound). R is the shape's object-space bounding radius: every point of the shape lies
/// within R. A datapath hit at t̂ ≥ bias ≥ 0 puts the exact ray's point p(t̂) within
/// `stable_error` of radius R, so the hit is impossible when SAFETY × that error is below
/// the margin slack·R: no hit is lost by skipping the object. The error has two parts:
///
/// - **The ray's own rounding** ([`Model::input_error`]): the datapath's object-space ray
///   is M⁻¹ rounded entry by entry (error e(1/smin) each, ‖·‖₂ ≤ 3e) times o − T (T
///   rounded) and times d, each component a dot3 rounded once. The origin moves by εo ≈
///   3e(1/smin)·W + √3·e(3W/smin), the direction by εd ≈ 3e(1/smin)·|d| + √3·e(3|d|/smin),
///   and the point at the hit's t ≤ (|o′| + 2R)/|d′| by εo + t·εd: **linear in |o′|**
///   (the old model was quadratic because it charged b² − 4ac).
/// - **The shape's decision** ([`Model::shape_error`]), on the datapath's ray taken as
///   exact (per shape, below).
///
/// Quadrics (sphere, cylinder, cone), g(t) = a t² + 2h t + c, g ≤ 0 inside. The datapath
/// computes â = a − α, ĥ = h + η, ĉ = c − γ and the quarter discriminant by Lagrange's
/// identity with error E, then the stable roots with √ error (ζ on ŝ²) and a division
/// error τ on t. A computed root t̂ is an exact root of â t² + 2ĥ t + c̃ (c̃ the c implied
/// by the computed discriminant) up to ζ/â; substituting gives
///   |g(t̂)| ≤ α|t̂|·Σ + |η|·Σ + (E + ζ)/|a| + 2|a t̂ + h|·τ + 2γ,
/// where Σ = 2√Δ′/|a| is the roots' spread (the α and η terms are α·t̂(t̂ − t_other) and
/// 2η(t̂ − t_mid), so they scale with the spread, not with c/a or h/a). At a hit near
/// the shape √Δ′ ≤ |d′|·|p₀| (p₀ the hit point; the Plücker moment d′ × p is the same
/// for any point of the line, which is why the Lagrange form's terms are O(|d′|), not
/// O(|d′||o′|): only their rounding scales with |o′|, linearly). |p(t̂)|² then exceeds
/// the shape's R² by at most |g(t̂)| (+ the height test's error for cylinder and cone),
/// i.e. |p| by ≈ |g|/(2R).
///
/// For the sphere |a| = |d′|² ≥ 1/smax². For the cylinder (a = |d′ₓ,z|²) and cone
/// (a = d′ₓ² − d′ᵧ² + d′z²) a can be arbitrarily small; the bound grows as 1/|a| in fixed
/// point (its step is absolute), so primary rays are gated per tile on a lower bound of
/// |a| ([`Primary`]) and secondary rays per ray ([`Secondary`]).
///
/// Plane shapes (disk, square): t̂ = −ôy/d̂y has a division error e(t); at t̂ the exact
/// |y| ≤ |d′|·e(t), and x̂ = ox + dx·t̂ is off by e(|d′|t) + e(|o′| + 2): the error is a
/// few steps, independent of |o′| (beyond the input part). Cube: each slab parameter is
/// off by e(1 + |o′|)/|dₐ| + e(t), so every coordinate of p(t̂) is within
/// e(1 + |o′|) + |d′|·e(t) of [−1, 1].
///
/// Saturation: every intermediate (|d′|(|o′| + 2), (|o′| + 2)², |d′|², t) must stay
/// below range/4; a saturated value could only turn a hit into a miss there (clipped
/// squares, t clipped to the far limit) but the model does not rely on it.
#[derive(Debug, Clone, Copy)]
struct Model {
    shape: Shape,
    f: Fmt,
    smin: f64,
    smax: f64,
    /// The shape's bounding radius R.
    r: f64,
    /// |T|.
    tmag: f64,
    minv: [[f64; 3]; 3],
    translate: [f64; 3],
}

impl Model {
    fn new(o: &Object, f: Fmt, smin: f64, smax: f64) -> Model {
        let rot = f::rotation(o.rotate);
        let sinv = f::diag(o.scale.map(|s| 1.0 / s));
        Model {
            shape: o.shape,
            f,
            smin,
            smax,
            r: object_radius(o.shape).unwrap_or(f64::INFINITY),
            tmag: f::dot(o.translate, o.translate).sqrt(),
            minv: f::mul(sinv, f::transpose(rot)),
            translate: o.translate,
        }
    }

    /// Displacement of the datapath's object-space ray from the exact one at the hit.
    fn input_error(&self, ray: &Ray) -> f64 {
        let f = &self.f;
        let em = f.e(1.0 / self.smin);
        let eo = 3.0 * em * ray.w
            + SQRT3 / self.smin * (f.e(self.tmag) + f.e(ray.w))
            + SQRT3 * f.e(3.0 * ray.w / self.smin);
        let ed = 3.0 * em * ray.dw + SQRT3 * f.e(3.0 * ray.dw / self.smin);
        eo + ray.t_max(self.r, self.smax) * ed
    }

    /// How far outside radius R the exact point of a datapath hit can lie, for the
    /// datapath's ray taken as exact (see the type's docs for each shape).
    fn shape_error(&self, ray: &Ray) -> f64 {
        let f = &self.f;
        let (l, dlo, dhi) = (ray.l, ray.dlo, ray.dhi);
        let t = ray.t_max(self.r, self.smax);
        let tau = f.e(t);
        // the height test's ŷ = oy + dy·t̂: one product and one sum
        let ey = f.e(dhi * t) + f.e(l + 2.0);
        // √ of a magnitude-s value: its rounding and the kernel's √ error; ζ on ŝ²
        let zeta = |s: f64| {
            let es = f.e(s) + f.sqrt_rel * s;
            2.0 * s * es + es * es
        };
        match self.shape {
            Shape::Sphere => {
                // a = d·d (dot3), h = d·o (dot3), c = o·o − 1, d × o by dot2 per
                // component; at a hit |d × p₀| = |d|·|p₀| ≤ 1.05|d|
                let a = dlo * dlo;
                let alpha = f.e(3.0 * dhi * dhi);
                let eta = f.e(3.0 * dhi * l);
                let gamma = f.e(3.0 * (l * l + 1.0));
                let ex = f.e(2.0 * dhi * l);
                let mom = 1.05 * dhi + ex;
                let e = alpha + f.e(3.0 * mom * mom) + 2.0 * SQRT3 * mom * ex + 3.0 * ex * ex;
                let s = 1.05 * dhi;
                let spread = 2.0 * s / a;
                let g = alpha * t * spread
                    + eta * spread
                    + (e + zeta(s) + f.e(dhi * dhi)) / a
                    + 2.0 * s * tau
                    + 2.0 * gamma;
                g / 2.0
            }
            Shape::Cylinder => {
                // 2-D: a = dx² + dz² (two plain products), h and the moment by dot2;
                // the moment and √Δ′ are ≤ 1.05·√a at a hit, so each term is a power of
                // a: take each at its worse end of [a_lo, dhi²]
                let gamma = f.e(3.0 * (l * l + 1.0));
                let terms = |a: f64| {
                    let sa = a.sqrt();
                    let alpha = f.e(3.0 * a);
                    let eta = f.e(3.0 * sa * l);
                    let ex = f.e(3.0 * sa * l);
                    let mom = 1.05 * sa + ex;
                    let e = alpha + f.e(3.0 * mom * mom) + 2.0 * mom * ex + ex * ex + f.e(a);
                    let s = 1.05 * sa;
                    let spread = 2.0 * s / a;
                    [
                        alpha * t * spread,
                        eta * spread,
                        (e + zeta(s)) / a,
                        2.0 * s * tau,
                    ]
                };
                let (lo, hi) = (terms(ray.a_lo().min(dhi * dhi)), terms(dhi * dhi));
                let g = lo.iter().zip(&hi).map(|(x, y)| x.max(*y)).sum::<f64>() + 2.0 * gamma;
                // |p|² ≤ 1 + g + (1 + ey)², R = √2
                SQRT2 * (g + 2.0 * ey + ey * ey) / 4.0
            }
            Shape::Cone => {
                // from the apex p = o − (0, 1, 0), |p| ≤ |o′| + 1; a: three plain
                // products; h, c by dot3; three moment components by dot2 and their
                // squares by one dot3; at a hit the apex-relative point is within
                // √2·1.03 < 1.5, so each moment component and √Δ′ are ≤ 1.5|d|
                let p = l + 1.0;
                let a = ray.a_lo();
                let alpha = f.e(3.0 * dhi * dhi);
                let eta = f.e(3.0 * dhi * p);
                let gamma = f.e(3.0 * p * p);
                let ex = f.e(2.0 * dhi * p);
                let mom = 1.5 * dhi + ex;
                let e = f.e(9.0 * mom * mom) + 6.0 * mom * ex + 3.0 * ex * ex;
                let s = 1.5 * dhi;
                let spread = 2.0 * s / a;
                let g = alpha * t * spread
                    + eta * spread
                    + (e + zeta(s)) / a
                    + 2.0 * s * tau
                    + 2.0 * gamma;
                // y ∈ [−ey, 1 + ey], r² ≤ (1 − y)² + g: |p|² ≤ 1 + g + 2ey + 2ey², R = 1
                (g + 2.0 * ey + 2.0 * ey * ey) / 2.0
            }
            Shape::Disk | Shape::Square => {
                let ex = f.e(dhi * t) + f.e(l + 2.0);
                let test = if self.shape == Shape::Disk {
                    2.0 * f.e(1.1)
                } else {
                    0.0
                };
                dhi * tau + SQRT2 * ex + test
            }
            Shape::Cube => SQRT3 * (f.e(1.0 + l) + dhi * tau),
            Shape::Plane => f64::INFINITY,
        }
    }

    /// Whether the model guarantees "no hit" for a culled ray like `ray`. The bounds take
    /// every factor |d′| at its worse end, so the |d′| range is split into pieces of ratio
    /// ≤ 1.05 (each piece bounded on its own) instead of mixing its two ends.
    fn admits(&self, ray: &Ray) -> bool {
        let steps = ((ray.dhi / ray.dlo).ln() / 1.05f64.ln())
            .ceil()
            .clamp(1.0, 200.0) as i32;
        let k = (ray.dhi / ray.dlo).powf(1.0 / steps as f64);
        (0..steps).all(|i| {
            let dlo = ray.dlo * k.powi(i);
            let dhi = if i + 1 == steps { ray.dhi } else { dlo * k };
            self.admits_piece(&Ray { dlo, dhi, ..*ray })
        })
    }

    fn admits_piece(&self, ray: &Ray) -> bool {
        let t = ray.t_max(self.r, self.smax);
        let big = [
            ray.dhi * (ray.l + 2.0),
            (ray.l + 2.0) * (ray.l + 2.0),
            ray.dhi * ray.dhi,
            t,
            ray.dhi * t,
        ]
        .into_iter()
        .fold(0.0f64, f64::max);
        if big.is_nan() || big > self.f.range / 4.0 {
            return false;
        }
        let err = stable_error(self, ray);
        err.is_finite() && SAFETY * err <= RADIUS_SLACK * self.r
    }

    /// The largest world distance W (≤ `cap`) from which every secondary ray (world
    /// direction of length in (½, 2), as the pretest requires) is covered, or 0.
    fn safe_distance(&self, cap: f64) -> f64 {
        let sq = 1.0 + self.f.sqrt_rel;
        let (dlo, dhi) = (0.5 / self.smax / sq, 2.0 * sq / self.smin);
        let ray = |w: f64| Ray {
            l: w / self.smin,
            dlo,
            dhi,
            a: FLOAT_KAPPA,
            kappa: true,
            w,
            dwlo: 0.5 / sq,
            dw: 2.0 * sq,
        };
        // geometric bisection: the answer spans 10⁻³ (Q8.24, small objects) to 10⁹
        let (mut lo, mut hi) = (1e-6f64, cap.min(1e15));
        if cap.is_nan() || hi <= lo || !self.admits(&ray(lo)) {
            return 0.0;
        }
        if self.admits(&ray(hi)) {
            return hi;
        }
        for _ in 0..40 {
            let mid = (lo * hi).sqrt();
            if self.admits(&ray(mid)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// The secondary-ray gate of a fixed-point cylinder or cone ([`Secondary`]): the
    /// smallest |a| at which the model admits every origin within `need` (capped at
    /// `cap`) for any direction whose length is in the gate's window ([`GATE_DD`]), then
    /// the largest distance that |a| admits, and the margins of the pretest's f32
    /// evaluation on top. Where `need` is out of reach even at |a| = dlo²/2 (half the
    /// smallest |d′|² of a direction in the window: a higher threshold would stop most
    /// rays), the distance shrinks by steps of 0.8 until it is admitted. None when no
    /// distance beyond the bound is.
    fn secondary(&self, cap: f64, need: f64) -> Option<Secondary> {
        let j = match self.shape {
            Shape::Cylinder => [1.0, 0.0, 1.0],
            Shape::Cone => [1.0, -1.0, 1.0],
            _ => return None,
        };
        // the window on |d|, widened by f32's rounding of d and of |d|² (< 6·2⁻²⁴)
        let (dwlo, dw) = (
            f64::from(GATE_DD.0).sqrt() * (1.0 - 2f64.powi(-20)),
            f64::from(GATE_DD.1).sqrt() * (1.0 + 2f64.powi(-20)),
        );
        let (dlo, dhi) = (dwlo / self.smax, dw / self.smin);
        let ray = |w: f64, a: f64| Ray {
            l: w / self.smin,
            dlo,
            dhi,
            a,
            kappa: false,
            w,
            dwlo,
            dw,
        };
        let a_cap = dlo * dlo / 2.0;
        let mut need = need.min(cap);
        for _ in 0..20 {
            if need <= self.r * self.smax || self.admits(&ray(need, a_cap)) {
                break;
            }
            need *= 0.8;
        }
        if need.is_nan() || need <= self.r * self.smax || !self.admits(&ray(need, a_cap)) {
            return None;
        }
        // the model's error falls as |a| grows (and grows with the distance): bisect
        let (mut lo, mut hi) = (0.0f64, a_cap);
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if self.admits(&ray(need, mid)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let a_model = hi;
        // the same |a| may admit farther origins than `need`
        let (mut wlo, mut whi) = (need, cap.min(1e15));
        if self.admits(&ray(whi, a_model)) {
            wlo = whi;
        } else {
            for _ in 0..30 {
                let mid = (wlo * whi).sqrt();
                if self.admits(&ray(mid, a_model)) {
                    wlo = mid;
                } else {
                    whi = mid;
                }
            }
        }
        let form = self.form(j);
        let norm = form.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
        let datapath = self.datapath_a_error(dw);
        // the pretest's f32 evaluation
        let pretest = 16.0 * 2f64.powi(-24) * norm * dw * dw + 2f64.powi(-120) * (1.0 + norm);
        let a_min = a_model + datapath + pretest;
        // the pretest holds F and the threshold in f32: keep both far inside its range
        if !(a_min.is_finite() && norm < 1e30 && a_min < 1e30) {
            return None;
        }
        Some(Secondary {
            form,
            a_min,
            a_model,
            safe_distance: wlo,
        })
    }

    /// How far the datapath's a = d′ᵀJd′ can be from the exact one for a world direction
    /// of length at most `d`: d′ = M⁻¹d is rounded twice, in M⁻¹'s entries (‖ΔM⁻¹‖ ≤ 3e,
    /// so 3e·d) and in its dot products (√3·e at |d′| ≤ 3d/smin), so |Δd′| ≤ ε and
    /// |Δa| ≤ 2ε|d′| + ε² with |d′| ≤ d/smin (see `Secondary`).
    fn datapath_a_error(&self, d: f64) -> f64 {
        let eps = 3.0 * self.f.e(1.0 / self.smin) * d + SQRT3 * self.f.e(3.0 * d / self.smin);
        2.0 * eps * d / self.smin + eps * eps
    }

    /// The world-space quadratic form M⁻ᵀ·diag(j)·M⁻¹ of a cylinder or cone.
    fn form(&self, j: [f64; 3]) -> [[f64; 3]; 3] {
        let mut q = [[0.0; 3]; 3];
        for (r, row) in q.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = (0..3)
                    .map(|k| self.minv[k][r] * j[k] * self.minv[k][c])
                    .sum();
            }
        }
        q
    }

    /// The primary-ray gate at the eye: world directions of unit length (to the √'s
    /// accuracy and the format's rounding).
    fn primary(&self, eye: [f64; 3]) -> Option<Primary> {
        let rel = self.f.rel + self.f.sqrt_rel + 1e-3;
        let wv = f::sub(eye, self.translate);
        let w = f::dot(wv, wv).sqrt();
        let ov = [
            f::dot(self.minv[0], wv),
            f::dot(self.minv[1], wv),
            f::dot(self.minv[2], wv),
        ];
        let (dlo, dhi) = ((1.0 - rel) / self.smax, (1.0 + rel) / self.smin);
        let ray = |a: f64| Ray {
            l: f::dot(ov, ov).sqrt(),
            dlo,
            dhi,
            a,
            kappa: false,
            w,
            dwlo: 1.0 - rel,
            dw: 1.0 + rel,
        };
        let j = match self.shape {
            Shape::Cylinder => [1.0, 0.0, 1.0],
            Shape::Cone => [1.0, -1.0, 1.0],
            _ => {
                return self.admits(&ray(dlo * dlo)).then_some(Primary {
                    form: None,
                    form_norm: 0.0,
                    a_min: 0.0,
                })
            }
        };
        let amax = dhi * dhi;
        if !self.admits(&ray(amax)) {
            return None;
        }
        let (mut lo, mut hi) = (0.0f64, amax);
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if self.admits(&ray(mid)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        // Q = M⁻ᵀ J M⁻¹; the datapath's d′ = M⁻¹d is rounded in M⁻¹'s entries and in its
        // dot products, which moves a(d) by up to `datapath_a_error` for |d| ≤ 1 + rel
        // (before session 7 only the first rounding was allowed for: 6e/smin instead of
        // ≈ 9.5e/smin in fixed point, still inside the model's factor-4 margin)
        let q = self.form(j);
        let norm = q.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
        let slop = self.datapath_a_error(1.0 + rel);
        // the tiles bound a(d) for unit d; the datapath's |d| may be 1 − rel
        Some(Primary {
            form: Some(q),
            form_norm: norm,
            a_min: (hi * (1.0 + 1e-9) + slop) / ((1.0 - rel) * (1.0 - rel)),
        })
    }
}

/// The Stable model's error: how far outside the shape's bounding radius the exact
/// point of a datapath hit can be, for a ray as described ([`Model`] has the derivation).
fn stable_error(m: &Model, ray: &Ray) -> f64 {
    m.shape_error(ray) + m.input_error(ray)
}

/// Per-tile lists of the objects a primary ray of the tile can hit, in object order (the
/// order `closest` relies on for ties).
pub struct Tiles {
    cols: u32,
    /// Start of each tile's list in `objs`, plus one end marker.
    starts: Vec<u32>,
    objs: Vec<u16>,
}

impl Tiles {
    /// Lists for a `width`×`height` frame seen through `cam`.
    pub(super) fn new(bounds: &[Option<Bound>], cam: &Cam, width: u32, height: u32) -> Tiles {
        let cols = width.div_ceil(TILE);
        let rows = height.div_ceil(TILE);
        // per object: None = always a candidate, else (unit direction to centre, angular
        // radius, the primary gate's quadratic form and its minimum |a|)
        type Cone = ([f64; 3], f64, Option<([[f64; 3]; 3], f64, f64)>);
        let cones: Vec<Option<Cone>> = bounds
            .iter()
            .map(|b| {
                let b = b.as_ref()?;
                let p = b.primary.as_ref()?;
                let to_c = f::sub(b.centre, cam.eye);
                let dist = f::dot(to_c, to_c).sqrt();
                if dist <= b.radius {
                    return None; // the eye is inside the bound
                }
                Some((
                    f::normalize(to_c),
                    (b.radius / dist).asin(),
                    p.form.map(|q| (q, p.form_norm, p.a_min)),
                ))
            })
            .collect();
        // the image-plane point of pixel coordinates (px, py) as a world direction
        let dir = |px: f64, py: f64| {
            let x = (2.0 * px / width as f64 - 1.0) * cam.s * cam.a;
            let y = (1.0 - 2.0 * py / height as f64) * cam.s;
            f::normalize([
                cam.u[0] * x + cam.v[0] * y - cam.w[0],
                cam.u[1] * x + cam.v[1] * y - cam.w[1],
                cam.u[2] * x + cam.v[2] * y - cam.w[2],
            ])
        };
        let mut starts = Vec::with_capacity((cols * rows + 1) as usize);
        let mut objs = Vec::new();
        for ty in 0..rows {
            for tx in 0..cols {
                starts.push(objs.len() as u32);
                let (x0, y0) = ((tx * TILE) as f64, (ty * TILE) as f64);
                let (x1, y1) = (
                    ((tx + 1) * TILE).min(width) as f64,
                    ((ty + 1) * TILE).min(height) as f64,
                );
                let centre = dir((x0 + x1) / 2.0, (y0 + y1) / 2.0);
                // the tile's directions lie within `half` of the centre: angle sublevel
                // sets on the image plane are convex, so the corners bound the rectangle
                let half = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
                    .iter()
                    .map(|&(px, py)| angle(centre, dir(px, py)))
                    .fold(0.0f64, f64::max);
                for (k, b) in cones.iter().enumerate() {
                    let keep = match b {
                        None => true,
                        Some((c, alpha, form)) => {
                            angle(centre, *c) <= half + alpha + ANGLE_SLACK
                                || form.is_some_and(|(q, norm, a_min)| {
                                    // |a| over the tile's directions (and the datapath's,
                                    // within the slack) is at least |a(centre)| − 2‖Q‖φ
                                    let qc = [
                                        f::dot(q[0], centre),
                                        f::dot(q[1], centre),
                                        f::dot(q[2], centre),
                                    ];
                                    let a_lo = f::dot(centre, qc).abs()
                                        - 2.0 * norm * (half + ANGLE_SLACK);
                                    a_lo < a_min
                                })
                        }
                    };
                    if keep {
                        objs.push(k as u16);
                    }
                }
            }
        }
        starts.push(objs.len() as u32);
        Tiles { cols, starts, objs }
    }

    /// The candidates of the tile holding pixel (i, j).
    #[inline(always)]
    pub fn at(&self, i: u32, j: u32) -> &[u16] {
        let t = ((j / TILE) * self.cols + i / TILE) as usize;
        match (self.starts.get(t), self.starts.get(t + 1)) {
            (Some(&a), Some(&b)) => self.objs.get(a as usize..b as usize).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// Mean candidates per tile (for `--stats` and docs).
    pub fn mean_candidates(&self) -> f64 {
        let n = self.starts.len().saturating_sub(1);
        if n == 0 {
            0.0
        } else {
            self.objs.len() as f64 / n as f64
        }
    }
}

/// Angle between two unit vectors, robust near 0 and π.
fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let c = f::cross(a, b);
    f::dot(c, c).sqrt().atan2(f::dot(a, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obj(shape: Shape, t: [f64; 3], s: [f64; 3], r: [f64; 3]) -> Object {
        Object {
            shape,
            translate: t,
            scale: s,
            rotate: r,
            material: 0,
        }
    }

    #[test]
    fn bounds_contain_their_shapes() {
        // sample each shape's surface in object space and check the world bound holds it
        let shapes = [
            Shape::Sphere,
            Shape::Disk,
            Shape::Square,
            Shape::Cylinder,
            Shape::Cone,
            Shape::Cube,
        ];
        for shape in shapes {
            let o = obj(
                shape,
                [1.0, -2.0, 0.5],
                [0.5, 2.0, 1.5],
                [10.0, 35.0, -70.0],
            );
            let (c, r) = world_bound(&o).expect("bounded");
            let m = f::mul(f::rotation(o.rotate), f::diag(o.scale));
            for a in 0..24 {
                for b in 0..=12 {
                    let (th, y) = (a as f64 / 24.0 * std::f64::consts::TAU, b as f64 / 12.0);
                    let p = match shape {
                        Shape::Sphere => {
                            let ph = y * std::f64::consts::PI;
                            [ph.sin() * th.cos(), ph.cos(), ph.sin() * th.sin()]
                        }
                        Shape::Disk => [y * th.cos(), 0.0, y * th.sin()],
                        Shape::Square => [2.0 * y - 1.0, 0.0, (a as f64 / 12.0) - 1.0],
                        Shape::Cylinder => [th.cos(), 2.0 * y - 1.0, th.sin()],
                        Shape::Cone => [(1.0 - y) * th.cos(), y, (1.0 - y) * th.sin()],
                        _ => [2.0 * y - 1.0, if a % 2 == 0 { 1.0 } else { -1.0 }, 1.0],
                    };
                    let w = [
                        m[0][0] * p[0] + m[0][1] * p[1] + m[0][2] * p[2] + o.translate[0],
                        m[1][0] * p[0] + m[1][1] * p[1] + m[1][2] * p[2] + o.translate[1],
                        m[2][0] * p[0] + m[2][1] * p[1] + m[2][2] * p[2] + o.translate[2],
                    ];
                    let d = f::sub(w, c);
                    assert!(
                        f::dot(d, d).sqrt() <= r * (1.0 + 1e-12),
                        "{shape:?} point {p:?} outside its bound"
                    );
                }
            }
        }
        assert!(world_bound(&obj(Shape::Plane, [0.0; 3], [1.0; 3], [0.0; 3])).is_none());
    }

    #[test]
    fn angle_is_accurate_at_the_extremes() {
        assert!(angle([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]).abs() < 1e-15);
        assert!((angle([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]) - std::f64::consts::PI).abs() < 1e-15);
        let e = 1e-9f64;
        assert!((angle([1.0, 0.0, 0.0], f::normalize([1.0, e, 0.0])) - e).abs() < 1e-20);
    }
}
