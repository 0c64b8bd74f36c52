//! The traversal's counters, pixels and framebuffer against the pixel walks of
//! [`super::walk_oracle`], on random triangles of every kind the model meets.

use proptest::prelude::*;
use protocol::raster::{Cull, Point, Rgb, Traversal};

use super::{setup, traverse, walk_oracle, EdgeWalk, TravCounters, COORD_LIMIT};
use crate::raster::Framebuffer;
use protocol::raster::MAX_SUBPIXEL_BITS;

/// Spans drawn into a write-tracked framebuffer: the order-insensitive result, with
/// every pixel's write count.
fn drawn(w: u32, h: u32, spans: &[(u32, u32, u32)]) -> Framebuffer {
    let mut fb = Framebuffer::new(w, h, Rgb::new(0, 0, 0));
    fb.track_writes(true);
    for &(y, a, b) in spans {
        fb.fill_span(y, a, b, Rgb::new(255, 128, 0));
    }
    fb
}

/// Whether a triangle was visible; fails the case on any difference between the
/// accounting and the walk.
fn check(v: &[Point; 3], bits: u8, w: u32, h: u32) -> Result<bool, TestCaseError> {
    let Some(s) = setup(v, bits, w, h, Cull::None) else {
        return Ok(false);
    };
    // The walk in i32, where it fits, steps the same bounds as in i64 over every row.
    let rows = s.bbox[3] - s.bbox[1];
    let mut wide = EdgeWalk::new(&s);
    if let Some(mut narrow) = wide.narrow::<i32>(rows) {
        for row in 0..rows {
            prop_assert_eq!(narrow.next_row(), wide.next_row(), "row {} of {:?}", row, v);
        }
    }
    for t in Traversal::ALL {
        let (mut got, mut want) = (TravCounters::default(), TravCounters::default());
        let (mut got_spans, mut want_spans) = (Vec::new(), Vec::new());
        traverse(&s, t, &mut got, &mut |y, a, b| got_spans.push((y, a, b)));
        walk_oracle::walk(&s, t, &mut want, &mut |y, a, b| want_spans.push((y, a, b)));
        prop_assert_eq!(
            got,
            want,
            "{:?} counters, {:?} at {} bits in {}x{}",
            t,
            v,
            bits,
            w,
            h
        );
        let mut got_px: Vec<(u32, u32)> = got_spans
            .iter()
            .flat_map(|&(y, a, b)| (a..b).map(move |x| (y, x)))
            .collect();
        let mut want_px: Vec<(u32, u32)> = want_spans
            .iter()
            .flat_map(|&(y, a, b)| (a..b).map(move |x| (y, x)))
            .collect();
        got_px.sort_unstable();
        want_px.sort_unstable();
        prop_assert!(
            got_px.windows(2).all(|p| p[0] != p[1]),
            "{:?}: pixel emitted twice",
            t
        );
        prop_assert_eq!(&got_px, &want_px, "{:?} pixels, {:?}", t, v);
        let (fg, fw) = (drawn(w, h, &got_spans), drawn(w, h, &want_spans));
        prop_assert_eq!(fg.rgb(), fw.rgb(), "{:?} framebuffer", t);
        prop_assert_eq!(fg.write_counts(), fw.write_counts());
        prop_assert_eq!(fg.overdraw(), 0);
        prop_assert_eq!(fg.fragments(), fw.fragments());
    }
    Ok(true)
}

fn point(
    x: core::ops::RangeInclusive<i32>,
    y: core::ops::RangeInclusive<i32>,
) -> impl Strategy<Value = Point> {
    (x, y).prop_map(|(x, y)| Point { x, y })
}

/// Triangles for a `w × h` viewport at `bits`: anywhere around it (clipped), on the pixel
/// grid and on pixel centres (edges through centres exercise the fill rule), slivers,
/// with a horizontal or vertical edge, and huge ones at the guard band.
fn triangles(bits: u8, w: u32, h: u32) -> BoxedStrategy<[Point; 3]> {
    let one = 1i32 << bits;
    let (wx, wy) = ((w as i32 + 24) * one, (h as i32 + 24) * one);
    let m = -24 * one;
    let near = move || point(m..=wx, m..=wy);
    let grid = (
        prop::array::uniform3((-6..=w as i32 + 6, -6..=h as i32 + 6)),
        any::<bool>(),
    )
        .prop_map(move |(p, centre)| {
            let c = if centre { one / 2 } else { 0 };
            p.map(|(x, y)| Point {
                x: x * one + c,
                y: y * one + c,
            })
        });
    let sliver =
        (near(), near(), -3i32..=3, -3i32..=3, 0..=bits as u32).prop_map(|(p, q, dx, dy, sh)| {
            [
                p,
                q,
                Point {
                    x: q.x + (dx << sh),
                    y: q.y + (dy << sh),
                },
            ]
        });
    let axis = (near(), near(), near(), any::<bool>()).prop_map(|(p, q, r, horizontal)| {
        let r = if horizontal {
            Point { x: r.x, y: p.y }
        } else {
            Point { x: p.x, y: r.y }
        };
        [p, q, r]
    });
    let l = COORD_LIMIT;
    let huge = prop::array::uniform3(point(-l..=l, -l..=l));
    prop_oneof![
        3 => prop::array::uniform3(near()),
        2 => grid,
        2 => sliver,
        2 => axis,
        1 => huge,
    ]
    .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1500))]

    /// Counters, pixel set and framebuffer of every traversal equal the pixel walk's.
    #[test]
    fn accounting_equals_the_walk(
        (bits, w, h, v) in (0..=MAX_SUBPIXEL_BITS, 1u32..=150, 1u32..=150)
            .prop_flat_map(|(bits, w, h)| (Just(bits), Just(w), Just(h), triangles(bits, w, h)))
    ) {
        check(&v, bits, w, h)?;
    }
}

/// Triangles the random ones rarely hit: spanning several coarse tiles with partial
/// last blocks, thin wedges along the box diagonal, and the guard band's corners.
#[test]
fn accounting_equals_the_walk_on_chosen_triangles() {
    let l = COORD_LIMIT;
    let p = |x: i32, y: i32| Point { x, y };
    let (mut visible, mut narrow) = (0, 0);
    for bits in [0u8, 4, 8] {
        let s = 1 << bits;
        let cases = [
            [p(0, 0), p(141 * s, 5 * s), p(8 * s, 146 * s)],
            [p(0, 0), p(200 * s, 190 * s), p(203 * s, 190 * s)],
            [p(3 * s, 250 * s), p(250 * s, 3 * s), p(251 * s, 4 * s)],
            [p(-l, -l), p(l, -l), p(0, l)],
            [p(l, l), p(-l, 1234), p(1000, -l)],
            [p(0, 0), p(255 * s + 1, 0), p(0, 255 * s - 1)],
            [p(5 * s / 2, 0), p(5 * s / 2, 200 * s), p(300 * s, 100 * s)],
        ];
        for v in cases {
            for (w, h) in [(256, 256), (97, 203), (300, 33)] {
                if let Some(s) = setup(&v, bits, w, h, Cull::None) {
                    narrow += EdgeWalk::new(&s)
                        .narrow::<i32>(s.bbox[3] - s.bbox[1])
                        .is_some() as u32;
                }
                visible += check(&v, bits, w, h)
                    .map_err(|e| e.to_string())
                    .expect("equal") as u32;
            }
        }
    }
    assert!(visible > 40, "the chosen triangles are visible");
    // Both widths of the walk are tried: the guard band's triangles do not fit i32.
    assert!(
        narrow > 20 && narrow < visible,
        "{narrow} of {visible} walks in i32"
    );
}
