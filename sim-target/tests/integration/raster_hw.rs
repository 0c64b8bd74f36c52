//! The hardware model: FIFO back-pressure, cycle counts, board time.

use protocol::raster::*;
use sim_target::raster::{records, Raster, FIFO_DEPTH};

fn raster(t: Traversal) -> Raster {
    let s = RasterSetup {
        width: 256,
        height: 256,
        subpixel_bits: 4,
        background: Rgb::new(0, 0, 0),
        aa: Aa::default(),
        cull: Cull::None,
        traversal: t,
    };
    Raster::new(256, 256, &s).expect("setup")
}

fn big() -> RasterCmd {
    RasterCmd::Triangle(Triangle {
        v: [
            Point { x: 0, y: 0 },
            Point {
                x: 250 * 16,
                y: 10 * 16,
            },
            Point {
                x: 30 * 16,
                y: 250 * 16,
            },
        ],
        shade: Shade::Flat(Rgb::new(1, 2, 3)),
        z: None,
        w: None,
        tex: None,
    })
}

fn fitkit_line() -> RasterCmd {
    RasterCmd::Line(Line {
        from: Point { x: 16, y: 16 },
        to: Point { x: 32, y: 48 },
        color: Rgb::new(1, 1, 1),
        color_to: None,
        width: 0,
        aa: false,
        algo: LineAlgo::Bresenham,
    })
}

#[test]
fn seed_000_record_counts() {
    assert_eq!(
        records(&fitkit_line(), 4),
        2,
        "45-bit line: two 36-bit records"
    );
    assert_eq!(records(&big(), 4), 2, "63-bit triangle: two records");
    assert_eq!(
        records(&big(), 0),
        4,
        "beyond 9-bit coordinates: the wide layout"
    );
    let RasterCmd::Triangle(t) = big() else {
        unreachable!()
    };
    let rich = RasterCmd::Triangle(Triangle {
        shade: Shade::Gouraud([Rgb::new(0, 0, 0); 3]),
        z: Some([0; 3]),
        ..t
    });
    assert_eq!(records(&rich, 4), 7, "125 + 48 + 72 = 245 bits");
}

#[test]
fn full_fifo_stalls_the_controller() {
    let mut r = raster(Traversal::BoundingBox);
    for _ in 0..300 {
        r.draw(&big()).expect("draw");
    }
    let s = *r.stats();
    assert!(s.fifo_stalls > 0, "a slow block must push back");
    assert!(s.fifo_max <= FIFO_DEPTH);
    // The set-up's record, then two per triangle.
    assert_eq!(s.fifo_records, 1 + 300 * 2);
    assert!(s.end_cycle >= s.cycles.triangle);
    assert!((s.board_seconds() - s.end_cycle as f64 / 142e6).abs() < 1e-12);
    assert_eq!(s.commands, 300);
}

#[test]
fn slow_link_never_fills_the_fifo() {
    let mut r = raster(Traversal::Tiles);
    r.set_push_period(10_000);
    for _ in 0..100 {
        r.draw(&fitkit_line()).expect("draw");
    }
    let s = *r.stats();
    assert_eq!(s.fifo_stalls, 0);
    // Only the lines that arrive while the set-up clears the 256 × 256 frame (one pixel
    // per cycle) queue up; after it, each line is done before the next arrives.
    let during_clear = (256 * 256 / (2 * 10_000) + 1) as u32;
    assert!(s.fifo_max <= 2 * during_clear, "{}", s.fifo_max);
    // The link, not the block, sets the end time.
    assert!(s.end_cycle >= 100 * 2 * 10_000);
}

#[test]
fn traversal_cycle_costs() {
    let cycles = |t| {
        let mut r = raster(t);
        r.draw(&big()).expect("draw");
        (
            r.stats().cycles.triangle,
            r.stats().fragments,
            r.stats().pixel_tests,
        )
    };
    let (bbox, frags, bbox_tests) = cycles(Traversal::BoundingBox);
    let (simd, f2, _) = cycles(Traversal::Simd8);
    let (tiles, f3, tile_tests) = cycles(Traversal::Tiles);
    assert_eq!(frags, f2);
    assert_eq!(frags, f3);
    assert!(simd * 6 < bbox, "eight lanes: {simd} vs {bbox}");
    assert!(
        tile_tests * 4 < bbox_tests,
        "tiles test only edge blocks per pixel"
    );
    assert!(tiles < bbox);
    // Cycles never beat one fragment per lane per cycle.
    assert!(bbox >= frags && simd * 8 >= frags);
}
