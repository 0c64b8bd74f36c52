//! A packet's shading and shadow rays in lanes: after the primary search, the eight hits
//! of a packet are shaded together, each light's shadow rays tested against the objects
//! eight at a time.
//!
//! Why: with the search in lanes, the rest of a Lambert frame (the hit point, the normal,
//! each light's vector, its shadow ray, the diffuse term) was four fifths of the time,
//! one ray at a time: the shadow test alone was 40 % (perf, one thread). Here every lane
//! does the same IEEE f32 operations in the same order as `Prepared::trace` does for its
//! ray, each branch both sides and a select on the same ordered comparison, so the frame
//! is the scalar kernel's bit for bit.
//!
//! Which lanes: those that hit an object whose material the lanes can shade (diffuse
//! Lambert, maybe an ambient term and a Blinn–Phong highlight; no texture,
//! Torrance–Sparrow term or reflection the kernel would use), under point and spot
//! lights. Any other lane (a miss, Oren–Nayar, Torrance–Sparrow, a texture, a mirror)
//! goes through `trace` as before; lanes are independent, so a packet may mix the two.
//!
//! The shadow test in lanes tests the objects one at a time against the packet's open
//! lanes, starting with the object that blocked the packet's previous shadow lanes and
//! stopping once every lane is blocked. An object is skipped only where every open
//! lane's ray fails its pretest (`pretest::Spheres::misses`, the same arithmetic as the
//! scalar pretest with the rays in lanes); otherwise its intersector runs for all eight.
//! So a lane may be tested against an object its own pretest dropped. The answer is the
//! same: an occlusion test is an any(), and the pretest drops only objects the exact
//! test would have missed (the planned kernel equals the general one bit for bit,
//! `rt_cull`).

use super::{max, min, neg, per_lane, sel, sphere, sqrt, F, LANES, M, P3};
use crate::num::powi_with;
use crate::rt::kernel::{Counts, Hit};
use crate::rt::prepare::Prepared;
use crate::rt::pretest::Rays8;
use crate::rt::scene::Shape;
use crate::rt::shade::SpecParams;
use crate::rt::V3;
use wide::{CmpGe, CmpGt, CmpLe, CmpLt};

/// What the lanes made of the packet's rays from the eye: in the lanes set in `live`, the
/// radiance and the first hit; every other lane is left to `trace`. Kept in lanes: the
/// row adds the radiance to its sums and quantises it eight pixels at a time, and builds
/// a lane's [`Hit`] only for the AOVs.
pub(super) struct Shaded {
    /// The lanes shaded here, as bits.
    pub(super) live: u8,
    /// Their radiance.
    pub(super) color: P3,
    t: F,
    n: P3,
    obj: [usize; LANES],
}

impl Shaded {
    /// No lane shaded.
    fn none() -> Self {
        let zero = F::ZERO;
        let z3 = P3 {
            x: zero,
            y: zero,
            z: zero,
        };
        Shaded {
            live: 0,
            color: z3,
            t: zero,
            n: z3,
            obj: [0; LANES],
        }
    }

    /// Lane `l`'s first hit (meaningful where `live` has `l`).
    pub(super) fn hit(&self, l: usize) -> Hit<f32> {
        let at = |v: F| v.to_array()[l % LANES];
        Hit::new(
            at(self.t),
            V3::new(at(self.n.x), at(self.n.y), at(self.n.z)),
            self.obj[l % LANES],
        )
    }
}

/// The packet's Blinn–Phong groups: lanes, k_s·c_s and the highlight's constants.
type Highlights = [Option<(M, V3<f32>, SpecParams<f32>)>; LANES];

/// A lane mask from bits (lane l true where bit l is set).
#[inline(always)]
fn mask(bits: u8) -> M {
    let on = f32::from_bits(u32::MAX);
    F::new(per_lane(|l| if bits >> l & 1 == 1 { on } else { 0.0 }))
}

/// Lanes set in a mask, as bits.
#[inline(always)]
fn bits(m: M) -> u8 {
    // eight lanes: the mask fits
    (m.move_mask() & 0xff) as u8
}

/// `shapes::normal` lane by lane (the object-space normal at `p`).
#[inline(always)]
fn normal(shape: Shape, p: P3) -> P3 {
    let (zero, one) = (F::ZERO, F::ONE);
    match shape {
        Shape::Sphere => p,
        Shape::Plane | Shape::Disk | Shape::Square => P3 {
            x: zero,
            y: one,
            z: zero,
        },
        Shape::Cylinder => P3 {
            x: p.x,
            y: zero,
            z: p.z,
        },
        Shape::Cone => P3 {
            x: p.x,
            y: one - p.y,
            z: p.z,
        },
        Shape::Cube => {
            let (ax, ay, az) = (super::abs(p.x), super::abs(p.y), super::abs(p.z));
            let sgn = |v: F| sel(v.cmp_lt(zero), F::splat(-1.0), one);
            let on_x = ax.cmp_ge(ay) & ax.cmp_ge(az);
            let on_y = !on_x & ay.cmp_ge(az);
            let on_z = !on_x & !on_y;
            P3 {
                x: sel(on_x, sgn(p.x), zero),
                y: sel(on_y, sgn(p.y), zero),
                z: sel(on_z, sgn(p.z), zero),
            }
        }
    }
}

/// A normal matrix applied lane by lane (`M3::mul_v`: each row a `dot3`, left to right).
#[inline(always)]
fn mul_v(m: &[[f32; 3]; 3], v: P3) -> P3 {
    let row = |r: [f32; 3]| F::splat(r[0]) * v.x + F::splat(r[1]) * v.y + F::splat(r[2]) * v.z;
    P3 {
        x: row(m[0]),
        y: row(m[1]),
        z: row(m[2]),
    }
}

#[inline(always)]
fn blend(m: M, t: P3, f: P3) -> P3 {
    P3 {
        x: sel(m, t.x, f.x),
        y: sel(m, t.y, f.y),
        z: sel(m, t.z, f.z),
    }
}

/// The lanes' BRDF times colour for one light: Lambert's `brdf`, plus k_s·c_s times
/// `shade::blinn_phong` (h = (wi + wo)/|wi + wo|, wo = −d, (e + 2)/(2π)·max(n·h, 0)^e)
/// in the lanes of each group in `specs`, as `trace` adds it.
#[inline(always)]
fn highlights(brdf: P3, specs: &Highlights, n: P3, wi: P3, d: P3) -> P3 {
    if specs.iter().all(Option::is_none) {
        return brdf;
    }
    let wo = P3 {
        x: neg(d.x),
        y: neg(d.y),
        z: neg(d.z),
    };
    let h = wi.add(wo).normalize();
    let nh = max(n.dot(h), F::ZERO);
    let mut b = brdf;
    for (m, kc, p) in specs.iter().flatten() {
        let fs = F::splat(p.norm) * powi_with(nh, p.e, F::ONE);
        let with = brdf.add(P3::splat(*kc).scale(fs));
        b = blend(*m, with, b);
    }
    b
}

impl Prepared<f32> {
    /// Shades the packet's rays from the eye (directions `d`, nearest hits `hits` as the
    /// search found them, the first `n` lanes inside the frame) where the lanes can, as
    /// `trace` would from those hits: radiance, first hit, and the ray counts in `cnt`.
    #[inline(always)]
    pub(super) fn shade_packet<const SH: bool, const SP: bool, const SO: bool>(
        &self,
        d: P3,
        hits: &[Option<(f32, usize)>; LANES],
        n: usize,
        cnt: &mut Counts,
        occluder: &mut usize,
    ) -> Shaded {
        if self.depth == 0 {
            return Shaded::none();
        }
        // the packet's lanes grouped by the object they hit, for the lanes that shade
        let mut groups: [(usize, u8); LANES] = [(0, 0); LANES];
        let mut ngroups = 0;
        let mut live = 0u8;
        for (l, h) in hits.iter().enumerate().take(n) {
            let Some((_, k)) = *h else { continue };
            if self.objs.get(k).is_none_or(|ob| ob.plain.is_none()) {
                continue;
            }
            live |= 1 << l;
            match groups[..ngroups].iter_mut().find(|g| g.0 == k) {
                Some(g) => g.1 |= 1 << l,
                None => {
                    groups[ngroups] = (k, 1 << l);
                    ngroups += 1;
                }
            }
        }
        if live == 0 {
            return Shaded::none();
        }
        let ts = per_lane(|l| hits[l].map_or(0.0, |h| h.0));
        let t = F::new(ts);
        let zero3 = P3::splat(V3::zero());
        // per object: the shading normal (before the side flip), the ambient term and
        // the Lambert BRDF times k_d·c_d (both constant over the material)
        let (mut nrm, mut ambient, mut brdf) = (zero3, zero3, zero3);
        // the groups with a Blinn–Phong highlight (only where the kernel has specular
        // terms: without, `trace` ignores them)
        let mut specs: Highlights = [None; LANES];
        for (&(k, lanes), spec) in groups[..ngroups].iter().zip(&mut specs) {
            let m = mask(lanes);
            let Some((ob, plain)) = self.objs.get(k).and_then(|ob| Some((ob, ob.plain?))) else {
                continue;
            };
            if SP {
                *spec = plain.spec.map(|(kc, p)| (m, kc, p));
            }
            let ld = d.to_object(ob);
            let lp = P3::splat(ob.eye).add(ld.scale(t));
            let on = if SO { lp } else { normal(ob.shape, lp) };
            nrm = blend(m, mul_v(&ob.nmat.0, on).normalize(), nrm);
            ambient = blend(m, P3::splat(plain.ambient), ambient);
            brdf = blend(m, P3::splat(plain.brdf), brdf);
        }
        let p = P3::splat(self.eye).add(d.scale(t));
        let inside = nrm.dot(d).cmp_ge(F::ZERO);
        let nrm = blend(
            inside,
            P3 {
                x: neg(nrm.x),
                y: neg(nrm.y),
                z: neg(nrm.z),
            },
            nrm,
        );
        let p_off = p.add(nrm.scale(F::splat(self.bias)));
        let mut lk = ambient;
        let lanes = mask(live);
        for light in &self.lights {
            let to_l = P3::splat(light.pos).sub(p);
            let dist2 = to_l.dot(to_l);
            let inv_dist = sel(
                dist2.cmp_gt(F::ZERO),
                F::ONE / sqrt(dist2),
                F::splat(f32::MAX),
            );
            let wi = to_l.scale(inv_dist);
            let ndl = nrm.dot(wi);
            let mut lit = lanes & !dist2.cmp_le(F::ZERO) & !ndl.cmp_le(F::ZERO);
            // `shade::spot_factor`: clamp((−(l_dir·wi) − cos_outer)·inv_width, 0, 1)
            let scf = match &light.spot {
                None => F::ONE,
                Some((dir, cos_o, inv_w)) => {
                    let c = neg(P3::splat(*dir).dot(wi));
                    let x = (c - F::splat(*cos_o)) * F::splat(*inv_w);
                    min(max(x, F::ZERO), F::ONE)
                }
            };
            lit &= !scf.cmp_le(F::ZERO);
            if SH && self.shadows {
                cnt.shadow += u64::from(bits(lit).count_ones());
                let dist = dist2 * inv_dist;
                lit &= !self.occluded_lanes::<SO>(p_off, wi, dist, lit, occluder);
            }
            let g = ndl / dist2 * scf;
            let b = highlights(brdf, &specs, nrm, wi, d);
            let c = P3::splat(light.color);
            let term = P3 {
                x: b.x * c.x,
                y: b.y * c.y,
                z: b.z * c.z,
            }
            .scale(g);
            lk = blend(lit, lk.add(term), lk);
        }
        // color = 0 + lk·weight, weight = 1
        let color = P3::splat(V3::zero()).add(lk.scale(F::ONE));
        cnt.primary += u64::from(live.count_ones());
        Shaded {
            live,
            color,
            t,
            n: nrm,
            obj: per_lane(|l| hits[l].map_or(0, |h| h.1)),
        }
    }

    /// Which of the `lanes` rays o + t·d, t ∈ [bias, tmax], hit some object: the scalar
    /// `occluded` of each lane. `first` is the object that blocked the last lanes: tried
    /// first (an any(): the order cannot change the answer).
    #[inline(always)]
    fn occluded_lanes<const SO: bool>(
        &self,
        o: P3,
        d: P3,
        tmax: F,
        lanes: M,
        first: &mut usize,
    ) -> M {
        let tmin = F::splat(self.bias);
        let mut blocked = F::ZERO;
        let mut open = bits(lanes);
        let rays = Rays8::new([o.x, o.y, o.z], [d.x, d.y, d.z]);
        let n = self.objs.len();
        let start = if *first < n { *first } else { 0 };
        for i in (start..n).chain(0..start) {
            if open == 0 {
                break;
            }
            // the pretest of each open lane's ray
            if open & !bits(self.spheres.misses(i, &rays)) == 0 {
                continue;
            }
            let Some(ob) = self.objs.get(i) else { break };
            let lo = o.sub(P3::splat(ob.translate)).to_object(ob);
            let ld = d.to_object(ob);
            let c = lo.dot(lo) - F::ONE;
            let (hit, _) = if SO {
                sphere(lo, ld, c, tmin, tmax)
            } else {
                super::shape_lanes(ob.shape, lo, ld, c, tmin, tmax)
            };
            let now = bits(hit) & open;
            if now != 0 {
                blocked |= mask(now);
                open &= !now;
                *first = i;
            }
        }
        blocked
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rt::shapes;

    /// Coordinates that meet `normal`'s branches: zeros of both signs, ties between
    /// axes (a cube's edges and corners), ±1, and ordinary values.
    fn coordinate(seed: &mut u64) -> f32 {
        let r = super::super::tests::draw(seed);
        let u = (r & 0xffff) as f32 / 65536.0;
        match r >> 28 {
            0 => 0.0,
            1 => -0.0,
            2 => 0.5,
            3 => -0.5,
            4 => 1.0,
            _ => 4.0 * (u - 0.5),
        }
    }

    /// Every shape's lane normal against `shapes::normal`, bit for bit (signed zeros and
    /// ties included).
    #[test]
    fn lane_normals_equal_the_scalar_ones() {
        let mut seed = 3;
        for &shape in Shape::ALL {
            for _ in 0..4000 {
                let p: [V3<f32>; LANES] = std::array::from_fn(|_| {
                    V3::new(
                        coordinate(&mut seed),
                        coordinate(&mut seed),
                        coordinate(&mut seed),
                    )
                });
                let lanes = P3 {
                    x: F::new(p.map(|v| v.x)),
                    y: F::new(p.map(|v| v.y)),
                    z: F::new(p.map(|v| v.z)),
                };
                let n = normal(shape, lanes);
                let (x, y, z) = (n.x.to_array(), n.y.to_array(), n.z.to_array());
                for l in 0..LANES {
                    let want = shapes::normal(shape, p[l]);
                    assert_eq!(
                        [want.x, want.y, want.z].map(f32::to_bits),
                        [x[l], y[l], z[l]].map(f32::to_bits),
                        "{shape:?} at {:?}",
                        p[l]
                    );
                }
            }
        }
    }

    /// The lane negation is f32's: −(+0) = −0, −(−0) = +0, a NaN's sign flips.
    #[test]
    fn negation_flips_the_sign_bit() {
        let v = [
            0.0,
            -0.0,
            1.5,
            -2.0,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            1e-40,
        ];
        let got = neg(F::new(v)).to_array();
        for (a, b) in v.iter().zip(got) {
            assert_eq!((-a).to_bits(), b.to_bits(), "−{a}");
        }
    }
}
