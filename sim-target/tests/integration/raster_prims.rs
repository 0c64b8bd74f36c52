//! Lines, circles, fills, polygons, Bézier curves and patches.

use proptest::prelude::*;
use protocol::raster::*;
use sim_target::raster::{circle, curve, line, Raster};
use std::collections::BTreeSet;

fn raster(w: u32, h: u32, bits: u8) -> Raster {
    let s = RasterSetup {
        width: w as u16,
        height: h as u16,
        subpixel_bits: bits,
        background: Rgb::new(0, 0, 0),
        aa: Aa::default(),
        cull: Cull::None,
        traversal: Traversal::Tiles,
    };
    Raster::new(w, h, &s).expect("setup")
}

fn pixels(a: (i64, i64), b: (i64, i64), algo: LineAlgo) -> Vec<(i64, i64)> {
    let mut v = Vec::new();
    line::thin_pixels(a, b, algo, &mut |x, y, _, _| v.push((x, y)));
    v
}

#[test]
fn bresenham_golden_vector() {
    // p₁ = 2Δy − Δx = −2; the tie at x = 4 (exact y 1.5) steps, as p = 0 does.
    let want = vec![
        (0, 0),
        (1, 0),
        (2, 1),
        (3, 1),
        (4, 2),
        (5, 2),
        (6, 2),
        (7, 3),
        (8, 3),
    ];
    assert_eq!(pixels((0, 0), (8, 3), LineAlgo::Bresenham), want);
    let mut rev = pixels((8, 3), (0, 0), LineAlgo::Bresenham);
    rev.sort();
    assert_eq!(rev, want);
}

fn check_line(a: (i64, i64), b: (i64, i64), algo: LineAlgo) -> Result<(), TestCaseError> {
    let fwd = pixels(a, b, algo);
    let back = pixels(b, a, algo);
    let fs: BTreeSet<_> = fwd.iter().copied().collect();
    let bs: BTreeSet<_> = back.iter().copied().collect();
    prop_assert_eq!(&fs, &bs, "A→B != B→A");
    prop_assert!(fs.contains(&a) && fs.contains(&b), "end points inclusive");
    let (dx, dy) = ((b.0 - a.0).abs(), (b.1 - a.1).abs());
    prop_assert_eq!(fwd.len() as i64, dx.max(dy) + 1, "one pixel per major step");
    prop_assert_eq!(fs.len(), fwd.len());
    for &(x, y) in &fwd {
        // Minor-axis distance to the true line at most ½.
        if dx >= dy && dx > 0 {
            let exact = a.1 as f64 + (x - a.0) as f64 * (b.1 - a.1) as f64 / (b.0 - a.0) as f64;
            prop_assert!((y as f64 - exact).abs() <= 0.5 + 1e-9);
        } else if dy > 0 {
            let exact = a.0 as f64 + (y - a.1) as f64 * (b.0 - a.0) as f64 / (b.1 - a.1) as f64;
            prop_assert!((x as f64 - exact).abs() <= 0.5 + 1e-9);
        }
    }
    Ok(())
}

#[test]
fn all_eight_octants() {
    for algo in [LineAlgo::Bresenham, LineAlgo::Dda] {
        for (dx, dy) in [
            (9, 4),
            (4, 9),
            (-4, 9),
            (-9, 4),
            (-9, -4),
            (-4, -9),
            (4, -9),
            (9, -4),
            (7, 7),
            (-7, 7),
            (0, 5),
            (5, 0),
            (0, 0),
        ] {
            check_line((20, 20), (20 + dx, 20 + dy), algo).expect("octant");
        }
    }
}

proptest! {
    #[test]
    fn lines_symmetric_and_exact(ax in -50i64..300, ay in -50i64..300, bx in -50i64..300, by in -50i64..300, dda in any::<bool>()) {
        check_line((ax, ay), (bx, by), if dda { LineAlgo::Dda } else { LineAlgo::Bresenham })?;
    }

    #[test]
    fn circles_within_half_a_pixel_and_symmetric(r in 0i64..300) {
        let pts = circle::outline(r);
        let set: BTreeSet<_> = pts.iter().copied().collect();
        for &(x, y) in &pts {
            let d = ((x * x + y * y) as f64).sqrt();
            prop_assert!((d - r as f64).abs() <= 0.5, "({x},{y}) at {d} for r {r}");
            for q in [(y, x), (-x, y), (x, -y), (-y, -x)] {
                prop_assert!(set.contains(&q), "8-way symmetry");
            }
        }
    }

    #[test]
    fn bezier_end_points_exact_and_flat(p in proptest::collection::vec((-4000i32..4000, -4000i32..4000), 3..=4), tol in 1u32..200) {
        let pts: heapless::Vec<Point, 4> = p.iter().map(|&(x, y)| Point { x, y }).collect();
        let poly = curve::flatten(&pts, tol).expect("arity");
        prop_assert_eq!(poly[0], pts[0]);
        prop_assert_eq!(*poly.last().expect("non-empty"), pts[pts.len() - 1]);
        let ctrl: Vec<(f64, f64)> = pts.iter().map(|q| (q.x as f64, q.y as f64)).collect();
        for k in 0..=400 {
            let c = curve::eval(&ctrl, k as f64 / 400.0);
            let d = poly.windows(2).map(|w| seg_dist(c, w[0], w[1])).fold(f64::INFINITY, f64::min);
            prop_assert!(d <= tol as f64 + 1e-6, "curve point {k} is {d} from the polyline (tol {tol})");
        }
    }
}

fn seg_dist(p: (f64, f64), a: Point, b: Point) -> f64 {
    let (ax, ay, bx, by) = (a.x as f64, a.y as f64, b.x as f64, b.y as f64);
    let (dx, dy) = (bx - ax, by - ay);
    let l2 = dx * dx + dy * dy;
    let t = if l2 == 0.0 {
        0.0
    } else {
        (((p.0 - ax) * dx + (p.1 - ay) * dy) / l2).clamp(0.0, 1.0)
    };
    (p.0 - ax - t * dx).hypot(p.1 - ay - t * dy)
}

#[test]
fn circle_d0_golden() {
    assert_eq!(circle::octant(5), vec![(0, 5), (1, 5), (2, 5), (3, 4)]);
    assert_eq!(circle::octant(1), vec![(0, 1)]);
}

#[test]
fn filled_circle_is_spans_around_the_outline() {
    let mut r = raster(64, 64, 4);
    r.framebuffer_mut().track_writes(true);
    let c = Circle {
        center: Point {
            x: 32 * 16,
            y: 32 * 16,
        },
        radius: 20 * 16,
        color: Rgb::new(0, 255, 0),
        fill: true,
    };
    r.draw(&RasterCmd::Circle(c)).expect("draw");
    assert_eq!(r.framebuffer().overdraw(), 0);
    for (dx, dy) in circle::outline(20) {
        assert_eq!(
            r.framebuffer().pixel((32 + dx) as u32, (32 + dy) as u32),
            Some(Rgb::new(0, 255, 0))
        );
    }
    for j in 0..64u32 {
        let row: Vec<bool> = (0..64)
            .map(|i| r.framebuffer().pixel(i, j) == Some(Rgb::new(0, 255, 0)))
            .collect();
        let runs = row.windows(2).filter(|w| w[0] != w[1]).count();
        assert!(runs == 0 || runs == 2, "row {j} is one span");
    }
}

#[test]
fn line_colour_interpolation_and_thickness() {
    let mut r = raster(64, 64, 4);
    let l = Line {
        from: Point {
            x: 2 * 16,
            y: 5 * 16,
        },
        to: Point {
            x: 60 * 16,
            y: 5 * 16,
        },
        color: Rgb::new(0, 0, 0),
        color_to: Some(Rgb::new(232, 116, 58)),
        width: 0,
        aa: false,
        algo: LineAlgo::Dda,
    };
    r.draw(&RasterCmd::Line(l)).expect("draw");
    assert_eq!(r.framebuffer().pixel(2, 5), Some(Rgb::new(0, 0, 0)));
    assert_eq!(r.framebuffer().pixel(60, 5), Some(Rgb::new(232, 116, 58)));
    assert_eq!(r.framebuffer().pixel(31, 5), Some(Rgb::new(116, 58, 29)));
    // Thick: 6 px wide diagonal; every drawn centre is within 3 px of the line, every
    // centre well inside is drawn.
    let mut r = raster(64, 64, 4);
    let t = Line {
        from: Point {
            x: 8 * 16,
            y: 10 * 16,
        },
        to: Point {
            x: 50 * 16,
            y: 40 * 16,
        },
        width: 6 * 16,
        color_to: None,
        color: Rgb::new(9, 9, 9),
        ..l
    };
    r.draw(&RasterCmd::Line(t)).expect("draw");
    let (x0, y0, x1, y1): (f64, f64, f64, f64) = (8.0, 10.0, 50.0, 40.0);
    let len = (x1 - x0).hypot(y1 - y0);
    let mut n = 0;
    for j in 0..64 {
        for i in 0..64 {
            let (px, py) = (i as f64 + 0.5 - x0, j as f64 + 0.5 - y0);
            let d = (px * (y1 - y0) - py * (x1 - x0)).abs() / len;
            let tpos = (px * (x1 - x0) + py * (y1 - y0)) / len;
            let on = r.framebuffer().pixel(i, j) == Some(Rgb::new(9, 9, 9));
            n += on as u32;
            if on {
                assert!(d <= 3.0 + 1e-9 && (-1e-9..=len + 1e-9).contains(&tpos));
            } else {
                assert!(
                    !(d < 2.99 && tpos > 0.01 && tpos < len - 0.01),
                    "hole at {i},{j}"
                );
            }
        }
    }
    assert!(n > 200);
}

#[test]
fn aa_line_covers_the_line_softly() {
    let mut r = raster(32, 32, 4);
    let l = Line {
        from: Point {
            x: 16 * 2 + 8,
            y: 16 * 3 + 8,
        },
        to: Point {
            x: 16 * 28 + 8,
            y: 16 * 20 + 8,
        },
        color: Rgb::new(255, 255, 255),
        color_to: None,
        width: 3 * 16,
        aa: true,
        algo: LineAlgo::Bresenham,
    };
    r.draw(&RasterCmd::Line(l)).expect("draw");
    let fb = r.framebuffer();
    // Butt ends through the end pixels' centres: half coverage there.
    assert!(fb.pixel(2, 3).is_some_and(|c| c.r >= 127));
    assert!(fb.pixel(28, 20).is_some_and(|c| c.r >= 127));
    let full = (0..32 * 32)
        .filter(|k| fb.pixel(k % 32, k / 32) == Some(Rgb::new(255, 255, 255)))
        .count();
    assert!(full > 10);
    let partial = (0..32 * 32)
        .filter(|k| matches!(fb.pixel(k % 32, k / 32), Some(c) if c.r > 0 && c.r < 255))
        .count();
    assert!(partial > 20, "edges are blended");
    assert_eq!(fb.pixel(2, 20), Some(Rgb::new(0, 0, 0)));
}

/// Four rooms split by a wall row (y = 5) and a wall column (x = 10) that cross at one
/// open cell, (10, 5). Its four direct neighbours are walls, so it joins the rooms only
/// through its diagonals: a 4-connected fill stays in one room, an 8-connected one
/// reaches all four.
fn maze(r: &mut Raster) {
    let wall = Rgb::new(255, 255, 255);
    for y in 0..12u32 {
        for x in 0..22u32 {
            if (x == 10) != (y == 5) {
                r.framebuffer_mut().put(x, y, wall);
            }
        }
    }
}

fn bfs(r: &Raster, seed: (u32, u32), eight: bool) -> BTreeSet<(u32, u32)> {
    let fb = r.framebuffer();
    let target = fb.pixel(seed.0, seed.1);
    let mut seen = BTreeSet::from([seed]);
    let mut q = vec![seed];
    while let Some((x, y)) = q.pop() {
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                if (dx == 0 && dy == 0) || (!eight && dx != 0 && dy != 0) {
                    continue;
                }
                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                if nx < 0 || ny < 0 {
                    continue;
                }
                let n = (nx as u32, ny as u32);
                if fb.pixel(n.0, n.1).is_some() && fb.pixel(n.0, n.1) == target && seen.insert(n) {
                    q.push(n);
                }
            }
        }
    }
    seen
}

fn fill_matches_bfs(mut r: Raster, seed: (u32, u32), eight: bool) -> usize {
    let want = bfs(&r, seed, eight);
    let red = Rgb::new(255, 0, 0);
    let f = SeedFill {
        seed: Pixel {
            x: seed.0 as u16,
            y: seed.1 as u16,
        },
        color: red,
        connectivity: if eight {
            Connectivity::Eight
        } else {
            Connectivity::Four
        },
    };
    r.draw(&RasterCmd::Fill(f)).expect("fill");
    let fb = r.framebuffer();
    let got: BTreeSet<(u32, u32)> = (0..fb.height())
        .flat_map(|y| (0..fb.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| fb.pixel(x, y) == Some(red))
        .collect();
    assert_eq!(got, want);
    got.len()
}

#[test]
fn maze_distinguishes_four_from_eight() {
    let mut r = raster(22, 12, 0);
    maze(&mut r);
    let four = fill_matches_bfs(r.clone(), (2, 2), false);
    let eight = fill_matches_bfs(r.clone(), (2, 2), true);
    assert!(
        eight > four,
        "8-connected fill leaks through the diagonal ({four} vs {eight})"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    #[test]
    fn seed_fill_equals_flood_reference(cells in proptest::collection::vec(0u8..100, 40 * 30), sx in 0u32..40, sy in 0u32..30, eight in any::<bool>()) {
        let mut r = raster(40, 30, 0);
        for (k, &c) in cells.iter().enumerate() {
            if c < 40 {
                r.framebuffer_mut().put(k as u32 % 40, k as u32 / 40, Rgb::new(255, 255, 255));
            }
        }
        fill_matches_bfs(r, (sx, sy), eight);
    }

    #[test]
    fn polygon_fill_equals_winding_reference(p in proptest::collection::vec((-100i32..700, -100i32..600), 3..12), nz in any::<bool>()) {
        let mut r = raster(40, 32, 4);
        let pts: heapless::Vec<Point, 16> = p.iter().map(|&(x, y)| Point { x, y }).collect();
        let rule = if nz { FillRule::NonZero } else { FillRule::EvenOdd };
        let col = Rgb::new(1, 2, 3);
        r.draw(&RasterCmd::Polygon(Polygon { points: pts.clone(), rule, color: col })).expect("draw");
        for j in 0..32i128 {
            for i in 0..40i128 {
                let (xc, yc) = (2 * i + 1, 2 * j + 1); // doubled pixel units × 16 / 16
                let (xc, yc) = (xc * 16, yc * 16);
                let mut wind = 0;
                let mut cnt = 0;
                for k in 0..pts.len() {
                    let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
                    let (a, b) = ((2 * a.x as i128, 2 * a.y as i128), (2 * b.x as i128, 2 * b.y as i128));
                    if a.1 == b.1 { continue; }
                    let (lo, hi, d) = if a.1 < b.1 { (a, b, 1) } else { (b, a, -1) };
                    if !(lo.1 <= yc && yc < hi.1) { continue; }
                    // crossing x ≤ xc ⇔ lo.x·den + (yc − lo.y)(hi.x − lo.x) ≤ xc·den
                    let den = hi.1 - lo.1;
                    if lo.0 * den + (yc - lo.1) * (hi.0 - lo.0) <= xc * den { wind += d; cnt += 1; }
                }
                let inside = if nz { wind != 0 } else { cnt % 2 == 1 };
                prop_assert_eq!(r.framebuffer().pixel(i as u32, j as u32) == Some(col), inside, "pixel {},{}", i, j);
            }
        }
    }
}

#[test]
fn pentagram_even_odd_versus_non_zero() {
    let star: heapless::Vec<Point, 16> = (0..5)
        .map(|k| {
            let a = -std::f64::consts::FRAC_PI_2 + k as f64 * 4.0 * std::f64::consts::PI / 5.0;
            Point {
                x: ((32.0 + 28.0 * a.cos()) * 16.0) as i32,
                y: ((32.0 + 28.0 * a.sin()) * 16.0) as i32,
            }
        })
        .collect();
    let col = Rgb::new(7, 7, 7);
    let mut eo = raster(64, 64, 4);
    eo.draw(&RasterCmd::Polygon(Polygon {
        points: star.clone(),
        rule: FillRule::EvenOdd,
        color: col,
    }))
    .expect("draw");
    let mut nz = raster(64, 64, 4);
    nz.draw(&RasterCmd::Polygon(Polygon {
        points: star,
        rule: FillRule::NonZero,
        color: col,
    }))
    .expect("draw");
    assert_ne!(
        eo.framebuffer().pixel(32, 33),
        Some(col),
        "even-odd leaves the centre empty"
    );
    assert_eq!(
        nz.framebuffer().pixel(32, 33),
        Some(col),
        "non-zero fills it"
    );
    assert_eq!(eo.framebuffer().pixel(32, 8), Some(col));
}

#[test]
fn bezier_patch_is_watertight() {
    let mut pts = [Point::default(); 16];
    for (k, p) in pts.iter_mut().enumerate() {
        let (i, j) = ((k % 4) as i32, (k / 4) as i32);
        *p = Point {
            x: (4 + i * 18 + j * j * 2) * 16 + 3,
            y: (4 + j * 17 + (i * (3 - i)) * 3) * 16 + 5,
        };
    }
    let mut r = raster(80, 80, 4);
    r.framebuffer_mut().track_writes(true);
    r.draw(&RasterCmd::Patch(BezierPatch {
        points: pts,
        steps: 9,
        color: Rgb::new(200, 100, 50),
    }))
    .expect("draw");
    assert_eq!(r.framebuffer().overdraw(), 0);
    assert_eq!(
        curve::patch_triangles(&BezierPatch {
            points: pts,
            steps: 9,
            color: Rgb::new(0, 0, 0)
        })
        .len(),
        162
    );
    // No cracks: no uncovered pixel has all four neighbours covered.
    let fb = r.framebuffer();
    let on = |i: u32, j: u32| fb.pixel(i, j) == Some(Rgb::new(200, 100, 50));
    let mut covered = 0;
    for j in 1..79 {
        for i in 1..79 {
            covered += on(i, j) as u32;
            assert!(
                on(i, j) || !(on(i - 1, j) && on(i + 1, j) && on(i, j - 1) && on(i, j + 1)),
                "crack at {i},{j}"
            );
        }
    }
    assert!(covered > 2000);
}

#[test]
fn bezier_draws_from_end_to_end() {
    let mut r = raster(64, 64, 4);
    let pts: heapless::Vec<Point, 4> = [(2, 60), (10, 0), (50, 64), (60, 4)]
        .iter()
        .map(|&(x, y)| Point {
            x: x * 16 + 8,
            y: y * 16 + 8,
        })
        .collect();
    r.draw(&RasterCmd::Bezier(Bezier {
        points: pts,
        color: Rgb::new(255, 255, 0),
        tolerance: 4,
    }))
    .expect("draw");
    assert_eq!(r.framebuffer().pixel(2, 60), Some(Rgb::new(255, 255, 0)));
    assert_eq!(r.framebuffer().pixel(60, 4), Some(Rgb::new(255, 255, 0)));
    let bad: heapless::Vec<Point, 4> = [Point::default(); 2].into_iter().collect();
    assert!(r
        .draw(&RasterCmd::Bezier(Bezier {
            points: bad,
            color: Rgb::new(0, 0, 0),
            tolerance: 1
        }))
        .is_err());
}

proptest! {
    #[test]
    fn drawn_lines_equal_the_walk(ax in 0i64..64, ay in 0i64..48, bx in -8i64..72, by in -8i64..56, dda in any::<bool>()) {
        // The raster's flat in-bounds fast path and the clipped general path must both
        // plot exactly the walk's pixels.
        let algo = if dda { LineAlgo::Dda } else { LineAlgo::Bresenham };
        let mut r = raster(64, 48, 4);
        let white = Rgb::new(255, 255, 255);
        let l = Line { from: Point { x: (ax as i32) * 16 + 3, y: (ay as i32) * 16 + 9 }, to: Point { x: (bx as i32) * 16 + 15, y: (by as i32) * 16 }, color: white, color_to: None, width: 0, aa: false, algo };
        r.draw(&RasterCmd::Line(l)).expect("draw");
        let want: BTreeSet<(i64, i64)> = pixels((ax, ay), (bx, by), algo).into_iter().filter(|&(x, y)| (0..64).contains(&x) && (0..48).contains(&y)).collect();
        let got: BTreeSet<(i64, i64)> = (0..48).flat_map(|y| (0..64).map(move |x| (x, y))).filter(|&(x, y)| r.framebuffer().pixel(x as u32, y as u32) == Some(white)).collect();
        prop_assert_eq!(got, want);
    }
}

#[test]
fn circle_outline_writes_each_pixel_once() {
    for radius in [0u32, 1, 2, 5, 17, 40] {
        let mut r = raster(100, 100, 4);
        r.framebuffer_mut().track_writes(true);
        let c = Circle {
            center: Point {
                x: 50 * 16,
                y: 50 * 16,
            },
            radius: radius * 16,
            color: Rgb::new(9, 8, 7),
            fill: false,
        };
        r.draw(&RasterCmd::Circle(c)).expect("draw");
        assert_eq!(r.framebuffer().overdraw(), 0, "r = {radius}");
        assert_eq!(
            r.framebuffer().fragments() as usize,
            circle::outline(radius as i64).len()
        );
    }
    let mut r = raster(10, 10, 0);
    let huge = Circle {
        center: Point { x: 5, y: 5 },
        radius: 5 * 4096,
        color: Rgb::new(1, 1, 1),
        fill: true,
    };
    assert!(
        r.draw(&RasterCmd::Circle(huge)).is_err(),
        "radius beyond four viewports is refused"
    );
}

/// The write log is the order a hardware block issues its memory writes: a clear as one
/// entry, a line in its canonical walk (the fast in-frame path is bypassed), a flat
/// triangle row by row from the top, left to right, clipped pixels absent; and the log
/// replayed over the frame before it gives the frame after it.
#[test]
fn recorded_writes_are_in_block_order_and_replay_to_the_frame() {
    use sim_target::raster::FbWrite;
    let mut r = raster(40, 30, 0);
    r.framebuffer_mut().record_writes(true);
    let white = Rgb::new(255, 255, 255);
    let red = Rgb::new(255, 0, 0);
    let p = |x, y| Point { x, y };
    r.draw(&RasterCmd::Clear(Rgb::new(0, 0, 85)))
        .expect("clear");
    let l = Line {
        from: p(35, 20),
        to: p(2, 3),
        color: white,
        color_to: None,
        width: 0,
        aa: false,
        algo: LineAlgo::Bresenham,
    };
    r.draw(&RasterCmd::Line(l)).expect("line");
    let t = Triangle {
        v: [p(30, 10), p(5, 25), p(60, 50)],
        shade: Shade::Flat(red),
        z: None,
        w: None,
        tex: None,
    };
    r.draw(&RasterCmd::Triangle(t)).expect("triangle");
    let log = r.framebuffer_mut().take_writes();

    assert_eq!(log[0], FbWrite::Clear(Rgb::new(0, 0, 85)));
    let walk = pixels((35, 20), (2, 3), LineAlgo::Bresenham);
    let drawn: Vec<(i64, i64)> = log[1..=walk.len()]
        .iter()
        .map(|w| match *w {
            FbWrite::Pixel { x, y, color } if color == white => (x as i64, y as i64),
            other => panic!("not a line pixel: {other:?}"),
        })
        .collect();
    assert_eq!(drawn, walk, "the line is logged in its walk order");
    let tri: Vec<(u32, u32)> = log[1 + walk.len()..]
        .iter()
        .map(|w| match *w {
            FbWrite::Pixel { x, y, color } if color == red => (y, x),
            other => panic!("not a triangle pixel: {other:?}"),
        })
        .collect();
    assert!(!tri.is_empty());
    assert!(
        tri.windows(2).all(|w| w[0] < w[1]),
        "rows top-down, left to right"
    );
    assert!(
        tri.iter().all(|&(y, x)| x < 40 && y < 30),
        "clipped to the frame"
    );

    let mut replay = raster(40, 30, 0);
    for w in &log {
        match *w {
            FbWrite::Clear(c) => replay.framebuffer_mut().clear(c),
            FbWrite::Pixel { x, y, color } => replay.framebuffer_mut().put(x, y, color),
        }
    }
    assert_eq!(replay.framebuffer().rgb(), r.framebuffer().rgb());
    assert!(r.framebuffer_mut().take_writes().is_empty(), "taken once");
}
