//! The plan's pretest of a secondary (shadow or reflected) ray against every object's
//! culling sphere at once.
//!
//! Why lanes: a secondary ray used to test each object's sphere in turn, ~25 scalar f32
//! operations and three unpredictable branches per object, which came to 11 % of an f32
//! frame. The spheres are stored as a structure of arrays, eight to a block, and each
//! block is answered with branch-free lane-wise arithmetic that the compiler turns into
//! SIMD; the answer is a bit mask of the objects the ray may hit. Every lane performs the
//! same IEEE f32 operations in the same order as the scalar test did, so the mask is that
//! test's answer bit for bit (checked against [`may_hit_scalar`] in the tests below).
//!
//! The same test also runs the other way round ([`Spheres::misses`]): eight rays in
//! lanes (a packet's shadow rays) against one object, with the same operations, so each
//! lane's answer is its ray's pretest bit.
//!
//! A fixed-point cylinder or cone carries a gate on the ray's own quadratic coefficient
//! |a| = |dᵀFd| ([`super::cull::Secondary`]): its lane culls only where the sphere test
//! says "miss" and |a| is at least the gate's threshold. The coefficient is six products
//! per lane (the ray's d_i·d_j are formed once per mask word); a scene without gates skips
//! them.

use super::cull::{Bound, GATE_DD};
use crate::num::Scalar;

use super::vec::V3;
use wide::{f32x4, f32x8, CmpGe, CmpGt, CmpLe, CmpLt};

/// Objects per block: one SSE register of f32.
const LANES: usize = 4;
/// Objects per mask word.
pub const CHUNK: usize = 64;

/// A secondary ray in f32 for the pretest, converted once per ray.
pub struct RayF32 {
    o: [f32; 3],
    d: [f32; 3],
    /// |d|²
    dd: f32,
    /// |o|₁, for the rounding allowance.
    omag: f32,
}

impl RayF32 {
    /// The ray o + t·d of the kernel's format, rounded to f32.
    #[inline(always)]
    pub fn new<S: Scalar>(o: V3<S>, d: V3<S>) -> Self {
        let g = |v: S| v.to_f64() as f32;
        let (o, d) = ([g(o.x), g(o.y), g(o.z)], [g(d.x), g(d.y), g(d.z)]);
        RayF32 {
            o,
            d,
            dd: d[0] * d[0] + d[1] * d[1] + d[2] * d[2],
            omag: o[0].abs() + o[1].abs() + o[2].abs(),
        }
    }

    /// The error analysis behind the bounds ([`super::cull::bounds`]) assumes a unit
    /// direction; a degenerate one (e.g. the normalisation of a zero vector) is tested
    /// against every object in full.
    #[inline(always)]
    fn unit(&self) -> bool {
        self.dd > 0.25 && self.dd < 4.0
    }
}

/// Four culling spheres, one per lane (padding lanes never cull).
#[derive(Clone, Copy)]
struct Block {
    cx: f32x4,
    cy: f32x4,
    cz: f32x4,
    /// Radius² (with the slack).
    r2: f32x4,
    /// Squared safe distance (capped so that an overflowed origin is never culled); a
    /// lane without a bound has −1, so that every ray is beyond it.
    safe2: f32x4,
    /// |c|₁, for the rounding allowance.
    cmag: f32x4,
    /// 1 for an unrotated flat object ([`Flat`]), else 0.
    flat: f32x4,
    /// Its plane's height T.y.
    ty: f32x4,
    /// The gate's form as coefficients of the ray's products ([`gate_products`]: F₀₀,
    /// F₁₁, F₂₂, 2F₀₁, 2F₀₂, 2F₁₂); 0 for a lane without a gate.
    f: [f32x4; 6],
    /// The gate's threshold on |a| (rounded up); −1 for a lane without a gate, which
    /// every ray passes (a unit ray's products are finite, so a = 0 there).
    amin: f32x4,
}

/// An unrotated flat object (plane, disk or square) for the side test: the height T.y of
/// its plane, the format's value rounded to f32.
///
/// Why it is exact: its test is t = −o′y/d′y with o′y = (o.y − T.y)·g and d′y = d.y·g
/// (g = 1/scale_y ≠ 0), and a hit needs t ≥ bias > 0. f32(o.y) > f32(T.y) implies
/// o.y > T.y in the format (rounding to f32 is monotonic), so o.y − T.y > 0 (a float
/// difference of distinct values is not zero; a fixed one is exact or saturates) and
/// o′y has the sign of g or is 0; f32(d.y) > 0 likewise gives d′y the sign of g or 0.
/// Same signs (or a zero) make the quotient ≥ 0 in every format (a fixed divider
/// truncates toward zero), so t ≤ 0 < bias: no hit. The mirror case (below the plane,
/// moving down) is the same. NaN compares false and is never culled. This removes the
/// floor from every shadow and reflected ray that leaves it upwards.
pub type Flat = Option<f32>;

/// One sphere's lane values, gathered before they are packed into [`Block`]s.
#[derive(Clone, Copy)]
struct Lane {
    c: [f32; 3],
    r2: f32,
    safe2: f32,
    cmag: f32,
    flat: Flat,
    f: [f32; 6],
    amin: f32,
}

const EMPTY: Lane = Lane {
    c: [0.0; 3],
    r2: 0.0,
    safe2: -1.0,
    cmag: 0.0,
    flat: None,
    f: [0.0; 6],
    amin: -1.0,
};

/// A bound's sphere test as the pretest holds it: its squared safe distance (−1: never
/// culled by the sphere) and its gate (coefficients and threshold; zeros and −1 without
/// one). A gated object's safe distance is the gate's own ([`super::cull::Secondary`]).
fn lane_gate(b: &Bound) -> (f32, [f32; 6], f32) {
    let sq = |d: f64| (d * d).min(1e30) as f32;
    if b.safe_distance > 0.0 {
        return (sq(b.safe_distance), [0.0; 6], -1.0);
    }
    match &b.secondary {
        Some(g) if g.safe_distance > 0.0 => {
            let q = &g.form;
            let f = [
                q[0][0],
                q[1][1],
                q[2][2],
                2.0 * q[0][1],
                2.0 * q[0][2],
                2.0 * q[1][2],
            ]
            .map(|v| v as f32);
            // rounded up: f32(x·(1 + 2⁻²²)) ≥ x for x above f32's normal range's floor
            let amin = (g.a_min * (1.0 + 2f64.powi(-22))) as f32;
            (sq(g.safe_distance), f, amin)
        }
        // no origin qualifies: as unbounded (never culled by the sphere)
        _ => (-1.0, [0.0; 6], -1.0),
    }
}

/// Every object's culling sphere, in blocks of [`LANES`].
pub struct Spheres {
    len: usize,
    blocks: Vec<Block>,
    /// The same values object by object, for [`Spheres::misses`].
    lanes: Vec<Lane>,
    /// False when no object has a bound: every ray tests every object, without the
    /// pretest's arithmetic.
    any: bool,
    /// True when some lane has a gate: only then does the pretest evaluate the forms.
    gated: bool,
}

impl Spheres {
    /// The spheres of `bounds` (None: not culled by a sphere) and the side tests of
    /// `flats` (one per object; None: no side test). An object with neither is always
    /// tested.
    pub fn new(bounds: &[Option<Bound>], flats: &[Flat]) -> Spheres {
        let lanes: Vec<Lane> = bounds
            .iter()
            .enumerate()
            .map(|(k, b)| {
                let flat = flats.get(k).copied().flatten();
                match b {
                    None => Lane { flat, ..EMPTY },
                    Some(b) => {
                        let (safe2, f, amin) = lane_gate(b);
                        Lane {
                            c: b.centre.map(|v| v as f32),
                            r2: (b.radius * b.radius) as f32,
                            safe2,
                            cmag: b.centre.iter().map(|v| v.abs()).sum::<f64>() as f32,
                            flat,
                            f,
                            amin,
                        }
                    }
                }
            })
            .collect();
        let blocks = lanes
            .chunks(LANES)
            .map(|ch| {
                let get = |f: &dyn Fn(&Lane) -> f32| {
                    f32x4::new(core::array::from_fn(|l| f(ch.get(l).unwrap_or(&EMPTY))))
                };
                Block {
                    cx: get(&|l| l.c[0]),
                    cy: get(&|l| l.c[1]),
                    cz: get(&|l| l.c[2]),
                    r2: get(&|l| l.r2),
                    safe2: get(&|l| l.safe2),
                    cmag: get(&|l| l.cmag),
                    flat: get(&|l| if l.flat.is_some() { 1.0 } else { 0.0 }),
                    ty: get(&|l| l.flat.unwrap_or(0.0)),
                    f: core::array::from_fn(|i| get(&|l| l.f[i])),
                    amin: get(&|l| l.amin),
                }
            })
            .collect();
        Spheres {
            len: bounds.len(),
            blocks,
            any: lanes.iter().any(|l| l.safe2 >= 0.0 || l.flat.is_some()),
            gated: lanes.iter().any(|l| l.amin >= 0.0),
            lanes,
        }
    }

    /// Number of mask words ([`CHUNK`] objects each).
    #[inline(always)]
    pub fn chunks(&self) -> usize {
        self.len.div_ceil(CHUNK)
    }

    /// Bit k set: the ray may hit object `CHUNK·chunk + k` and must be tested in full;
    /// clear only when it certainly misses the object's culling sphere. NaN and
    /// out-of-range origins answer "may hit".
    #[inline(always)]
    pub fn may_hit(&self, chunk: usize, r: &RayF32) -> u64 {
        let first = chunk * CHUNK;
        let n = self.len.saturating_sub(first).min(CHUNK);
        let all = if n == CHUNK {
            u64::MAX
        } else {
            (1u64 << n) - 1
        };
        if !self.any || !r.unit() {
            return all;
        }
        let mut culled = 0u64;
        let blocks = self.blocks.iter().skip(first / LANES).take(CHUNK / LANES);
        if self.gated {
            let p = gate_products(r);
            for (j, b) in blocks.enumerate() {
                culled |= (cull_lanes::<true>(b, r, &p) as u64) << (j * LANES);
            }
        } else {
            let p = [f32x4::ZERO; 6];
            for (j, b) in blocks.enumerate() {
                culled |= (cull_lanes::<false>(b, r, &p) as u64) << (j * LANES);
            }
        }
        all & !culled
    }
}

/// The ray's d_x², d_y², d_z², d_x·d_y, d_x·d_z, d_y·d_z (one rounding each, the same in
/// every lane) for the gates' quadratic forms, formed only when a scene has gates (an f32
/// frame has none and does not pay for them); all 0 when |d|² is outside the gates' window
/// ([`super::cull::GATE_DD`]), so that a = 0 passes the ungated lanes (threshold −1) and
/// fails every gate (threshold > 0). Formed in lanes: six scalar products stored and then
/// splatted reloaded them across stores (a failed store forward, 3 % of a Q16.16 frame).
#[inline(always)]
fn gate_products(r: &RayF32) -> [f32x4; 6] {
    if r.dd > GATE_DD.0 && r.dd < GATE_DD.1 {
        let (x, y, z) = (
            f32x4::splat(r.d[0]),
            f32x4::splat(r.d[1]),
            f32x4::splat(r.d[2]),
        );
        [x * x, y * y, z * z, x * y, x * z, y * z]
    } else {
        [f32x4::ZERO; 6]
    }
}

/// Lane-wise f32 arithmetic and ordered compares, as `wide` gives them for four and
/// eight lanes: the one [`cull_test`] serves both layouts (objects in lanes against one
/// ray, rays in lanes against one object).
trait Lanes:
    Copy
    + core::ops::Add<Output = Self>
    + core::ops::Sub<Output = Self>
    + core::ops::Mul<Output = Self>
    + core::ops::BitAnd<Output = Self>
    + core::ops::BitOr<Output = Self>
    + CmpLt<Output = Self>
    + CmpGt<Output = Self>
    + CmpLe<Output = Self>
{
    fn splat(x: f32) -> Self;
}

impl Lanes for f32x4 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x4::splat(x)
    }
}

impl Lanes for f32x8 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x8::splat(x)
    }
}

/// One sphere-and-side test, each value an object's or a ray's (splatted where the
/// other is in lanes).
struct Test<V> {
    /// The sphere: centre, radius², squared safe distance, |c|₁.
    c: [V; 3],
    r2: V,
    safe2: V,
    cmag: V,
    /// 1 for a flat object, and its plane's height.
    flat: V,
    ty: V,
    /// The ray: origin, direction, |d|², |o|₁.
    o: [V; 3],
    d: [V; 3],
    dd: V,
    omag: V,
}

/// The pretest's arithmetic (the scalar test's operations, without branches): where the
/// ray certainly misses the sphere, and where it leaves a flat object's plane.
#[inline(always)]
fn cull_test<V: Lanes>(t: &Test<V>) -> (V, V) {
    // `wide` maps each operation onto SSE (NEON, wasm SIMD, or plain arrays elsewhere):
    // every lane rounds exactly as scalar f32 does, and the compares are ordered (false
    // on NaN) exactly as Rust's `<`, `>`, `<=`.
    let s = V::splat;
    let (ox, oy, oz) = (t.c[0] - t.o[0], t.c[1] - t.o[1], t.c[2] - t.o[2]);
    let oc2 = ox * ox + oy * oy + oz * oz;
    let tca = ox * t.d[0] + oy * t.d[1] + oz * t.d[2];
    let near = oc2.cmp_le(t.safe2);
    // the centre behind the origin and the origin outside: every point of the sphere has
    // t < 0
    let behind = tca.cmp_lt(s(0.0)) & oc2.cmp_gt(t.r2);
    // squared distance of the line from the centre (times |d|²) beyond r²
    let mag = t.cmag + t.omag;
    let apart = (oc2 * t.dd - tca * tca).cmp_gt((t.r2 + s(1e-6) * mag * mag) * t.dd);
    // a flat object the ray leaves on its side of the plane ([`Flat`])
    let (y, dy, zero) = (t.o[1], t.d[1], s(0.0));
    let up = y.cmp_gt(t.ty) & dy.cmp_gt(zero);
    let down = y.cmp_lt(t.ty) & dy.cmp_lt(zero);
    let away = t.flat.cmp_gt(zero) & (up | down);
    (near & (behind | apart), away)
}

/// Bit l set: the ray certainly misses lane l's sphere. `GATE`: evaluate the lanes'
/// gates on the ray's products `p` (without it every lane must be ungated, which passes
/// every ray).
#[inline(always)]
fn cull_lanes<const GATE: bool>(b: &Block, r: &RayF32, p: &[f32x4; 6]) -> u8 {
    let s = f32x4::splat;
    let (sphere, away) = cull_test(&Test {
        c: [b.cx, b.cy, b.cz],
        r2: b.r2,
        safe2: b.safe2,
        cmag: b.cmag,
        flat: b.flat,
        ty: b.ty,
        o: r.o.map(s),
        d: r.d.map(s),
        dd: s(r.dd),
        omag: s(r.omag),
    });
    let sphere = if GATE {
        // |dᵀFd| at or above the gate (`cull::Secondary`); ungated lanes have a = 0 ≥ −1
        let a = b.f[0] * p[0]
            + b.f[1] * p[1]
            + b.f[2] * p[2]
            + b.f[3] * p[3]
            + b.f[4] * p[4]
            + b.f[5] * p[5];
        sphere & a.abs().cmp_ge(b.amin)
    } else {
        sphere
    };
    (sphere | away).move_mask() as u8
}

/// Eight f32 rays, one per lane, for [`Spheres::misses`]: a packet's shadow rays.
pub struct Rays8 {
    o: [f32x8; 3],
    d: [f32x8; 3],
    dd: f32x8,
    omag: f32x8,
    /// Lanes whose direction is near unit ([`RayF32::unit`]).
    unit: f32x8,
}

impl Rays8 {
    /// Rays o + t·d, lane by lane: |d|² and |o|₁ formed as [`RayF32::new`] forms them.
    #[inline(always)]
    pub fn new(o: [f32x8; 3], d: [f32x8; 3]) -> Self {
        let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        Rays8 {
            o,
            d,
            dd,
            omag: o[0].abs() + o[1].abs() + o[2].abs(),
            unit: dd.cmp_gt(f32x8::splat(0.25)) & dd.cmp_lt(f32x8::splat(4.0)),
        }
    }
}

impl Spheres {
    /// Lanes of `r` that certainly miss object `k`: the pretest's answer for each ray
    /// (its [`may_hit`](Self::may_hit) bit clear), with the rays in lanes instead of the
    /// objects. A gated object is culled only by its side test (a subset of what the
    /// pretest culls); an object beyond the list, never.
    #[inline(always)]
    pub fn misses(&self, k: usize, r: &Rays8) -> f32x8 {
        let Some(l) = self.lanes.get(k).filter(|_| self.any) else {
            return f32x8::ZERO;
        };
        let s = f32x8::splat;
        let (sphere, away) = cull_test(&Test {
            c: l.c.map(s),
            r2: s(l.r2),
            safe2: s(l.safe2),
            cmag: s(l.cmag),
            flat: s(if l.flat.is_some() { 1.0 } else { 0.0 }),
            ty: s(l.flat.unwrap_or(0.0)),
            o: r.o,
            d: r.d,
            dd: r.dd,
            omag: r.omag,
        });
        let sphere = if l.amin >= 0.0 { f32x8::ZERO } else { sphere };
        (sphere | away) & r.unit
    }
}

/// The same test on one sphere with branches, as the kernel did it before the lanes: the
/// reference the lanes are checked against.
#[cfg(test)]
fn may_hit_scalar(b: Option<&Bound>, flat: Flat, r: &RayF32) -> bool {
    if !r.unit() {
        return true;
    }
    if let Some(ty) = flat {
        let (y, dy) = (r.o[1], r.d[1]);
        if (y > ty && dy > 0.0) || (y < ty && dy < 0.0) {
            return false;
        }
    }
    b.is_none_or(|b| may_hit_sphere(b, r))
}

#[cfg(test)]
fn may_hit_sphere(b: &Bound, r: &RayF32) -> bool {
    let c = b.centre.map(|v| v as f32);
    let r2 = (b.radius * b.radius) as f32;
    // the gated quadrics' own safe distance
    let (safe, gate) = match b.secondary {
        Some(g) if b.safe_distance <= 0.0 => (g.safe_distance, Some(g)),
        _ => (b.safe_distance, None),
    };
    if safe <= 0.0 {
        return true;
    }
    let safe2 = (safe * safe).min(1e30) as f32;
    let cmag = b.centre.iter().map(|v| v.abs()).sum::<f64>() as f32;
    let oc = [c[0] - r.o[0], c[1] - r.o[1], c[2] - r.o[2]];
    let oc2 = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2];
    if oc2 > safe2 {
        return true;
    }
    if !(r.dd > 0.25 && r.dd < 4.0) {
        return true;
    }
    let tca = oc[0] * r.d[0] + oc[1] * r.d[1] + oc[2] * r.d[2];
    let behind = tca < 0.0 && oc2 > r2;
    let mag = cmag + r.omag;
    let apart = oc2 * r.dd - tca * tca > (r2 + 1e-6 * mag * mag) * r.dd;
    if !(behind || apart) {
        return true;
    }
    gate.is_some_and(|g| !steep_scalar(&g, r))
}

/// The gate of `cull::Secondary` on one ray in plain f32: the coefficients and their
/// order as the lanes hold them, the threshold rounded up the same way.
#[cfg(test)]
fn steep_scalar(g: &super::cull::Secondary, r: &RayF32) -> bool {
    if !(r.dd > GATE_DD.0 && r.dd < GATE_DD.1) {
        return false;
    }
    let q = &g.form;
    let f = [
        q[0][0] as f32,
        q[1][1] as f32,
        q[2][2] as f32,
        (2.0 * q[0][1]) as f32,
        (2.0 * q[0][2]) as f32,
        (2.0 * q[1][2]) as f32,
    ];
    let d = r.d;
    let p = [
        d[0] * d[0],
        d[1] * d[1],
        d[2] * d[2],
        d[0] * d[1],
        d[0] * d[2],
        d[1] * d[2],
    ];
    let a = f[0] * p[0] + f[1] * p[1] + f[2] * p[2] + f[3] * p[3] + f[4] * p[4] + f[5] * p[5];
    a.abs() >= (g.a_min * (1.0 + 2f64.powi(-22))) as f32
}

#[cfg(test)]
mod tests {
    use super::super::cull::Secondary;
    use super::*;
    use proptest::prelude::*;

    fn bound(c: [f64; 3], r: f64, safe: f64) -> Bound {
        Bound {
            centre: c,
            radius: r,
            safe_distance: safe,
            primary: None,
            secondary: None,
        }
    }

    /// A symmetric form from its six distinct entries.
    fn form(e: [f64; 6]) -> [[f64; 3]; 3] {
        [[e[0], e[3], e[4]], [e[3], e[1], e[5]], [e[4], e[5], e[2]]]
    }

    fn gate(e: [f64; 6], a_min: f64, safe: f64) -> Secondary {
        Secondary {
            form: form(e),
            a_min,
            a_model: a_min,
            safe_distance: safe,
        }
    }

    /// A bound's test object: maybe a sphere (centre, radius, safe distance, maybe a
    /// gate: form entries, threshold, safe distance), maybe a flat object's height.
    type Obj = (
        Option<([f64; 3], f64, f64, Option<([f64; 6], f64, f64)>)>,
        Option<f32>,
    );

    /// Bounded and unbounded objects, gated and not, flat and not.
    fn object() -> impl Strategy<Value = Obj> {
        (
            prop::option::weighted(
                0.8,
                (
                    prop::array::uniform3(-10.0f64..10.0),
                    0.01f64..5.0,
                    prop_oneof![4 => 0.5f64..50.0, 2 => Just(0.0)],
                    // a cylinder's or cone's gate (used where the safe distance is 0):
                    // forms of either sign, thresholds around the rays' |a|
                    prop::option::weighted(
                        0.5,
                        (
                            prop::array::uniform6(-2.0f64..2.0),
                            prop_oneof![4 => 0.001f64..3.0, 1 => 1e-30f64..1e-20],
                            prop_oneof![4 => 0.5f64..50.0, 1 => Just(0.0)],
                        ),
                    ),
                ),
            ),
            prop::option::weighted(0.3, prop_oneof![-3.0f32..3.0, Just(0.0f32)]),
        )
    }

    /// Any direction, or a near-unit one (where the gates apply, and their window's
    /// edges).
    fn direction() -> impl Strategy<Value = [f64; 3]> {
        prop_oneof![
            prop::array::uniform3(-1.5f64..1.5),
            (prop::array::uniform3(-1.0f64..1.0), 0.85f64..1.15).prop_map(|(v, l)| {
                let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-9);
                v.map(|x| x * l / n)
            }),
        ]
    }

    /// Origin coordinates: ordinary, NaN, huge.
    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            8 => -20.0f64..20.0,
            1 => Just(f64::NAN),
            1 => Just(1e30f64),
            1 => Just(-3e38f64),
        ]
    }

    /// The objects' spheres as the pretest holds them.
    fn spheres(objs: &[Obj]) -> (Vec<Option<Bound>>, Vec<Flat>, Spheres) {
        let bounds: Vec<Option<Bound>> = objs
            .iter()
            .map(|(b, _)| {
                b.map(|(c, r, s, g)| Bound {
                    secondary: g.map(|(e, a, gs)| gate(e, a, gs)),
                    ..bound(c, r, s)
                })
            })
            .collect();
        let flats: Vec<Flat> = objs.iter().map(|(_, f)| *f).collect();
        let sph = Spheres::new(&bounds, &flats);
        (bounds, flats, sph)
    }

    /// The lanes answer exactly what the scalar test answers, for any mix of bounded and
    /// unbounded objects, with and without gates (more than one block and more than one
    /// mask word included), NaN and huge origins, degenerate directions.
    #[test]
    fn lanes_match_the_scalar_test() {
        let cases = (
            prop::collection::vec(object(), 1..140),
            prop::array::uniform3(coordinate()),
            direction(),
        );
        proptest!(ProptestConfig::with_cases(600), |((objs, o, d) in cases)| {
            let (bounds, flats, sph) = spheres(&objs);
            let ray = RayF32::new(V3::new(o[0], o[1], o[2]), V3::new(d[0], d[1], d[2]));
            for (k, b) in bounds.iter().enumerate() {
                let mask = sph.may_hit(k / CHUNK, &ray);
                let want = may_hit_scalar(b.as_ref(), flats[k], &ray);
                prop_assert_eq!(mask >> (k % CHUNK) & 1 == 1, want, "object {}", k);
            }
            // no bit beyond the last object
            let last = sph.may_hit(sph.chunks() - 1, &ray);
            let n = bounds.len() - (sph.chunks() - 1) * CHUNK;
            prop_assert_eq!(if n == CHUNK { 0 } else { last >> n }, 0);
        });
    }

    /// Eight rays in lanes against one object at a time (`Spheres::misses`): every lane
    /// it culls the pretest culls too, and for an ungated object it culls exactly those.
    #[test]
    fn rays_in_lanes_match_the_pretest() {
        let ray = (prop::array::uniform3(coordinate()), direction());
        let cases = (
            prop::collection::vec(object(), 1..70),
            prop::array::uniform8(ray),
        );
        proptest!(ProptestConfig::with_cases(400), |((objs, rays) in cases)| {
            let (bounds, _, sph) = spheres(&objs);
            let rays = rays.map(|(o, d)| {
                RayF32::new(V3::new(o[0], o[1], o[2]), V3::new(d[0], d[1], d[2]))
            });
            let lane = |f: &dyn Fn(&RayF32) -> f32| f32x8::new(core::array::from_fn(|l| f(&rays[l])));
            let r8 = Rays8::new(
                [lane(&|r| r.o[0]), lane(&|r| r.o[1]), lane(&|r| r.o[2])],
                [lane(&|r| r.d[0]), lane(&|r| r.d[1]), lane(&|r| r.d[2])],
            );
            for (k, b) in bounds.iter().enumerate() {
                let culled = sph.misses(k, &r8).move_mask();
                let gated = b.is_some_and(|b| b.safe_distance <= 0.0 && b.secondary.is_some());
                for (l, one) in rays.iter().enumerate() {
                    let pretest = sph.may_hit(k / CHUNK, one) >> (k % CHUNK) & 1 == 0;
                    let lanes = culled >> l & 1 == 1;
                    prop_assert!(!lanes || pretest, "object {} ray {}: culled, pretest keeps it", k, l);
                    if !gated {
                        prop_assert_eq!(lanes, pretest, "object {} ray {}", k, l);
                    }
                }
            }
            // beyond the list: never culled
            prop_assert_eq!(sph.misses(bounds.len(), &r8).move_mask(), 0);
        });
    }

    /// A ray pointing away from a sphere it starts outside of is culled; one through its
    /// centre is not (the test is not vacuous).
    #[test]
    fn culls_what_it_should() {
        // a sphere ahead, an unbounded object, a floor below and a ceiling above
        let sph = Spheres::new(
            &[Some(bound([0.0, 0.0, -5.0], 1.0, 100.0)), None, None, None],
            &[None, None, Some(-1.0), Some(2.0)],
        );
        let at = |d: [f64; 3]| {
            sph.may_hit(
                0,
                &RayF32::new(V3::new(0.0, 0.0, 0.0), V3::new(d[0], d[1], d[2])),
            )
        };
        // level rays may hit both planes (they are not moving away from either)
        assert_eq!(at([0.0, 0.0, -1.0]), 0b1111);
        assert_eq!(at([0.0, 0.0, 1.0]), 0b1110);
        assert_eq!(at([1.0, 0.0, 0.0]), 0b1110);
        // up: away from the floor; down: away from the ceiling
        assert_eq!(at([0.0, 0.6, -0.8]), 0b1010);
        assert_eq!(at([0.0, -0.6, 0.8]), 0b0110);
    }

    /// A gated lane (a cylinder's form diag(1, 0, 1), threshold 0.1) culls a ray that
    /// misses its sphere only when the ray is far enough from the axis and of near-unit
    /// length; the same sphere without a gate culls them all.
    #[test]
    fn gates_stop_rays_along_the_axis() {
        let gated = Bound {
            secondary: Some(gate([1.0, 0.0, 1.0, 0.0, 0.0, 0.0], 0.1, 100.0)),
            ..bound([0.0, 0.0, -5.0], 1.0, 0.0)
        };
        let sph = Spheres::new(
            &[Some(gated), Some(bound([0.0, 0.0, -5.0], 1.0, 100.0))],
            &[None, None],
        );
        let at = |d: [f64; 3]| {
            sph.may_hit(
                0,
                &RayF32::new(V3::new(0.0, 0.0, 0.0), V3::new(d[0], d[1], d[2])),
            )
        };
        // along the axis (a = 0), just inside the gate (a = 0.09), well outside it
        assert_eq!(at([0.0, 1.0, 0.0]), 0b01);
        assert_eq!(at([0.3, 0.954, 0.0]), 0b01);
        assert_eq!(at([0.4, 0.9165, 0.0]), 0b00);
        assert_eq!(at([0.0, 0.0, 1.0]), 0b00);
        // a direction outside the window |d| ∈ (0.9, 1.1) never passes a gate
        assert_eq!(at([0.0, 0.0, 1.5]), 0b01);
        assert_eq!(at([0.0, 0.0, 0.85]), 0b01);
        // toward the sphere: tested, gate or not
        assert_eq!(at([0.0, 0.0, -1.0]), 0b11);
    }
}
