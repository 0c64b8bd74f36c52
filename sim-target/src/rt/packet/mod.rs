//! Primary rays traced in packets of eight: the f32 kernels' nearest-hit search for eight
//! neighbouring pixels at once, lane by lane the operations of the scalar kernel.
//!
//! Why packets: a primary ray's search runs every candidate object's intersection, a few
//! dozen dependent f32 operations and several unpredictable branches each, one ray at a
//! time. Eight pixels of one row share their tile's candidate list and the eye, so each
//! object is tested against all eight directions with branch-free lane-wise arithmetic
//! (`wide::f32x8`: AVX where the build enables it, two SSE halves otherwise, plain arrays
//! on other architectures). Where the hit's material is Lambert's term alone, the
//! shading and the shadow rays run in lanes too ([`shade`]); every other lane goes on
//! ray by ray in `trace`.
//!
//! Why bit for bit: every lane performs the same IEEE f32 operations in the same order as
//! the scalar code ([`super::shapes`], `V3::normalize`, `PObj::to_object`), each branch
//! becoming both sides and a select on the same comparison (ordered compares: false on
//! NaN, as Rust's `<`). The scalar kernel stays the oracle: the golden hashes and the
//! packet-against-scalar tests hold the two to the same frame.
//!
//! Only f32 gets packets. The fixed formats count every saturated result, and a packet
//! computes both sides of every branch: a lane the scalar code had left early could clip
//! and be counted. The other formats and the instrumented wrappers keep the scalar kernel.
//! So does a frame with a non-default square root or quadratic (`Math`), whose scalar
//! forms these lanes do not repeat.

use super::kernel::{rows_for, FrameCtx, Hit, Primary, Rendered, RowFn, RowOut, Rows};
use super::prepare::{PObj, Prepared};
use super::scene::Shape;
use super::shapes::Quadratic;
use super::{cull, ToneMap, V3};
use crate::num::SqrtKind;
use wide::{f32x8, CmpEq, CmpGe, CmpGt, CmpLe, CmpLt};

mod shade;

/// Rays per packet.
pub(super) const LANES: usize = 8;

// a packet's pixels must share one tile's candidates
const _: () = assert!((cull::TILE as usize).is_multiple_of(LANES));

type F = f32x8;

/// A lane mask: all ones where true (what `wide`'s compares return).
type M = f32x8;

/// A vector per lane.
#[derive(Clone, Copy)]
struct P3 {
    x: F,
    y: F,
    z: F,
}

/// An array of one value per lane, written out. Why not `std::array::from_fn` or
/// `map`: their closures stayed out of line behind the `try_` machinery underneath
/// (perf: 16 % of a frame in `call_mut` and `try_map`).
#[inline(always)]
fn per_lane<T>(mut f: impl FnMut(usize) -> T) -> [T; LANES] {
    [f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7)]
}

#[inline(always)]
fn sel(m: M, t: F, f: F) -> F {
    m.blend(t, f)
}

/// IEEE negation: the sign bit flipped. Why not `-x`: `wide`'s `Neg` is 0 − x, which
/// gives +0 for +0 and drops a NaN's sign, where f32's `-` gives −0.
#[inline(always)]
fn neg(x: F) -> F {
    x ^ F::splat(-0.0)
}

/// `composed::abs`: −x where x < 0 (so −0 stays −0, unlike a sign-bit clear).
#[inline(always)]
fn abs(x: F) -> F {
    sel(x.cmp_lt(F::ZERO), neg(x), x)
}

/// `composed::max`: x where x > o, else o.
#[inline(always)]
fn max(x: F, o: F) -> F {
    sel(x.cmp_gt(o), x, o)
}

/// `composed::min`: x where x < o, else o.
#[inline(always)]
fn min(x: F, o: F) -> F {
    sel(x.cmp_lt(o), x, o)
}

/// f32's `Scalar::sqrt`: √x for x > 0, else 0 (NaN included).
#[inline(always)]
fn sqrt(x: F) -> F {
    sel(x.cmp_gt(F::ZERO), x.sqrt(), F::ZERO)
}

impl P3 {
    #[inline(always)]
    fn splat(v: V3<f32>) -> Self {
        P3 {
            x: F::splat(v.x),
            y: F::splat(v.y),
            z: F::splat(v.z),
        }
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        P3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        P3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
    #[inline(always)]
    fn scale(self, s: F) -> Self {
        P3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
    /// `Scalar::dot3` of f32: (a·b + c·d) + e·f.
    #[inline(always)]
    fn dot(self, o: Self) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// `V3::cross2`: each component a `dot2` with the second product negated first.
    #[inline(always)]
    fn cross2(self, o: Self) -> Self {
        P3 {
            x: self.y * o.z + neg(self.z) * o.y,
            y: self.z * o.x + neg(self.x) * o.z,
            z: self.x * o.y + neg(self.y) * o.x,
        }
    }
    /// `V3::normalize` with the exact √: v·(1/√(v·v)), v itself where v·v ≤ 0, and
    /// v·f32::MAX where v·v is NaN (the scalar `rsqrt` of a non-positive argument).
    #[inline(always)]
    fn normalize(self) -> Self {
        let l2 = self.dot(self);
        let r = sel(l2.cmp_gt(F::ZERO), F::ONE / sqrt(l2), F::splat(f32::MAX));
        let n = self.scale(r);
        let keep = l2.cmp_le(F::ZERO);
        P3 {
            x: sel(keep, self.x, n.x),
            y: sel(keep, self.y, n.y),
            z: sel(keep, self.z, n.z),
        }
    }
    /// A direction's image in object space: `PObj::to_object(_, d).1`.
    #[inline(always)]
    fn to_object(self, ob: &PObj<f32>) -> Self {
        match ob.diag {
            Some(g) => P3 {
                x: self.x * F::splat(g.x),
                y: self.y * F::splat(g.y),
                z: self.z * F::splat(g.z),
            },
            None => {
                let m = &ob.minv.0;
                let row = |r: [f32; 3]| {
                    F::splat(r[0]) * self.x + F::splat(r[1]) * self.y + F::splat(r[2]) * self.z
                };
                P3 {
                    x: row(m[0]),
                    y: row(m[1]),
                    z: row(m[2]),
                }
            }
        }
    }
}

/// Where each lane hits (mask) and at which t.
type Lanes = (M, F);

/// `shapes::clearly_misses`.
#[inline(always)]
fn clearly_misses(a: F, h: F, c: F) -> M {
    let hh = h * h;
    let ac = a * c;
    (hh - ac).cmp_lt(neg(
        (hh + abs(ac)) * F::splat(1.0 / 256.0) + F::splat(1.0 / 64.0)
    ))
}

/// `shapes::solve_lagrange`: whether there are roots, and both in ascending order.
#[inline(always)]
fn solve_lagrange(a: F, h: F, c: F, disc: F) -> (M, F, F) {
    let zero = F::ZERO;
    // a = 0: one root −c/2h unless h = 0
    let linear = a.cmp_eq(zero);
    let tl = neg(c) / (h + h);
    let ok_linear = !h.cmp_eq(zero);
    // a ≠ 0: none when Δ′ < 0 (a NaN Δ′ goes on, as in the scalar code)
    let ok_quad = !disc.cmp_lt(zero);
    let sq = sqrt(disc);
    let q = sel(h.cmp_lt(zero), sq - h, neg(h + sq));
    let q0 = q.cmp_eq(zero);
    let t1 = sel(q0, zero, q / a);
    let t2 = sel(q0, zero, c / q);
    let le = t1.cmp_le(t2);
    let (lo, hi) = (sel(le, t1, t2), sel(le, t2, t1));
    (
        sel(linear, ok_linear, ok_quad),
        sel(linear, tl, lo),
        sel(linear, tl, hi),
    )
}

#[inline(always)]
fn in_range(t: F, tmin: F, tmax: F) -> M {
    t.cmp_ge(tmin) & t.cmp_le(tmax)
}

/// The first of two roots in [tmin, tmax] (`sphere_c`'s and `cube`'s choice).
#[inline(always)]
fn pick(ok: M, t1: F, t2: F, tmin: F, tmax: F) -> Lanes {
    let (r1, r2) = (in_range(t1, tmin, tmax), in_range(t2, tmin, tmax));
    (ok & (r1 | r2), sel(r1, t1, t2))
}

/// `shapes::pick_in_height`: the first root in range whose point's y is in [lo, hi].
#[inline(always)]
fn pick_in_height(ok: M, (t1, t2): (F, F), o: P3, d: P3, tmin: F, tmax: F, lo: f32) -> Lanes {
    let (lo, hi) = (F::splat(lo), F::ONE);
    let good = |t: F| {
        let y = o.y + d.y * t;
        in_range(t, tmin, tmax) & y.cmp_ge(lo) & y.cmp_le(hi)
    };
    let (g1, g2) = (good(t1), good(t2));
    (ok & (g1 | g2), sel(g1, t1, t2))
}

/// `shapes::sphere_c` (stable quadratic).
#[inline(always)]
fn sphere(o: P3, d: P3, c: F, tmin: F, tmax: F) -> Lanes {
    let a = d.dot(d);
    let h = d.dot(o);
    let miss = clearly_misses(a, h, c);
    let x = d.cross2(o);
    let (ok, t1, t2) = solve_lagrange(a, h, c, a - x.dot(x));
    pick(ok & !miss, t1, t2, tmin, tmax)
}

/// `shapes::plane_t`, and the point's x, z at that t.
#[inline(always)]
fn plane(o: P3, d: P3, tmin: F, tmax: F) -> (M, F, F, F) {
    let t = neg(o.y) / d.y;
    let ok = !d.y.cmp_eq(F::ZERO) & in_range(t, tmin, tmax);
    (ok, t, o.x + d.x * t, o.z + d.z * t)
}

/// `shapes::cylinder` (stable quadratic).
#[inline(always)]
fn cylinder(o: P3, d: P3, tmin: F, tmax: F) -> Lanes {
    let a = d.x * d.x + d.z * d.z;
    let c = o.x * o.x + o.z * o.z - F::ONE;
    let h = d.x * o.x + d.z * o.z;
    let miss = clearly_misses(a, h, c);
    let x = d.x * o.z + neg(d.z) * o.x;
    let (ok, t1, t2) = solve_lagrange(a, h, c, a - x * x);
    let ok = ok & !miss & !a.cmp_eq(F::ZERO);
    pick_in_height(ok, (t1, t2), o, d, tmin, tmax, -1.0)
}

/// `shapes::cone` (stable quadratic).
#[inline(always)]
fn cone(o: P3, d: P3, tmin: F, tmax: F) -> Lanes {
    let a = d.x * d.x - d.y * d.y + d.z * d.z;
    let p = P3 {
        x: o.x,
        y: o.y - F::ONE,
        z: o.z,
    };
    let h = d.x * p.x + neg(d.y) * p.y + d.z * p.z;
    let c = p.x * p.x + neg(p.y) * p.y + p.z * p.z;
    let miss = clearly_misses(a, h, c);
    let xy = d.x * p.y + neg(d.y) * p.x;
    let yz = d.y * p.z + neg(d.z) * p.y;
    let xz = d.x * p.z + neg(d.z) * p.x;
    let (ok, t1, t2) = solve_lagrange(a, h, c, xy * xy + yz * yz + neg(xz) * xz);
    pick_in_height(ok & !miss, (t1, t2), o, d, tmin, tmax, 0.0)
}

/// `shapes::cube`: the slab test, an axis the ray is parallel to leaving near and far as
/// they were (and missing when the origin is outside that slab).
#[inline(always)]
fn cube(o: P3, d: P3, tmin: F, tmax: F) -> Lanes {
    let one = F::ONE;
    let mut ok = F::ZERO.cmp_eq(F::ZERO);
    let mut near = F::splat(-f32::MAX);
    let mut far = F::splat(f32::MAX);
    for (oa, da) in [(o.x, d.x), (o.y, d.y), (o.z, d.z)] {
        let parallel = da.cmp_eq(F::ZERO);
        ok &= !(parallel & abs(oa).cmp_gt(one));
        let t0 = (F::splat(-1.0) - oa) / da;
        let t1 = (one - oa) / da;
        let le = t0.cmp_le(t1);
        let (lo, hi) = (sel(le, t0, t1), sel(le, t1, t0));
        near = sel(parallel, near, max(near, lo));
        far = sel(parallel, far, min(far, hi));
    }
    pick(ok & !near.cmp_gt(far), near, far, tmin, tmax)
}

/// A shape's hits for the packet: its scalar intersector ([`super::shapes::intersect`])
/// lane by lane; `c` is a sphere's |o|² − 1, which every caller has at hand.
#[inline(always)]
fn shape_lanes(shape: Shape, o: P3, d: P3, c: F, tmin: F, tmax: F) -> Lanes {
    match shape {
        Shape::Sphere => sphere(o, d, c, tmin, tmax),
        Shape::Plane => {
            let (ok, t, _, _) = plane(o, d, tmin, tmax);
            (ok, t)
        }
        Shape::Disk => {
            let (ok, t, x, z) = plane(o, d, tmin, tmax);
            (ok & (x * x + z * z).cmp_le(F::ONE), t)
        }
        Shape::Square => {
            let (ok, t, x, z) = plane(o, d, tmin, tmax);
            (ok & abs(x).cmp_le(F::ONE) & abs(z).cmp_le(F::ONE), t)
        }
        Shape::Cylinder => cylinder(o, d, tmin, tmax),
        Shape::Cone => cone(o, d, tmin, tmax),
        Shape::Cube => cube(o, d, tmin, tmax),
    }
}

/// One object's hits for a packet of rays from the eye (`Prepared::hit` with the eye's
/// object-space image and |eye′|² − 1 precomputed, as the scalar kernel has them).
#[inline(always)]
fn hit<const SO: bool>(ob: &PObj<f32>, d: P3, tmin: F, tmax: F) -> Lanes {
    let (o, c) = (P3::splat(ob.eye), F::splat(ob.eye_c));
    if SO {
        return sphere(o, d, c, tmin, tmax);
    }
    shape_lanes(ob.shape, o, d, c, tmin, tmax)
}

/// Nearest hit of each lane's ray from the eye: `Prepared::closest` over `list` (the
/// tile's candidates in object order), t and object index per lane.
#[inline(always)]
fn closest<const SO: bool>(
    p: &Prepared<f32>,
    d: P3,
    list: &[u16],
) -> [Option<(f32, usize)>; LANES] {
    let tmin = F::splat(p.bias);
    let mut best = F::splat(p.maxd);
    // object index + 1 per lane, 0: none (exact in f32 below 2²⁴)
    let mut found = F::ZERO;
    for &k in list {
        let Some(ob) = p.objs.get(usize::from(k)) else {
            continue;
        };
        let (ok, t) = hit::<SO>(ob, d.to_object(ob), tmin, best);
        if ok.any() {
            best = sel(ok, t, best);
            found = sel(ok, F::splat(f32::from(k) + 1.0), found);
        }
    }
    let (best, found) = (best.to_array(), found.to_array());
    per_lane(|l| (found[l] > 0.0).then(|| (best[l], found[l] as usize - 1)))
}

/// The next `n` pixels of the row from their sums of radiance in lanes: `RowOut::pixel`'s
/// mean, tone map and ⌊255·c⌋ eight at a time (the same f32 operations: `composed`'s
/// max and min, then a truncation, exact for the product in [0, 255]), and each pixel's
/// AOVs from its first hit.
#[inline(always)]
fn pixels(
    out: &mut RowOut<f32>,
    f: &FrameCtx<f32>,
    acc: P3,
    first: &mut [Option<Option<Hit<f32>>>; LANES],
    n: usize,
) {
    if f.aovs {
        for h in first.iter_mut().take(n) {
            out.aovs(f, h.take());
        }
    }
    let c = if f.spp == 1 {
        acc
    } else {
        acc.scale(F::splat(f.inv_spp))
    };
    let tone = |v: F| match f.tone_map {
        ToneMap::Clamp => v,
        ToneMap::Reinhard => {
            let v = max(v, F::ZERO);
            v / (F::ONE + v)
        }
    };
    let q = |v: F| {
        (min(max(tone(v), F::ZERO), F::ONE) * F::splat(255.0))
            .fast_trunc_int()
            .to_array()
    };
    let (r, g, b) = (q(c.x), q(c.y), q(c.z));
    let mut bytes = [0u8; 3 * LANES];
    for (l, px) in bytes.chunks_exact_mut(3).enumerate() {
        // in [0, 255]: the cast keeps the value
        px.copy_from_slice(&[r[l] as u8, g[l] as u8, b[l] as u8]);
    }
    out.push_rgb(&bytes[..3 * n]);
}

/// [`Prepared::row_packets`]: primary rays in packets.
pub(super) struct PacketRows;

impl Rows<f32> for PacketRows {
    fn row<const SH: bool, const TX: bool, const SP: bool, const RF: bool, const SO: bool>(
    ) -> RowFn<f32> {
        Prepared::<f32>::row_packets::<SH, TX, SP, RF, SO>
    }
}

impl Prepared<f32> {
    /// The packet kernel for a feature set: [`Self::row_packets`] over the same 32
    /// monomorphisations as [`Prepared::kernel`].
    pub(super) fn packet_kernel(f: super::Features) -> RowFn<f32> {
        rows_for::<f32, PacketRows>(f)
    }

    /// Row `j` with the primary rays' nearest hits found eight pixels at a time, the
    /// lanes that hit a plain material shaded together ([`Self::shade_packet`]), the rest
    /// of each other ray ([`Prepared::trace`] from its hit) and the pixel's output as the
    /// scalar row does them. A frame these lanes do not repeat (a non-default √ or
    /// quadratic) goes to the scalar row.
    fn row_packets<
        const SH: bool,
        const TX: bool,
        const SP: bool,
        const RF: bool,
        const SO: bool,
    >(
        &self,
        f: &FrameCtx<f32>,
        j: u32,
    ) -> Rendered<Vec<f32>, Vec<u16>> {
        if self.m.sqrt != SqrtKind::Exact
            || f.sqrt != SqrtKind::Exact
            || self.m.quadratic != Quadratic::Stable
            || f.eye != self.eye
        {
            return self.row::<SH, TX, SP, RF, SO>(f, j);
        }
        let vys = f.sample_row_offsets(j);
        let mut out = RowOut::new(f);
        let cw = P3::splat(f.cw);
        // the object that blocked the lanes' last shadow rays
        let mut occluder = 0;
        let mut i0 = 0;
        while i0 < f.width {
            let n = (f.width - i0).min(LANES as u32) as usize;
            let eye_objs = f.eye_objs(i0, j);
            let mut acc = P3::splat(V3::zero());
            let mut first: [Option<Option<Hit<f32>>>; LANES] = Default::default();
            for s in 0..f.spp {
                let Some(&vy) = vys.get((s / f.grid) as usize) else {
                    continue;
                };
                // this sample's radiance, lane by lane
                let (mut cx, mut cy, mut cz) = ([0.0f32; LANES], [0.0f32; LANES], [0.0f32; LANES]);
                if eye_objs.is_empty() {
                    for l in 0..n {
                        let c = self.miss_from_eye(&mut out.cnt);
                        (cx[l], cy[l], cz[l]) = (c.x, c.y, c.z);
                        if s == 0 {
                            first[l] = Some(None);
                        }
                    }
                } else {
                    // u·x of each lane's sample column (the row's last packet repeats its
                    // last pixel in the lanes beyond the frame, whose results are dropped;
                    // every column inside the frame has its entry)
                    let ux: [V3<f32>; LANES] = per_lane(|l| {
                        let i = i0 + (l.min(n - 1)) as u32;
                        f.col(i, s).unwrap_or_else(V3::zero)
                    });
                    let u = P3 {
                        x: F::new(per_lane(|l| ux[l].x)),
                        y: F::new(per_lane(|l| ux[l].y)),
                        z: F::new(per_lane(|l| ux[l].z)),
                    };
                    let d = u.add(P3::splat(vy)).sub(cw).normalize();
                    let hits = closest::<SO>(self, d, eye_objs);
                    let shaded =
                        self.shade_packet::<SH, SP, SO>(d, &hits, n, &mut out.cnt, &mut occluder);
                    (cx, cy, cz) = (
                        shaded.color.x.to_array(),
                        shaded.color.y.to_array(),
                        shaded.color.z.to_array(),
                    );
                    let all = u8::MAX >> (LANES - n);
                    if shaded.live != all || (s == 0 && f.aovs) {
                        let (dx, dy, dz) = (d.x.to_array(), d.y.to_array(), d.z.to_array());
                        for l in 0..n {
                            if shaded.live >> l & 1 == 1 {
                                if s == 0 && f.aovs {
                                    first[l] = Some(Some(shaded.hit(l)));
                                }
                                continue;
                            }
                            let primary = Primary {
                                objs: eye_objs,
                                found: Some(hits[l]),
                            };
                            let (c, hit) = self.trace::<SH, TX, SP, RF, SO>(
                                f.eye,
                                V3::new(dx[l], dy[l], dz[l]),
                                0,
                                false,
                                primary,
                                &mut out.cnt,
                            );
                            (cx[l], cy[l], cz[l]) = (c.x, c.y, c.z);
                            if s == 0 {
                                first[l] = Some(hit);
                            }
                        }
                    }
                }
                acc = acc.add(P3 {
                    x: F::new(cx),
                    y: F::new(cy),
                    z: F::new(cz),
                });
            }
            pixels(&mut out, f, acc, &mut first, n);
            i0 += n as u32;
        }
        out.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rt::{shapes, Math};

    /// The next 31 bits of a 64-bit LCG (Knuth's MMIX constants): the packet tests'
    /// repeatable source of special and ordinary values.
    pub(super) fn draw(seed: &mut u64) -> u32 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 33) as u32
    }

    /// Ray components that meet the intersectors' branches: exact zeros (rays parallel
    /// to a face, a plane or an axis), ±1 (on a slab's face or a cone's apex plane),
    /// tiny and huge values, and random ones.
    fn component(seed: &mut u64) -> f32 {
        let r = draw(seed);
        let u = (r & 0xffff) as f32 / 65536.0;
        match r >> 28 {
            0 | 1 => 0.0,
            2 => 1.0,
            3 => -1.0,
            4 => 1e-7 * (u - 0.5),
            5 => 1e7 * (u - 0.5),
            _ => 6.0 * (u - 0.5),
        }
    }

    fn v3(seed: &mut u64) -> V3<f32> {
        V3::new(component(seed), component(seed), component(seed))
    }

    fn pack(v: &[V3<f32>; LANES]) -> P3 {
        P3 {
            x: F::new(v.map(|v| v.x)),
            y: F::new(v.map(|v| v.y)),
            z: F::new(v.map(|v| v.z)),
        }
    }

    /// Every shape's lanes against its scalar intersector on 40 000 rays each: the
    /// same hit or miss, and the same t to the bit.
    #[test]
    fn lanes_equal_the_scalar_intersectors() {
        let m = Math::default();
        let mut seed = 7;
        for &shape in Shape::ALL {
            for _ in 0..5000 {
                let o: [V3<f32>; LANES] = std::array::from_fn(|_| v3(&mut seed));
                let d: [V3<f32>; LANES] = std::array::from_fn(|_| v3(&mut seed));
                let (tmin, tmax) = (1e-3f32, if seed & 1 == 0 { 1e6 } else { 3.0 });
                let c = F::new(o.map(|o| o.dot(o) - 1.0));
                let (ok, t) =
                    shape_lanes(shape, pack(&o), pack(&d), c, F::splat(tmin), F::splat(tmax));
                let (ok, t) = (ok.move_mask(), t.to_array());
                for l in 0..LANES {
                    let want = shapes::intersect(shape, o[l], d[l], tmin, tmax, &m);
                    let got = (ok >> l & 1 == 1).then_some(t[l]);
                    assert_eq!(
                        want.map(f32::to_bits),
                        got.map(f32::to_bits),
                        "{shape:?} o={:?} d={:?}: scalar {want:?}, lanes {got:?}",
                        o[l],
                        d[l]
                    );
                }
            }
        }
    }

    /// `P3::normalize` against `V3::normalize`, zero and NaN-length vectors included.
    #[test]
    fn normalize_equals_the_scalar_one() {
        let mut seed = 11;
        for _ in 0..5000 {
            let mut v: [V3<f32>; LANES] = std::array::from_fn(|_| v3(&mut seed));
            v[7] = V3::new(f32::NAN, 0.0, 1.0);
            let n = pack(&v).normalize();
            let (x, y, z) = (n.x.to_array(), n.y.to_array(), n.z.to_array());
            for l in 0..LANES {
                let want = v[l].normalize(SqrtKind::Exact);
                assert_eq!(
                    [want.x, want.y, want.z].map(f32::to_bits),
                    [x[l], y[l], z[l]].map(f32::to_bits),
                    "{:?}",
                    v[l]
                );
            }
        }
    }
}
