//! A frozen scene with every primitive: the framebuffer's FNV-1a hash per traversal is a
//! regression vector for the bit-exact contract (any change of a single pixel fails).
//! The hash was recorded from this model after the property tests above passed; it is
//! a change detector, not an independent reference.

use protocol::raster::*;
use sim_target::raster::Raster;

fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

fn p(x: f64, y: f64) -> Point {
    Point {
        x: (x * 16.0 + 0.5).floor() as i32,
        y: (y * 16.0 + 0.5).floor() as i32,
    }
}

fn scene() -> Vec<RasterCmd> {
    let c = |r, g, b| Rgb::new(r, g, b);
    let line = |a: Point, b: Point, algo, width, aa, color_to| {
        RasterCmd::Line(Line {
            from: a,
            to: b,
            color: c(255, 255, 255),
            color_to,
            width,
            aa,
            algo,
        })
    };
    let mut patch = [Point::default(); 16];
    for (k, q) in patch.iter_mut().enumerate() {
        let (i, j) = ((k % 4) as f64, (k / 4) as f64);
        *q = p(
            90.0 + i * 10.0 + j * 2.0,
            60.0 + j * 9.0 + (i - 1.5) * (i - 1.5) * 2.0,
        );
    }
    vec![
        RasterCmd::Triangle(Triangle {
            v: [p(10.5, 20.25), p(100.0, 30.0), p(50.0, 90.75)],
            shade: Shade::Flat(c(255, 128, 0)),
            z: None,
            w: None,
            tex: None,
        }),
        RasterCmd::Triangle(Triangle {
            v: [p(60.0, 5.0), p(120.0, 50.0), p(70.0, 70.0)],
            shade: Shade::Gouraud([c(255, 0, 0), c(0, 255, 0), c(0, 0, 255)]),
            z: Some([1000, 9_000_000, 16_000_000]),
            w: Some([65536, 3 * 65536, 65536 / 2]),
            tex: None,
        }),
        line(
            p(3.0, 4.0),
            p(100.0, 50.0),
            LineAlgo::Bresenham,
            0,
            false,
            None,
        ),
        line(
            p(3.0, 50.0),
            p(40.0, 110.0),
            LineAlgo::Dda,
            0,
            false,
            Some(c(0, 0, 255)),
        ),
        line(
            p(5.0, 100.0),
            p(60.0, 80.0),
            LineAlgo::Bresenham,
            48,
            false,
            None,
        ),
        line(
            p(70.0, 110.0),
            p(120.0, 90.0),
            LineAlgo::Bresenham,
            24,
            true,
            None,
        ),
        RasterCmd::Circle(Circle {
            center: p(30.0, 60.0),
            radius: 15 * 16,
            color: c(0, 255, 0),
            fill: false,
        }),
        RasterCmd::Circle(Circle {
            center: p(100.0, 100.0),
            radius: 10 * 16,
            color: c(0, 128, 255),
            fill: true,
        }),
        RasterCmd::Polygon(Polygon {
            points: [
                p(5.0, 5.0),
                p(30.0, 10.0),
                p(10.0, 30.0),
                p(30.0, 30.0),
                p(8.0, 12.0),
            ]
            .into_iter()
            .collect(),
            rule: FillRule::EvenOdd,
            color: c(200, 200, 0),
        }),
        RasterCmd::Bezier(Bezier {
            points: [
                p(10.0, 120.0),
                p(40.0, 60.0),
                p(80.0, 125.0),
                p(125.0, 70.0),
            ]
            .into_iter()
            .collect(),
            color: c(255, 255, 0),
            tolerance: 8,
        }),
        RasterCmd::Patch(BezierPatch {
            points: patch,
            steps: 6,
            color: c(180, 90, 200),
        }),
        RasterCmd::Fill(SeedFill {
            seed: Pixel { x: 126, y: 2 },
            color: c(0, 0, 80),
            connectivity: Connectivity::Four,
        }),
    ]
}

fn render(t: Traversal) -> u64 {
    let s = RasterSetup {
        width: 128,
        height: 128,
        subpixel_bits: 4,
        background: Rgb::new(0, 0, 0),
        aa: Aa::default(),
        cull: Cull::None,
        traversal: t,
    };
    let mut r = Raster::new(128, 128, &s).expect("setup");
    for cmd in scene() {
        r.draw(&cmd).expect("draw");
    }
    fnv(r.framebuffer().rgb())
}

#[test]
fn every_traversal_renders_the_frozen_scene() {
    let h = render(Traversal::BoundingBox);
    for t in [
        Traversal::Scanline,
        Traversal::Zigzag,
        Traversal::Tiles,
        Traversal::Simd8,
    ] {
        assert_eq!(render(t), h, "{t:?}");
    }
    println!("scene hash {h:#018x}");
    assert_eq!(h, GOLDEN);
}

const GOLDEN: u64 = 0x7d68_767b_5386_a0f8;
