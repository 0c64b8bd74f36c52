//! Bézier curves by adaptive subdivision with a flatness tolerance, and bicubic patches
//! tessellated into triangles that share vertices exactly (so the top-left rule keeps
//! the patch watertight).

use super::RasterError;
use protocol::raster::{BezierPatch, Point};

/// Deepest subdivision: 2^16 segments bound the work of a tiny tolerance.
pub(crate) const MAX_DEPTH: u32 = 16;

type P = (f64, f64);

fn mid(a: P, b: P) -> P {
    ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0)
}

/// Distance to the chord *segment*: the capsule around it is convex and holds the end
/// points, so if it holds the inner control points it holds the hull and the curve.
fn dist_to_chord(p: P, a: P, b: P) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let l2 = dx * dx + dy * dy;
    let t = if l2 == 0.0 {
        0.0
    } else {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / l2).clamp(0.0, 1.0)
    };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// De Casteljau split at ½ of a quadratic or cubic (any degree) control polygon.
fn split(c: &[P]) -> (Vec<P>, Vec<P>) {
    let mut left = vec![c[0]];
    let mut right = vec![c[c.len() - 1]];
    let mut cur = c.to_vec();
    while cur.len() > 1 {
        cur = cur.windows(2).map(|w| mid(w[0], w[1])).collect();
        left.push(cur[0]);
        right.push(cur[cur.len() - 1]);
    }
    right.reverse();
    (left, right)
}

/// The polyline of a quadratic (3 points) or cubic (4 points) Bézier curve. The first
/// and last vertices are the end points exactly; every piece is accepted only when its
/// inner control points lie within `tolerance − 0.75` units of its chord segment (the curve
/// lies in the hull, and rounding a vertex moves it by at most √½), so the curve stays
/// within `tolerance` sub-pixel units of the polyline.
pub fn flatten(points: &[Point], tolerance: u32) -> Result<Vec<Point>, RasterError> {
    if !(3..=4).contains(&points.len()) {
        return Err(RasterError::BezierArity(points.len()));
    }
    let tol = (tolerance as f64 - 0.75).max(0.25);
    let ctrl: Vec<P> = points.iter().map(|p| (p.x as f64, p.y as f64)).collect();
    let mut out = vec![points[0]];
    // Explicit stack, right half pushed first so pieces come out in order.
    let mut stack = vec![(ctrl, 0u32)];
    while let Some((c, depth)) = stack.pop() {
        let (a, b) = (c[0], c[c.len() - 1]);
        let flat = c[1..c.len() - 1]
            .iter()
            .all(|&p| dist_to_chord(p, a, b) <= tol);
        if flat || depth >= MAX_DEPTH {
            out.push(Point {
                x: b.0.round() as i32,
                y: b.1.round() as i32,
            });
        } else {
            let (l, r) = split(&c);
            stack.push((r, depth + 1));
            stack.push((l, depth + 1));
        }
    }
    if let (Some(last), Some(end)) = (out.last_mut(), points.last()) {
        *last = *end;
    }
    Ok(out)
}

/// Evaluates a Bézier curve of any degree at `t` (for tests and patches).
pub fn eval(c: &[(f64, f64)], t: f64) -> (f64, f64) {
    let mut cur = c.to_vec();
    while cur.len() > 1 {
        cur = cur
            .windows(2)
            .map(|w| {
                (
                    w[0].0 + (w[1].0 - w[0].0) * t,
                    w[0].1 + (w[1].1 - w[0].1) * t,
                )
            })
            .collect();
    }
    cur[0]
}

/// Tessellates a bicubic patch into `steps × steps × 2` triangles. The grid vertices are
/// evaluated and rounded once, so neighbouring triangles share exact vertices.
pub fn patch_triangles(p: &BezierPatch) -> Vec<[Point; 3]> {
    let n = p.steps.max(1) as usize;
    let net: Vec<P> = p.points.iter().map(|q| (q.x as f64, q.y as f64)).collect();
    let mut grid = Vec::with_capacity((n + 1) * (n + 1));
    for i in 0..=n {
        let v = i as f64 / n as f64;
        // Curves along u for each row of the net, then one curve along v.
        for j in 0..=n {
            let u = j as f64 / n as f64;
            let rows: Vec<P> = (0..4).map(|r| eval(&net[r * 4..r * 4 + 4], u)).collect();
            let q = eval(&rows, v);
            grid.push(Point {
                x: q.0.round() as i32,
                y: q.1.round() as i32,
            });
        }
    }
    let at = |i: usize, j: usize| grid[i * (n + 1) + j];
    let mut tris = Vec::with_capacity(2 * n * n);
    for i in 0..n {
        for j in 0..n {
            tris.push([at(i, j), at(i, j + 1), at(i + 1, j)]);
            tris.push([at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]);
        }
    }
    tris
}
