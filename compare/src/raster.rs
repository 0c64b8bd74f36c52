//! The edges of a raster job: where its primitives' boundaries lie, for the coverage
//! allowance. The rules follow the raster block's coverage contract (docs/raster.md) and
//! dEQP's verifier; docs/compare.md draws them.

use protocol::raster::{Line, Point, RasterCmd, RasterSetup};

use crate::Edge;

/// Every edge a rasteriser could decide either way in the frame `setup` and `cmds` draw:
///
/// * a triangle: its three sides; a polygon: its sides, the last back to the first;
/// * a thin line (aliased, at most one pixel wide): the parallelogram dEQP's non-strict
///   line verifier draws, its long sides ½ px either side of the axis along the minor
///   axis and its ends ½ px beyond the end pixels' centres along the major axis. The axis
///   runs between the centres of the pixels that hold the end points, because that is
///   where fpgfx's Bresenham and DDA run (both end points drawn);
/// * a wide or anti-aliased line: its rectangle (half the width either side of the exact
///   axis, butt ends), dEQP's strict line quad;
/// * clear: none, its edges are the frame's border with no pixel beyond; circles, seed
///   fills, Béziers and patches: none, their pixels are integer algorithms on snapped
///   input with nothing left to decide (docs/compare.md says what that means for them).
pub fn raster_edges(setup: &RasterSetup, cmds: &[RasterCmd]) -> Vec<Edge> {
    let bits = setup.subpixel_bits;
    let scale = f64::from(1u32 << bits);
    let px = |p: Point| (f64::from(p.x) / scale, f64::from(p.y) / scale);
    let mut edges = Vec::new();
    for cmd in cmds {
        match cmd {
            RasterCmd::Triangle(t) => sides(&t.v.map(px), &mut edges),
            RasterCmd::Polygon(p) => {
                let pts: Vec<_> = p.points.iter().map(|&q| px(q)).collect();
                sides(&pts, &mut edges);
            }
            RasterCmd::Line(l) => sides(&line_outline(l, bits), &mut edges),
            RasterCmd::Clear(_)
            | RasterCmd::Circle(_)
            | RasterCmd::Fill(_)
            | RasterCmd::Bezier(_)
            | RasterCmd::Patch(_) => {}
        }
    }
    edges
}

/// The sides of the closed polygon through `pts`, the last back to the first.
fn sides(pts: &[(f64, f64)], edges: &mut Vec<Edge>) {
    for (k, &(x0, y0)) in pts.iter().enumerate() {
        let (x1, y1) = pts[(k + 1) % pts.len()];
        edges.push(Edge::new(x0, y0, x1, y1));
    }
}

/// The four corners, in order around, of the region a line covers.
fn line_outline(l: &Line, bits: u8) -> [(f64, f64); 4] {
    let scale = f64::from(1u32 << bits);
    let width = f64::from(l.width) / scale;
    if l.aa || width > 1.0 {
        // The anti-aliased line's 50 % coverage contour is its rectangle at half the
        // width (at least one pixel), the same shape a wide line fills.
        let half = if l.aa { width.max(1.0) } else { width } / 2.0;
        let (x0, y0) = (f64::from(l.from.x) / scale, f64::from(l.from.y) / scale);
        let (x1, y1) = (f64::from(l.to.x) / scale, f64::from(l.to.y) / scale);
        let (dx, dy) = (x1 - x0, y1 - y0);
        let len = dx.hypot(dy);
        let (nx, ny) = if len > 0.0 {
            (-dy / len * half, dx / len * half)
        } else {
            (0.0, half)
        };
        return [
            (x0 + nx, y0 + ny),
            (x1 + nx, y1 + ny),
            (x1 - nx, y1 - ny),
            (x0 - nx, y0 - ny),
        ];
    }
    // Pixel centres of the end points' pixels (floor, as the block's shift does).
    let centre = |p: Point| (f64::from(p.x >> bits) + 0.5, f64::from(p.y >> bits) + 0.5);
    let (a, b) = (centre(l.from), centre(l.to));
    let x_major = (b.0 - a.0).abs() >= (b.1 - a.1).abs();
    // (major, minor) coordinates, walking towards growing major.
    let mm = |p: (f64, f64)| if x_major { p } else { (p.1, p.0) };
    let back = |p: (f64, f64)| if x_major { p } else { (p.1, p.0) };
    let (s, e) = {
        let (s, e) = (mm(a), mm(b));
        if e.0 < s.0 {
            (e, s)
        } else {
            (s, e)
        }
    };
    let slope = if e.0 > s.0 {
        (e.1 - s.1) / (e.0 - s.0)
    } else {
        0.0
    };
    let (m0, n0) = (s.0 - 0.5, s.1 - 0.5 * slope);
    let (m1, n1) = (e.0 + 0.5, e.1 + 0.5 * slope);
    [
        back((m0, n0 - 0.5)),
        back((m1, n1 - 0.5)),
        back((m1, n1 + 0.5)),
        back((m0, n0 + 0.5)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::raster::{LineAlgo, Rgb, Shade, Triangle};

    fn setup(bits: u8) -> RasterSetup {
        RasterSetup {
            width: 16,
            height: 16,
            subpixel_bits: bits,
            background: Rgb::new(0, 0, 0),
            aa: Default::default(),
            cull: Default::default(),
            traversal: Default::default(),
        }
    }

    fn line(from: (i32, i32), to: (i32, i32), width: u32, aa: bool) -> RasterCmd {
        RasterCmd::Line(Line {
            from: Point {
                x: from.0,
                y: from.1,
            },
            to: Point { x: to.0, y: to.1 },
            color: Rgb::new(255, 255, 255),
            color_to: None,
            width,
            aa,
            algo: LineAlgo::Bresenham,
        })
    }

    #[test]
    fn triangle_sides_in_pixels() {
        let t = RasterCmd::Triangle(Triangle {
            v: [
                Point { x: 4, y: 2 },
                Point { x: 40, y: 2 },
                Point { x: 4, y: 30 },
            ],
            shade: Shade::Flat(Rgb::new(1, 2, 3)),
            z: None,
            w: None,
            tex: None,
        });
        let e = raster_edges(&setup(2), &[t, RasterCmd::Clear(Rgb::new(0, 0, 0))]);
        assert_eq!(
            e,
            [
                Edge::new(1.0, 0.5, 10.0, 0.5),
                Edge::new(10.0, 0.5, 1.0, 7.5),
                Edge::new(1.0, 7.5, 1.0, 0.5),
            ]
        );
    }

    #[test]
    fn thin_line_is_the_minor_axis_parallelogram_between_pixel_centres() {
        // From pixel (1, 1) (sub-pixel 1.75, 1.25) to pixel (5, 3): x-major, slope ½.
        let e = raster_edges(&setup(2), &[line((7, 5), (21, 13), 4, false)]);
        assert_eq!(
            e,
            [
                Edge::new(1.0, 0.75, 6.0, 3.25),
                Edge::new(6.0, 3.25, 6.0, 4.25),
                Edge::new(6.0, 4.25, 1.0, 1.75),
                Edge::new(1.0, 1.75, 1.0, 0.75),
            ]
        );
        // Reversed and y-major: the same region, its corners swapped back to (x, y).
        let e = raster_edges(&setup(0), &[line((3, 9), (1, 1), 1, false)]);
        assert_eq!(e[0], Edge::new(0.875, 1.0, 3.125, 10.0));
        assert_eq!(e[1], Edge::new(3.125, 10.0, 4.125, 10.0));
    }

    #[test]
    fn wide_line_is_its_rectangle() {
        // Horizontal, 3 px wide at 0 sub-pixel bits.
        let e = raster_edges(&setup(0), &[line((2, 5), (10, 5), 3, false)]);
        assert_eq!(e[0], Edge::new(2.0, 6.5, 10.0, 6.5));
        assert_eq!(e[2], Edge::new(10.0, 3.5, 2.0, 3.5));
        // Anti-aliased: at least one pixel wide.
        let e = raster_edges(&setup(0), &[line((2, 5), (10, 5), 0, true)]);
        assert_eq!(e[0], Edge::new(2.0, 5.5, 10.0, 5.5));
    }
}
