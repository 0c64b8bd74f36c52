//! Triangle coverage against an exact brute-force reference, for every traversal.

use proptest::prelude::*;
use protocol::raster::*;
use protocol::MAX_FRAME_SIDE;
use sim_target::raster::{oracle, tri, Raster, RasterError};

fn setup(w: u16, h: u16, bits: u8, t: Traversal) -> RasterSetup {
    RasterSetup {
        width: w,
        height: h,
        subpixel_bits: bits,
        background: Rgb::new(0, 0, 0),
        aa: Aa::default(),
        cull: Cull::None,
        traversal: t,
    }
}

/// The top-left oracle the block is checked against (also `fpgfx stress`'s), with both
/// windings drawn.
fn ref_inside(v: &[Point; 3], bits: u8, i: i64, j: i64) -> bool {
    oracle::covers(v, bits, Cull::None, i, j)
}

fn reference(v: &[Point; 3], bits: u8, w: u16, h: u16) -> Vec<u8> {
    let mut out = vec![0u8; w as usize * h as usize];
    for j in 0..h as i64 {
        for i in 0..w as i64 {
            out[j as usize * w as usize + i as usize] = ref_inside(v, bits, i, j) as u8;
        }
    }
    out
}

fn render(tris: &[[Point; 3]], bits: u8, w: u16, h: u16, t: Traversal) -> (Vec<u8>, u64) {
    let mut r = Raster::new(w as u32, h as u32, &setup(w, h, bits, t)).expect("setup");
    r.framebuffer_mut().track_writes(true);
    for v in tris {
        r.draw(&RasterCmd::Triangle(Triangle {
            v: *v,
            shade: Shade::Flat(Rgb::new(255, 255, 255)),
            z: None,
            w: None,
            tex: None,
        }))
        .expect("draw");
    }
    let fb = r.framebuffer();
    (fb.write_counts().expect("tracked").to_vec(), fb.overdraw())
}

fn check(v: [Point; 3], bits: u8, w: u16, h: u16) -> Result<(), TestCaseError> {
    let want = reference(&v, bits, w, h);
    for t in Traversal::ALL {
        let (got, over) = render(&[v], bits, w, h, t);
        prop_assert_eq!(over, 0);
        prop_assert!(
            got == want,
            "{:?} differs from reference for {:?} bits {}",
            t,
            v,
            bits
        );
    }
    Ok(())
}

fn pt(range: std::ops::Range<i32>) -> impl Strategy<Value = Point> {
    (range.clone(), range).prop_map(|(x, y)| Point { x, y })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn random_triangles_match_reference(bits in 0u8..=8, a in pt(-3000..23000), b in pt(-3000..23000), c in pt(-3000..23000)) {
        // Coordinates are interpreted at `bits`; scale so the triangle lands near the
        // 64 × 48 viewport whatever the precision.
        let s = |p: Point| Point { x: (p.x >> (8 - bits)), y: (p.y >> (8 - bits)) * 3 / 4 };
        check([s(a), s(b), s(c)], bits, 64, 48)?;
    }

    #[test]
    fn slivers_match_reference(bits in 4u8..=8, a in pt(0..16000), d in pt(-200..200), t in 0i32..16) {
        // Long thin triangles: the third vertex is close to the first two's line.
        let b = Point { x: 16000 - a.x, y: 12000 - a.y.min(12000) };
        let m = Point { x: a.x + (b.x - a.x) * t / 16 + d.x / 8, y: a.y + (b.y - a.y) * t / 16 + d.y / 8 };
        let s = |p: Point| Point { x: p.x >> (8 - bits), y: p.y >> (8 - bits) };
        check([s(a), s(b), s(m)], bits, 64, 48)?;
    }

    #[test]
    fn guard_band_vertices_match_reference(
        bits in 0u8..=8,
        v in proptest::collection::vec((-tri::COORD_LIMIT..=tri::COORD_LIMIT, -tri::COORD_LIMIT..=tri::COORD_LIMIT, 0u8..4), 3),
    ) {
        // Each coordinate is random in the guard band, or pinned to one of its limits,
        // or near the viewport: the huge edge values must stay exact.
        let l = tri::COORD_LIMIT;
        let pick = |c: i32, k: u8| match k { 0 => c, 1 => l, 2 => -l, _ => c.rem_euclid(64 << bits) };
        let p: Vec<Point> = v.iter().map(|&(x, y, k)| Point { x: pick(x, k), y: pick(y, k.wrapping_add(x as u8) % 4) }).collect();
        check([p[0], p[1], p[2]], bits, 64, 48)?;
    }

    #[test]
    fn degenerate_and_grid_aligned(a in pt(0..64), b in pt(0..64), k in -3i32..4) {
        // Vertices on pixel centres and corners (quarter-pixel units: even = ½ px), so
        // plus collinear triples (zero area: nothing drawn).
        let bits = 2;
        let s = |p: Point| Point { x: p.x * 2, y: p.y * 2 };
        let c = Point { x: a.x + k * (b.x - a.x), y: a.y + k * (b.y - a.y) };
        check([s(a), s(b), s(c)], bits, 40, 40)?;
        check([s(a), s(b), Point { x: a.x * 4, y: b.y * 4 }], bits, 40, 40)?;
        // Axis-aligned right triangles: horizontal and vertical edges through centres.
        check([s(a), Point { x: s(b).x, y: s(a).y }, s(b)], bits, 40, 40)?;
        check([s(a), Point { x: s(a).x, y: s(b).y }, s(b)], bits, 40, 40)?;
    }
}

#[test]
fn viewport_limit_vertices() {
    // Vertices at ±COORD_LIMIT: edge values must stay exact in i64. The block is run at
    // the largest viewport; rows are spot-checked against the i128 reference.
    let l = tri::COORD_LIMIT;
    let cases = [
        [
            Point { x: -l, y: -l },
            Point { x: l, y: -l + 7 },
            Point { x: -l + 3, y: l },
        ],
        [
            Point { x: l, y: l },
            Point { x: -l, y: 1234 },
            Point { x: 1000, y: -l },
        ],
        [
            Point { x: -l, y: 0 },
            Point { x: l, y: 1 },
            Point {
                x: 0,
                y: 2 * 256 * 4096 / 3,
            },
        ],
    ];
    let dim = MAX_FRAME_SIDE;
    for v in cases {
        // The i64 bound documented in tri.rs: |E| < 2^52 anywhere in the viewport.
        let s = tri::setup(&v, 8, dim, dim, Cull::None).expect("covers the viewport");
        for e in s.edges {
            for (i, j) in [
                (0, 0),
                (dim as i64, 0),
                (0, dim as i64),
                (dim as i64, dim as i64),
            ] {
                let exact = e.a as i128 * i as i128 + e.b as i128 * j as i128 + e.c as i128;
                assert!(
                    exact.abs() < 1i128 << 52,
                    "edge value {exact} beyond the documented bound"
                );
            }
        }
        for t in Traversal::ALL {
            let mut rows = vec![Vec::new(); dim as usize];
            let mut c = tri::TravCounters::default();
            tri::traverse(&s, t, &mut c, &mut |y, x0, x1| {
                rows[y as usize].push((x0, x1))
            });
            for j in (0..dim).step_by(331) {
                let mut got = vec![false; dim as usize];
                for &(a, b) in &rows[j as usize] {
                    for x in a..b {
                        assert!(!got[x as usize], "pixel emitted twice");
                        got[x as usize] = true;
                    }
                }
                for i in 0..dim {
                    assert_eq!(
                        got[i as usize],
                        ref_inside(&v, 8, i as i64, j as i64),
                        "{t:?} row {j} col {i}"
                    );
                }
            }
        }
    }
}

#[test]
fn coordinates_beyond_the_guard_band_are_refused() {
    let mut r = Raster::new(16, 16, &setup(16, 16, 8, Traversal::Tiles)).expect("setup");
    let bad = Triangle {
        v: [
            Point {
                x: tri::COORD_LIMIT + 1,
                y: 0,
            },
            Point { x: 0, y: 5 },
            Point { x: 9, y: 9 },
        ],
        shade: Shade::Flat(Rgb::new(1, 2, 3)),
        z: None,
        w: None,
        tex: None,
    };
    assert!(matches!(
        r.draw(&RasterCmd::Triangle(bad)),
        Err(RasterError::Coordinate {
            field: "triangle.v[0]",
            ..
        })
    ));
    assert!(Raster::new(16, 16, &setup(16, 16, 9, Traversal::Tiles)).is_err());
    assert!(Raster::new(0, 16, &setup(16, 16, 8, Traversal::Tiles)).is_err());
}

/// A perturbed grid mesh plus a fan: shared edges of every orientation.
fn mesh() -> Vec<[Point; 3]> {
    let mut tris = Vec::new();
    let n = 6;
    let mut seed = 12345u32;
    let mut rnd = move |m: i32| {
        seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12345);
        (seed >> 16) as i32 % m
    };
    let mut g = vec![vec![Point::default(); n + 1]; n + 1];
    for (j, row) in g.iter_mut().enumerate() {
        for (i, p) in row.iter_mut().enumerate() {
            let jit = |k: usize, r: i32| if k == 0 || k == n { 0 } else { r - 500 };
            *p = Point {
                x: (i as i32 * 10 * 256) + jit(i, rnd(1000)) + 512,
                y: (j as i32 * 8 * 256) + jit(j, rnd(1000)) + 256,
            };
        }
    }
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (g[j][i], g[j][i + 1], g[j + 1][i], g[j + 1][i + 1]);
            if (i + j) % 2 == 0 {
                tris.push([a, b, c]);
                tris.push([b, d, c]);
            } else {
                tris.push([a, d, b]);
                tris.push([a, c, d]);
            }
        }
    }
    // A fan with pixel-aligned spokes (exact ties on edges and at the hub).
    let hub = Point {
        x: 40 * 256 + 128,
        y: 70 * 256 + 128,
    };
    let rim: Vec<Point> = (0..12)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 12.0;
            Point {
                x: hub.x + (a.cos() * 20.0).round() as i32 * 256,
                y: hub.y + (a.sin() * 15.0).round() as i32 * 256,
            }
        })
        .collect();
    for k in 0..12 {
        tris.push([hub, rim[k], rim[(k + 1) % 12]]);
    }
    tris
}

#[test]
fn mesh_is_watertight_for_every_traversal() {
    let tris = mesh();
    let (w, h) = (72, 96);
    let mut want = vec![0u8; w * h];
    for v in &tris {
        for (k, c) in reference(v, 8, w as u16, h as u16).into_iter().enumerate() {
            want[k] += c;
        }
    }
    assert!(
        want.iter().all(|&c| c <= 1),
        "reference itself double-covers"
    );
    // The interior of the grid has no holes: every pixel centre in it is covered once.
    for j in 2..46 {
        for i in 3..60 {
            assert_eq!(want[j * w + i], 1, "crack at {i},{j}");
        }
    }
    for t in Traversal::ALL {
        let (got, over) = render(&tris, 8, w as u16, h as u16, t);
        assert_eq!(over, 0, "{t:?} overdraw");
        assert_eq!(got, want, "{t:?}");
    }
}

#[test]
fn zigzag_keeps_thin_triangles_the_seed_rule_loses() {
    // A thin diagonal sliver crossing the middle of an 8 × 8 block: each corner of the
    // block is outside (by different edges), yet the diagonal pixels are inside.
    let bits = 8;
    let s = 256;
    // Spine y = (x − ½)/2 + 2½ passes through the centre of pixel (16, 10).
    let v = [
        Point { x: 0, y: 576 },
        Point {
            x: 64 * s,
            y: 8768 + 205,
        },
        Point {
            x: 64 * s,
            y: 8768 - 205,
        },
    ];
    let st = tri::setup(&v, bits, 64, 64, Cull::None).expect("visible");
    let (bx, by) = (16, 8);
    let (x1, y1) = (bx + tri::ZIGZAG_BLOCK - 1, by + tri::ZIGZAG_BLOCK - 1);
    assert!(
        tri::seed004_rejects(&st.edges, bx, by, x1, y1),
        "seed 004's rule would drop this block"
    );
    assert_ne!(tri::classify(&st.edges, bx, by, x1, y1), tri::Class::Reject);
    assert!(ref_inside(&v, bits, 16, 10), "the block has covered pixels");
    let (got, _) = render(&[v], bits, 64, 64, Traversal::Zigzag);
    assert_eq!(got, reference(&v, bits, 64, 64));
}

fn draw_one(t: Triangle, cull: Cull) -> Raster {
    let mut s = setup(32, 32, 4, Traversal::Tiles);
    s.cull = cull;
    let mut r = Raster::new(32, 32, &s).expect("setup");
    r.draw(&RasterCmd::Triangle(t)).expect("draw");
    r
}

fn tri16(v: [(i32, i32); 3], shade: Shade) -> Triangle {
    Triangle {
        v: v.map(|(x, y)| Point {
            x: x * 16,
            y: y * 16,
        }),
        shade,
        z: None,
        w: None,
        tex: None,
    }
}

#[test]
fn back_face_culling_by_screen_winding() {
    let red = Shade::Flat(Rgb::new(255, 0, 0));
    // (0,0) → (30,0) → (0,30) runs clockwise on a y-down screen.
    let cw = tri16([(0, 0), (30, 0), (0, 30)], red);
    let lit = |r: &Raster| r.framebuffer().fragments();
    assert_eq!(lit(&draw_one(cw, Cull::Clockwise)), 0);
    assert!(lit(&draw_one(cw, Cull::CounterClockwise)) > 0);
    assert!(lit(&draw_one(cw, Cull::None)) > 0);
    let ccw = tri16([(0, 0), (0, 30), (30, 0)], red);
    assert_eq!(lit(&draw_one(ccw, Cull::CounterClockwise)), 0);
    assert!(lit(&draw_one(ccw, Cull::Clockwise)) > 0);
}

fn bary(v: &[Point; 3], bits: u8, i: u32, j: u32) -> [f64; 3] {
    let s = (1 << bits) as f64;
    let p: Vec<(f64, f64)> = v.iter().map(|q| (q.x as f64 / s, q.y as f64 / s)).collect();
    let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
    let e = |a: (f64, f64), b: (f64, f64)| (x - a.0) * (b.1 - a.1) - (y - a.1) * (b.0 - a.0);
    let area = e(p[1], p[2]) + e(p[2], p[0]) + e(p[0], p[1]);
    [
        e(p[1], p[2]) / area,
        e(p[2], p[0]) / area,
        e(p[0], p[1]) / area,
    ]
}

#[test]
fn gouraud_matches_barycentric_reference() {
    let cols = [
        Rgb::new(255, 0, 0),
        Rgb::new(0, 255, 0),
        Rgb::new(0, 0, 255),
    ];
    for v in [[(1, 1), (30, 3), (5, 29)], [(1, 1), (5, 29), (30, 3)]] {
        let t = tri16(v, Shade::Gouraud(cols));
        let r = draw_one(t, Cull::None);
        let mut n = 0;
        for j in 0..32 {
            for i in 0..32 {
                if !ref_inside(&t.v, 4, i as i64, j as i64) {
                    continue;
                }
                n += 1;
                let l = bary(&t.v, 4, i, j);
                let px = r.framebuffer().pixel(i, j).expect("in range");
                let want = [l[0] * 255.0, l[1] * 255.0, l[2] * 255.0];
                for (g, w) in [px.r, px.g, px.b].iter().zip(want) {
                    assert!((*g as f64 - w).abs() <= 0.5 + 1e-9, "({i},{j}) {g} vs {w}");
                }
            }
        }
        assert!(n > 100);
    }
}

#[test]
fn perspective_correct_colour() {
    let cols = [
        Rgb::new(255, 0, 0),
        Rgb::new(0, 255, 0),
        Rgb::new(0, 0, 255),
    ];
    let mut t = tri16([(1, 1), (30, 3), (5, 29)], Shade::Gouraud(cols));
    // Equal w: identical to affine.
    t.w = Some([3 << 16; 3]);
    let affine = draw_one(Triangle { w: None, ..t }, Cull::None);
    assert_eq!(
        draw_one(t, Cull::None).framebuffer().rgb(),
        affine.framebuffer().rgb()
    );
    let w = [1.0f64, 4.0, 0.5];
    t.w = Some(w.map(|w| (w * 65536.0) as u32));
    let r = draw_one(t, Cull::None);
    let mut differs = false;
    for j in 0..32 {
        for i in 0..32 {
            if !ref_inside(&t.v, 4, i as i64, j as i64) {
                continue;
            }
            let l = bary(&t.v, 4, i, j);
            let q: Vec<f64> = (0..3).map(|k| l[k] / w[k]).collect();
            let sum: f64 = q.iter().sum();
            let want = [q[0] / sum * 255.0, q[1] / sum * 255.0, q[2] / sum * 255.0];
            let px = r.framebuffer().pixel(i, j).expect("in range");
            for (g, w) in [px.r, px.g, px.b].iter().zip(want) {
                assert!((*g as f64 - w).abs() <= 0.5 + 1e-6, "({i},{j}) {g} vs {w}");
            }
            differs |= affine.framebuffer().pixel(i, j) != Some(px);
        }
    }
    assert!(differs, "perspective must change something");
}

#[test]
fn z_test_less_is_order_independent() {
    let near = Triangle {
        z: Some([100, 100, 100]),
        ..tri16([(0, 0), (31, 0), (0, 31)], Shade::Flat(Rgb::new(255, 0, 0)))
    };
    let far = Triangle {
        z: Some([200, 5000, 90000]),
        ..tri16(
            [(31, 31), (0, 2), (31, 0)],
            Shade::Flat(Rgb::new(0, 0, 255)),
        )
    };
    let mut a = Raster::new(32, 32, &setup(32, 32, 4, Traversal::Scanline)).expect("setup");
    let mut b = a.clone();
    for t in [near, far] {
        a.draw(&RasterCmd::Triangle(t)).expect("draw");
    }
    for t in [far, near] {
        b.draw(&RasterCmd::Triangle(t)).expect("draw");
    }
    assert_eq!(a.framebuffer().rgb(), b.framebuffer().rgb());
    assert_eq!(a.framebuffer().pixel(5, 5), Some(Rgb::new(255, 0, 0)));
    assert_eq!(a.framebuffer().pixel(28, 28), Some(Rgb::new(0, 0, 255)));
    // Equal depth does not pass "less": the second triangle loses.
    let mut c = Raster::new(32, 32, &setup(32, 32, 4, Traversal::Scanline)).expect("setup");
    c.draw(&RasterCmd::Triangle(near)).expect("draw");
    c.draw(&RasterCmd::Triangle(Triangle {
        shade: Shade::Flat(Rgb::new(0, 255, 0)),
        ..near
    }))
    .expect("draw");
    assert_eq!(c.framebuffer().pixel(5, 5), Some(Rgb::new(255, 0, 0)));
}

#[test]
fn viewport_clipping_of_partly_outside_triangles() {
    let v = [
        Point { x: -400, y: -300 },
        Point { x: 900, y: 100 },
        Point { x: 50, y: 1000 },
    ];
    let want = reference(&v, 4, 32, 32);
    for t in Traversal::ALL {
        let (got, _) = render(&[v], 4, 32, 32, t);
        assert_eq!(got, want);
    }
}
