//! embedded-graphics on the FPGA: `firmware::Canvas` over the golden model must draw
//! what embedded-graphics draws in software, pixel for pixel, or differ only where the
//! two fill rules do (a triangle's or circle's edge pixels), and its accelerated
//! primitives must cost one command each instead of one per pixel.

use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{
    Circle, Line, PrimitiveStyle, PrimitiveStyleBuilder, Rectangle, Styled, Triangle,
};
use firmware::{Accelerated, Canvas, CanvasCounters, CanvasError};
use sim_board::in_process::SimBus;
use sim_target::Device;

const W: u32 = 96;
const H: u32 = 64;
const BG: Rgb888 = Rgb888::new(0x10, 0x20, 0x30);

/// embedded-graphics' own rendering, into memory.
struct Soft(Vec<Rgb888>);

impl Soft {
    fn new() -> Self {
        Soft(vec![BG; (W * H) as usize])
    }
}

impl OriginDimensions for Soft {
    fn size(&self) -> Size {
        Size::new(W, H)
    }
}

impl DrawTarget for Soft {
    type Color = Rgb888;
    type Error = core::convert::Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        it: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in it {
            if (0..W as i32).contains(&p.x) && (0..H as i32).contains(&p.y) {
                self.0[(p.y as u32 * W + p.x as u32) as usize] = c;
            }
        }
        Ok(())
    }
}

fn canvas(layout: &'static protocol::bus::BusLayout) -> Canvas<SimBus> {
    Canvas::new(SimBus(Device::new(layout)), layout, W as u16, H as u16, BG).expect("set-up")
}

fn frame(c: &mut Canvas<SimBus>) -> Vec<Rgb888> {
    c.finish().expect("drawn");
    let fb = c.bus().0.raster().expect("a raster block").framebuffer();
    (0..H)
        .flat_map(|y| (0..W).map(move |x| (x, y)))
        .map(|(x, y)| {
            let p = fb.pixel(x, y).expect("in the frame");
            Rgb888::new(p.r, p.g, p.b)
        })
        .collect()
}

/// Pixels where the two frames differ, and how many of them are not on an edge of the
/// software drawing (a pixel whose 8-neighbourhood in either frame holds another colour).
fn diff(soft: &[Rgb888], fpga: &[Rgb888]) -> (usize, Vec<(u32, u32)>) {
    let at = |f: &[Rgb888], x: i32, y: i32| {
        ((0..W as i32).contains(&x) && (0..H as i32).contains(&y))
            .then(|| f[(y as u32 * W + x as u32) as usize])
    };
    let edge = |f: &[Rgb888], x: i32, y: i32| {
        let c = at(f, x, y);
        (-1..=1).any(|dy| (-1..=1).any(|dx| at(f, x + dx, y + dy).is_some_and(|n| Some(n) != c)))
    };
    let mut n = 0;
    let mut inner = Vec::new();
    for y in 0..H as i32 {
        for x in 0..W as i32 {
            if at(soft, x, y) != at(fpga, x, y) {
                n += 1;
                if !edge(soft, x, y) && !edge(fpga, x, y) {
                    inner.push((x as u32, y as u32));
                }
            }
        }
    }
    (n, inner)
}

fn fill(c: Rgb888) -> PrimitiveStyle<Rgb888> {
    PrimitiveStyle::with_fill(c)
}

fn stroke(c: Rgb888) -> PrimitiveStyle<Rgb888> {
    PrimitiveStyle::with_stroke(c, 1)
}

/// Draws `item` on a fresh canvas (accelerated) and in software; returns the pixel
/// differences, the interior ones and the canvas's bus counters.
fn compare<T: Accelerated + Drawable<Color = Rgb888>>(
    item: &T,
) -> (usize, Vec<(u32, u32)>, CanvasCounters) {
    let mut c = canvas(&protocol::bus::WIDE);
    c.draw(item).expect("drawn");
    let fpga = frame(&mut c);
    let mut soft = Soft::new();
    item.draw(&mut soft).expect("infallible");
    let (n, inner) = diff(&soft.0, &fpga);
    (n, inner, c.counters())
}

fn lines() -> Vec<Styled<Line, PrimitiveStyle<Rgb888>>> {
    let c = Rgb888::new(255, 255, 255);
    [
        ((2, 3), (90, 60)),
        ((90, 3), (2, 60)),
        ((5, 50), (80, 10)),
        ((40, 2), (45, 62)),
        ((45, 62), (40, 2)),
        ((0, 0), (95, 0)),
        ((10, 10), (10, 50)),
        ((3, 7), (93, 8)),
    ]
    .into_iter()
    .map(|((a, b), (x, y))| Line::new(Point::new(a, b), Point::new(x, y)).into_styled(stroke(c)))
    .collect()
}

#[test]
fn embedded_graphics_rectangles_and_clear_are_exact() {
    for r in [
        Rectangle::new(Point::new(3, 4), Size::new(20, 11)),
        Rectangle::new(Point::new(0, 0), Size::new(1, 1)),
        Rectangle::new(Point::new(80, 50), Size::new(40, 40)),
        Rectangle::new(Point::new(-5, -5), Size::new(12, 9)),
    ] {
        let item = r.into_styled(fill(Rgb888::new(200, 40, 90)));
        let (n, _, counters) = compare(&item);
        assert_eq!(n, 0, "{r:?}: {n} pixels differ");
        assert_eq!(counters.commands, 2, "{r:?}: a rectangle is two triangles");
    }
    // fill_solid of the whole frame and clear are one clear command.
    let mut c = canvas(&protocol::bus::WIDE);
    c.clear(Rgb888::new(1, 2, 3)).expect("cleared");
    c.fill_solid(
        &Rectangle::new(Point::zero(), Size::new(W, H)),
        Rgb888::new(9, 8, 7),
    )
    .expect("filled");
    assert_eq!(c.counters().commands, 2);
    assert!(frame(&mut c).iter().all(|&p| p == Rgb888::new(9, 8, 7)));
}

/// Lines: both are Bresenham, end points inclusive, one pixel per step of the major axis.
/// They may differ only in a step where the ideal line passes exactly half-way between
/// two pixels: the seed's decision variable (p₁ = 2Δy − Δx) steps the minor axis on a
/// tie, embedded-graphics' does not.
#[test]
fn embedded_graphics_lines_differ_only_at_ties() {
    let mut ties = 0;
    for l in lines() {
        let mut c = canvas(&protocol::bus::WIDE);
        c.draw(&l).expect("drawn");
        assert_eq!(c.counters().commands, 1);
        let fpga = frame(&mut c);
        let mut soft = Soft::new();
        l.draw(&mut soft).expect("infallible");
        let (a, b) = (l.primitive.start, l.primitive.end);
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let x_major = dx.abs() >= dy.abs();
        let (major, minor) = if x_major { (dx, dy) } else { (dy, dx) };
        let lit = |f: &[Rgb888], m: i32| -> Vec<i32> {
            // The minor coordinates lit at major coordinate `m`.
            (0..if x_major { H } else { W } as i32)
                .filter(|&n| {
                    let (x, y) = if x_major { (m, n) } else { (n, m) };
                    (0..W as i32).contains(&x)
                        && (0..H as i32).contains(&y)
                        && f[(y as u32 * W + x as u32) as usize] != BG
                })
                .collect()
        };
        let (m0, m1) = if x_major { (a.x, b.x) } else { (a.y, b.y) };
        for m in m0.min(m1)..=m0.max(m1) {
            let (s, f) = (lit(&soft.0, m), lit(&fpga, m));
            assert_eq!(f.len(), 1, "{:?}: {} pixels at {m}", l.primitive, f.len());
            if s != f {
                // Ideal minor offset at this step: minor · k / major, k steps from the
                // start; a tie when its fraction is exactly ½.
                let k = (m - m0).abs();
                let twice = 2 * (minor * k).abs() % (2 * major.abs());
                assert_eq!(
                    twice,
                    major.abs(),
                    "{:?}: step {m} differs ({s:?} vs {f:?}) and is not a tie",
                    l.primitive
                );
                assert_eq!((s[0] - f[0]).abs(), 1);
                ties += 1;
            }
        }
    }
    println!("{ties} tie steps differ over {} lines", lines().len());
}

#[test]
fn embedded_graphics_triangles_differ_only_on_edges() {
    let c = Rgb888::new(40, 200, 90);
    for v in [
        [(3, 3), (80, 12), (20, 60)],
        [(90, 2), (10, 30), (70, 62)],
        [(5, 5), (6, 40), (7, 6)],
        [(0, 0), (95, 0), (0, 63)],
    ] {
        let t = Triangle::new(
            Point::new(v[0].0, v[0].1),
            Point::new(v[1].0, v[1].1),
            Point::new(v[2].0, v[2].1),
        )
        .into_styled(fill(c));
        let (n, inner, counters) = compare(&t);
        assert_eq!(counters.commands, 1);
        assert!(
            inner.is_empty(),
            "{v:?}: {n} differ, off the edges at {inner:?}"
        );
        println!("triangle {v:?}: {n} edge pixels differ (fill rules)");
    }
}

#[test]
fn embedded_graphics_circles_differ_only_on_edges() {
    let c = Rgb888::new(250, 200, 0);
    for (d, style) in [(21, fill(c)), (31, stroke(c)), (9, fill(c)), (1, fill(c))] {
        let item = Circle::new(Point::new(30, 15), d).into_styled(style);
        let (n, inner, counters) = compare(&item);
        assert_eq!(counters.commands, 1);
        assert!(
            inner.is_empty(),
            "d {d}: {n} differ, off the edges at {inner:?}"
        );
        println!("circle d {d}: {n} boundary pixels differ (midpoint vs embedded-graphics)");
    }
}

#[test]
fn embedded_graphics_styles_the_block_cannot_draw_fall_back_to_pixels() {
    let c = Rgb888::new(0, 255, 0);
    let style = PrimitiveStyleBuilder::new()
        .stroke_color(c)
        .stroke_width(3)
        .fill_color(Rgb888::new(0, 0, 255))
        .build();
    let t = Triangle::new(Point::new(10, 10), Point::new(60, 20), Point::new(30, 50))
        .into_styled(style);
    let (n, _, counters) = compare(&t);
    assert_eq!(n, 0, "the pixel path is exactly embedded-graphics'");
    assert!(counters.commands > 100, "{counters:?}");
    // An even diameter has no centre pixel for the block's circle.
    let (n, _, counters) = compare(&Circle::new(Point::new(5, 5), 10).into_styled(fill(c)));
    assert_eq!(n, 0);
    assert!(counters.commands > 10);
}

#[test]
fn embedded_graphics_on_the_fitkit_layout_refuses_a_circle_by_name() {
    let mut c = canvas(&protocol::bus::FITKIT);
    let item = Circle::new(Point::new(5, 5), 11).into_styled(fill(Rgb888::new(255, 0, 0)));
    let err = c.draw(&item).expect_err("no circle unit on the FITkit");
    assert!(matches!(err, CanvasError::Layout(_)), "{err:?}");
    assert!(err.to_string().contains("circle"), "{err}");
    // Its pixels still go: pixel by pixel.
    c.draw_pixels(&item).expect("pixels");
    // Lines and rectangles are accelerated on the FITkit too, at whole pixels.
    for l in lines() {
        c.draw(&l).expect("a FITkit line");
    }
}

/// Bytes on the bus per primitive, accelerated against pixel by pixel (printed: the
/// table in docs/embedded-graphics.md comes from `cargo test -p sim-board --test
/// embedded_graphics bytes -- --nocapture`).
#[test]
fn embedded_graphics_bytes_per_primitive() {
    /// Draws `item` both ways on fresh canvases: (accelerated, pixel by pixel).
    fn both<T: Accelerated>(item: &T) -> (CanvasCounters, CanvasCounters) {
        let mut acc = canvas(&protocol::bus::WIDE);
        acc.draw(item).expect("drawn");
        let mut px = canvas(&protocol::bus::WIDE);
        px.draw_pixels(item).expect("drawn");
        (acc.counters(), px.counters())
    }
    let c = Rgb888::new(255, 255, 255);
    let rows = [
        (
            "line 88 px",
            both(&Line::new(Point::new(2, 3), Point::new(90, 60)).into_styled(stroke(c))),
        ),
        (
            "triangle",
            both(
                &Triangle::new(Point::new(3, 3), Point::new(80, 12), Point::new(20, 60))
                    .into_styled(fill(c)),
            ),
        ),
        (
            "disc d 41",
            both(&Circle::new(Point::new(20, 10), 41).into_styled(fill(c))),
        ),
        (
            "rectangle 60 x 40",
            both(&Rectangle::new(Point::new(10, 10), Size::new(60, 40)).into_styled(fill(c))),
        ),
    ];
    println!(
        "| primitive | accelerated: commands, bytes | pixel by pixel: commands, bytes | ratio |"
    );
    println!("|---|---|---|---|");
    for (name, (a, p)) in rows {
        let ratio = p.bits as f64 / a.bits as f64;
        println!(
            "| {name} | {}, {} B | {}, {} B | {ratio:.0}× |",
            a.commands,
            a.bits / 8,
            p.commands,
            p.bits / 8
        );
        assert!(ratio > 10.0, "{name}: only {ratio:.1}× fewer bytes");
    }
}
