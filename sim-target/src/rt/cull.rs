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
//! through a cheap f32 pretest in the kernel, with a rounding allowance. `fpgfx stress`
//! renders random scenes both ways and fails on any difference.

use super::scene::{Object, Scene, Shape};
use super::vec::f;
use super::Cam;
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
    /// World-space centre.
    pub centre: [f64; 3],
    /// Radius, widened by [`RADIUS_SLACK`].
    pub radius: f64,
    /// Distance from the centre within which a ray origin keeps the format's intersection
    /// arithmetic well inside its range; rays from farther away are tested exhaustively,
    /// since a saturated term could invent a hit the geometry does not have.
    pub safe_distance: f64,
}

/// The culling spheres of a scene's objects in format `S`: `None` for an unbounded object
/// (never culled) and for every object when the format does not admit culling. The
/// format must declare its rounding ([`Scalar::rounding`]) and be fine enough that its
/// errors stay far below the slack: f64, f32, Q16.16, Q8.24 and Q32.32 are admitted, f16
/// (2⁻¹¹) and Q24.8 (2⁻⁸) are always tested exhaustively.
pub fn bounds<S: Scalar>(scene: &Scene) -> Vec<Option<Bound>> {
    let rounding = match S::rounding() {
        Some((rel, abs)) if rel <= 2f64.powi(-20) && abs <= 2f64.powi(-14) => Some((rel, abs)),
        _ => None,
    };
    let range = S::max_value().to_f64();
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
            // every product of the test rounds to `abs`: a = |d′|² ≥ 1/smax² must stay
            // far above it
            if abs > 0.0 && smax * smax * abs > BUDGET {
                return None;
            }
            // origins closer than this keep the object-space terms in range and accurate,
            // and (for a fixed format) their own world coordinates unsaturated
            let cmax = centre.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let safe_distance =
                (safe_object_distance(rel, abs, range, smin, smax) * smin).min(range / 2.0 - cmax);
            (safe_distance.is_finite() && safe_distance > 0.0).then_some(Bound {
                centre,
                radius: r * (1.0 + RADIUS_SLACK),
                safe_distance,
            })
        })
        .collect()
}

/// The discriminant's margin at a miss by the slack (≈ 0.16a) over the error constant
/// (16) and a factor 4 to spare, as a fraction of a = |d′|².
const BUDGET: f64 = 0.16 / 16.0 / 4.0;

/// Largest ratio of an object's scale factors for which it is culled: a strongly
/// anisotropic transform makes the object-space ray ill-conditioned (large |o′| along
/// the thin axis), and the datapath's answer is then no longer the geometry's.
pub const MAX_ANISOTROPY: f64 = 16.0;

/// The largest object-space origin distance |o′| at which a ray (unit direction) that
/// misses the widened bound still gets "no hit" from the format's arithmetic, with a
/// factor 4 to spare.
/// A miss by the slack leaves the unit shape's discriminant at −4a·((1 + slack)² − 1) ≈
/// −0.16a, a = |d′|² ≥ 1/smax²; the discriminant's rounding error is about 16·rel·a·|o′|²
/// in floating point and 16·abs·|d′||o′|(|d′| + |o′|) in fixed point (each of b², 4ac
/// carries the input roundings through two products). Saturation: b² and 4ac must stay
/// below range/2.
fn safe_object_distance(rel: f64, abs: f64, range: f64, smin: f64, smax: f64) -> f64 {
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
        // per object: None = always a candidate, else (unit direction to centre, angular radius)
        let cones: Vec<Option<([f64; 3], f64)>> = bounds
            .iter()
            .map(|b| {
                let b = b.as_ref()?;
                let to_c = f::sub(b.centre, cam.eye);
                let dist = dot(to_c, to_c).sqrt();
                if dist <= b.radius || dist > b.safe_distance {
                    return None; // the eye is inside the bound, or too far for the format
                }
                Some((f::normalize(to_c), (b.radius / dist).asin()))
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
                        Some((c, alpha)) => angle(centre, *c) <= half + alpha + ANGLE_SLACK,
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

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Angle between two unit vectors, robust near 0 and π.
fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let c = f::cross(a, b);
    dot(c, c).sqrt().atan2(dot(a, b))
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
                        dot(d, d).sqrt() <= r * (1.0 + 1e-12),
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
