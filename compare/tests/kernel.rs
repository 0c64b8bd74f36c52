//! The comparison kernel through its public API, as the CLI and the C library call it:
//! every counter on hand-built frames, the tolerance and allowance boundaries, the error
//! figures, the mask and the unusable-input errors.

use compare::{
    compare, psnr, raster_edges, Class, CompareError, Coverage, Edge, Errors, Frame, Options, Side,
    MASK_ALLOWED, MASK_FAIL,
};
use proptest::prelude::*;
use protocol::raster::{Point, RasterCmd, RasterSetup, Rgb, Shade, Triangle};

const BLACK: [u8; 3] = [0, 0, 0];
const RED: [u8; 3] = [200, 0, 0];
const GREEN: [u8; 3] = [0, 200, 0];
const BLUE: [u8; 3] = [0, 0, 200];

fn frame(w: u32, h: u32, px: &[[u8; 3]]) -> Frame {
    Frame::rgb8(w, h, px.concat())
}

fn levels(r: &compare::Report) -> compare::LevelErrors {
    match r.errors {
        Errors::Levels(l) => l,
        Errors::Float(_) => panic!("an RGB comparison reports levels"),
    }
}

fn tolerance(t: f64) -> Options {
    Options {
        tolerance: t,
        ..Options::default()
    }
}

#[test]
fn identical_frames_count_nothing_and_psnr_is_infinite() {
    let f = frame(3, 2, &[RED, GREEN, BLUE, BLACK, BLACK, BLACK]);
    let r = compare(&f, &f, &Options::default()).expect("comparable");
    assert_eq!((r.equal, r.within_tolerance, r.near_edge), (6, 0, 0));
    assert_eq!((r.missing, r.unexpected, r.differing), (0, 0, 0));
    assert!(r.passed() && r.mismatches.is_empty());
    let l = levels(&r);
    assert_eq!((l.max, l.mean), (0, 0.0));
    assert_eq!(l.psnr_db, f64::INFINITY);
    // An empty frame is identical too (and divides by nothing).
    let empty = Frame::rgb8(0, 0, vec![]);
    let r = compare(&empty, &empty, &Options::default()).expect("comparable");
    assert_eq!(levels(&r).psnr_db, f64::INFINITY);
    assert_eq!(psnr(&[], &[]), f64::INFINITY);
}

#[test]
fn psnr_of_one_full_scale_error() {
    // One sample off by 255 among 3 · 100: MSE = 255² / 300, PSNR = 10·log10(300).
    let e = Frame::rgb8(10, 10, vec![0; 300]);
    let mut a = vec![0; 300];
    a[7] = 255;
    let r = compare(&e, &Frame::rgb8(10, 10, a), &Options::default()).expect("comparable");
    let l = levels(&r);
    assert!((l.psnr_db - 10.0 * 300f64.log10()).abs() < 1e-9, "{l:?}");
    assert_eq!(l.max, 255);
    assert!((l.mean - 255.0 / 300.0).abs() < 1e-12);
}

#[test]
fn every_counter_on_a_hand_built_frame() {
    // Expected: black background (7 of 10 pixels), three drawn pixels.
    #[rustfmt::skip]
    let e = frame(5, 2, &[
        BLACK, RED,   BLACK, RED,   BLACK,
        BLACK, BLACK, RED,   BLACK, BLACK,
    ]);
    #[rustfmt::skip]
    let a = frame(5, 2, &[
        BLACK, BLACK, GREEN, BLUE, BLACK,        // missing, unexpected, differing
        BLACK, [2, 2, 0], [203, 0, 0], BLACK, BLACK, // within 3 (background-ish), within 3
    ]);
    let r = compare(&e, &a, &tolerance(3.0)).expect("comparable");
    assert_eq!(r.background, Some(BLACK));
    assert_eq!(r.equal, 5);
    assert_eq!(r.within_tolerance, 2);
    assert_eq!(r.near_edge, 0);
    assert_eq!((r.missing, r.unexpected, r.differing), (1, 1, 1));
    assert_eq!(r.failures(), 3);
    assert!(!r.passed());
    let listed: Vec<_> = r.mismatches.iter().map(|m| (m.x, m.y, m.class)).collect();
    assert_eq!(
        listed,
        [
            (1, 0, Class::Missing),
            (2, 0, Class::Unexpected),
            (3, 0, Class::Differing)
        ]
    );
    assert_eq!(r.mismatches[2].expected, [200.0, 0.0, 0.0]);
    assert_eq!(r.mismatches[2].actual, [0.0, 0.0, 200.0]);
    let l = levels(&r);
    assert_eq!(l.max, 200);
    assert_eq!(l.mean, (200 + 200 + 200 + 200 + 2 + 2 + 3) as f64 / 30.0);
}

#[test]
fn all_failures_are_counted_but_only_the_first_listed() {
    let e = frame(4, 1, &[BLACK; 4]);
    let a = frame(4, 1, &[RED, BLACK, RED, RED]);
    let opts = Options {
        max_listed: 2,
        ..Options::default()
    };
    let r = compare(&e, &a, &opts).expect("comparable");
    assert_eq!(r.unexpected, 3);
    let at: Vec<_> = r.mismatches.iter().map(|m| (m.x, m.y)).collect();
    assert_eq!(at, [(0, 0), (2, 0)]);
}

#[test]
fn background_is_the_most_common_colour_ties_to_the_first() {
    let e = frame(4, 1, &[GREEN, RED, RED, GREEN]);
    let r = compare(&e, &e, &Options::default()).expect("comparable");
    assert_eq!(r.background, Some(GREEN));
    let e = frame(5, 1, &[GREEN, RED, RED, GREEN, RED]);
    let r = compare(&e, &e, &Options::default()).expect("comparable");
    assert_eq!(r.background, Some(RED));
}

#[test]
fn the_mask_dims_the_expected_frame_and_marks_the_differences() {
    let e = frame(3, 1, &[[100, 50, 10], RED, BLACK]);
    let a = frame(3, 1, &[[100, 50, 10], [201, 0, 0], GREEN]);
    let r = compare(&e, &a, &tolerance(1.0)).expect("comparable");
    assert_eq!(r.mask.len(), 9);
    assert_eq!(&r.mask[0..3], &[30, 15, 3]);
    assert_eq!(&r.mask[3..6], &MASK_ALLOWED);
    assert_eq!(&r.mask[6..9], &MASK_FAIL);
}

proptest! {
    /// LEVELS allowed, LEVELS + 1 not, in any channel: the comparison is `d ≤ LEVELS`.
    #[test]
    fn tolerance_is_closed(levels in 0u8..=254, channel in 0usize..3, base: u8) {
        // Room above the base for LEVELS + 1.
        let base = (u16::from(base) % (255 - u16::from(levels))) as u8;
        let up = |d: u8| {
            let mut p = [base; 3];
            p[channel] = base + d;
            p
        };
        let e = frame(2, 1, &[[base; 3], [base; 3]]);
        let at = frame(2, 1, &[[base; 3], up(levels)]);
        let r = compare(&e, &at, &tolerance(f64::from(levels))).expect("comparable");
        prop_assert!(r.passed(), "{levels} levels must pass: {r:?}");
        prop_assert_eq!(r.within_tolerance + r.equal, 2);
        let beyond = frame(2, 1, &[[base; 3], up(levels + 1)]);
        let r = compare(&e, &beyond, &tolerance(f64::from(levels))).expect("comparable");
        prop_assert_eq!(r.failures(), 1, "{} levels must fail", levels + 1);
    }

    /// Whatever the frames, every pixel lands in exactly one class, the mask has the
    /// frame's size, and a frame always equals itself.
    #[test]
    fn classes_partition_the_pixels(
        w in 1u32..12, h in 1u32..12, seed: u64, tol in 0u8..40, bits in 0u8..6,
    ) {
        let n = (w * h) as usize;
        let byte = |i: usize, s: u64| ((s.wrapping_mul(i as u64 * 2 + 1) >> 13) % 4 * 60) as u8;
        let e: Vec<u8> = (0..3 * n).map(|i| byte(i, seed)).collect();
        let a: Vec<u8> = (0..3 * n).map(|i| byte(i, seed ^ 0x9e37)).collect();
        let opts = Options {
            tolerance: f64::from(tol),
            coverage: Some(Coverage {
                bits,
                edges: vec![Edge::new(0.0, 0.0, f64::from(w), f64::from(h))],
            }),
            max_listed: 5,
        };
        let (e, a) = (Frame::rgb8(w, h, e), Frame::rgb8(w, h, a));
        let r = compare(&e, &a, &opts).expect("comparable");
        prop_assert_eq!(
            r.equal + r.within_tolerance + r.near_edge + r.failures(),
            u64::from(w * h)
        );
        prop_assert_eq!(r.mask.len(), 3 * n);
        prop_assert_eq!(r.mismatches.len() as u64, r.failures().min(5));
        let same = compare(&e, &e, &opts).expect("comparable");
        prop_assert_eq!(same.equal, u64::from(w * h));
    }
}

/// A flat triangle whose top side is horizontal at `top` px (sub-pixel exact at `bits`).
fn triangle_with_top_at(top_subpx: i32, bits: u8) -> (RasterSetup, RasterCmd) {
    let s = 1i32 << bits;
    let setup = RasterSetup {
        width: 8,
        height: 8,
        subpixel_bits: bits,
        background: Rgb::new(0, 0, 0),
        aa: Default::default(),
        cull: Default::default(),
        traversal: Default::default(),
    };
    let t = RasterCmd::Triangle(Triangle {
        v: [
            Point { x: 0, y: top_subpx },
            Point {
                x: 8 * s,
                y: top_subpx,
            },
            Point { x: 0, y: 8 * s },
        ],
        shade: Shade::Flat(Rgb::new(255, 255, 255)),
        z: None,
        w: None,
        tex: None,
    });
    (setup, t)
}

/// Row 3 expected background, actual drawn at pixel (1, 3): the pixel a rasteriser
/// snapping differently would add below an edge lying just under its centre (3.5).
fn edge_case() -> (Frame, Frame) {
    let e = Frame::rgb8(8, 8, vec![0; 8 * 8 * 3]);
    let mut a = vec![0; 8 * 8 * 3];
    a[3 * (3 * 8 + 1)..3 * (3 * 8 + 1) + 3].copy_from_slice(&[255, 255, 255]);
    (e, Frame::rgb8(8, 8, a))
}

fn with_edges(bits: u8, edges: Vec<Edge>) -> Options {
    Options {
        coverage: Some(Coverage { bits, edges }),
        ..Options::default()
    }
}

#[test]
fn allowance_at_exactly_two_to_the_minus_bits_from_a_triangle_edge() {
    let (e, a) = edge_case();
    for bits in 0u8..=8 {
        // The triangle's top side at y = 3.5 + 2^-bits: pixel centre (1.5, 3.5) lies
        // exactly 2^-bits from it, and the rule is `distance ≤ 2^-bits`.
        let (setup, t) = triangle_with_top_at((7 << bits) + 1, bits + 1);
        let edges = raster_edges(&setup, &[t]);
        assert_eq!(edges[0].y0, 3.5 + 0.5f64.powi(i32::from(bits) + 1));
        let r = compare(&e, &a, &with_edges(bits + 1, edges.clone())).expect("comparable");
        assert_eq!((r.near_edge, r.failures()), (1, 0), "bits {}", bits + 1);
        // One more bit of precision halves the allowance: the pixel fails.
        let r = compare(&e, &a, &with_edges(bits + 2, edges)).expect("comparable");
        assert_eq!((r.near_edge, r.unexpected), (0, 1), "bits {}", bits + 2);
    }
}

#[test]
fn allowance_refuses_two_to_the_minus_bits_plus_epsilon() {
    let (e, a) = edge_case();
    for bits in 0u8..=12 {
        let r = 0.5f64.powi(i32::from(bits));
        let at = |y: f64| with_edges(bits, vec![Edge::new(0.0, y, 8.0, y)]);
        let exact = compare(&e, &a, &at(3.5 + r)).expect("comparable");
        assert!(
            exact.passed(),
            "bits {bits}: exactly 2^-bits away is allowed"
        );
        let eps = 2f64.powi(-30);
        let beyond = compare(&e, &a, &at(3.5 + r + eps)).expect("comparable");
        assert_eq!(beyond.unexpected, 1, "bits {bits}: 2^-bits + 2^-30 is not");
        // Above the centre alike.
        let beyond = compare(&e, &a, &at(3.5 - r - eps)).expect("comparable");
        assert_eq!(beyond.unexpected, 1);
    }
    // The allowance marks the pixel allowed in the mask, and it is not listed.
    let r = compare(&e, &a, &with_edges(0, vec![Edge::new(0.0, 4.0, 8.0, 4.0)])).unwrap();
    assert!(r.mismatches.is_empty());
    assert_eq!(&r.mask[3 * 25..3 * 26], &MASK_ALLOWED);
}

#[test]
fn float_frames_report_absolute_and_relative_error_and_empty_samples() {
    let inf = f32::INFINITY;
    let e = Frame::float(6, 1, 1, vec![1.0, 2.0, 0.0, inf, 4.0, inf]);
    let a = Frame::float(6, 1, 1, vec![1.5, 2.0, 0.25, f32::NAN, inf, 3.0]);
    let r = compare(&e, &a, &tolerance(0.25)).expect("comparable");
    assert_eq!(r.background, None);
    // 2.0 equal, inf/NaN both empty; 0.25 within; 0.5 beyond; 4 → ∞ missing; ∞ → 3 unexpected.
    assert_eq!((r.equal, r.within_tolerance), (2, 1));
    assert_eq!((r.missing, r.unexpected, r.differing), (1, 1, 1));
    let Errors::Float(f) = r.errors else {
        panic!("a float comparison reports float errors")
    };
    // Over the finite pairs 1→1.5, 2→2, 0→0.25; relative over the non-zero expected.
    assert_eq!((f.max_abs, f.mean_abs), (0.5, 0.25));
    assert_eq!((f.max_rel, f.mean_rel), (0.5, 0.25));
    assert_eq!(r.mismatches[0].class, Class::Differing);
    assert_eq!(r.mismatches[1].class, Class::Missing);
    assert_eq!(r.mismatches[1].actual[0], inf);
    // Three planes: one bad channel fails the pixel.
    let e = Frame::float(1, 1, 3, vec![0.0, 1.0, 0.0]);
    let a = Frame::float(1, 1, 3, vec![0.0, 0.9, 0.0]);
    let r = compare(&e, &a, &tolerance(0.05)).expect("comparable");
    assert_eq!((r.differing, r.channels), (1, 3));
}

#[test]
fn unusable_input_is_an_error_not_a_report() {
    let rgb = |w, h| Frame::rgb8(w, h, vec![0; (w * h * 3) as usize]);
    let o = Options::default();
    assert_eq!(
        compare(&rgb(2, 2), &rgb(3, 2), &o),
        Err(CompareError::Size {
            expected: (2, 2),
            actual: (3, 2)
        })
    );
    let depth = Frame::float(2, 2, 1, vec![0.0; 4]);
    let normal = Frame::float(2, 2, 3, vec![0.0; 12]);
    assert!(matches!(
        compare(&rgb(2, 2), &depth, &o),
        Err(CompareError::Kind { .. })
    ));
    let e = compare(&depth, &normal, &o).unwrap_err().to_string();
    assert!(
        e.contains("1-channel float") && e.contains("3-channel float"),
        "{e}"
    );
    assert!(matches!(
        compare(&Frame::rgb8(2, 2, vec![0; 11]), &rgb(2, 2), &o),
        Err(CompareError::Length {
            side: Side::Expected,
            got: 11,
            ..
        })
    ));
    assert!(matches!(
        compare(&depth, &Frame::float(2, 2, 4, vec![0.0; 16]), &o),
        Err(CompareError::Channels {
            side: Side::Actual,
            channels: 4
        })
    ));
    for t in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            compare(&rgb(1, 1), &rgb(1, 1), &tolerance(t)),
            Err(CompareError::Tolerance(_))
        ));
    }
}

/// A 4294967295 × 4294967295 frame with a 6-byte buffer (`fpgfx_compare_exact` as the
/// `capi` fuzz target's seed `seed-compare-huge` calls it): width · height · 3 overflowed
/// and the kernel panicked, which the C library reported as FPGFX_INTERNAL_ERROR, instead
/// of refusing the length.
#[test]
fn a_size_whose_sample_count_overflows_is_a_length_error() {
    let e = Frame::rgb8(u32::MAX, u32::MAX, vec![0; 6]);
    let got = compare(&e, &e, &Options::default());
    assert!(
        matches!(
            got,
            Err(CompareError::Length {
                side: Side::Expected,
                got: 6,
                ..
            })
        ),
        "{got:?}"
    );
    let text = got.unwrap_err().to_string();
    assert!(
        text.contains("55340232195358851075 samples"),
        "the message names the whole product: {text}"
    );
    let f = Frame::float(u32::MAX, u32::MAX, 3, vec![0.0; 3]);
    assert!(matches!(
        compare(&f, &f, &Options::default()),
        Err(CompareError::Length { got: 3, .. })
    ));
}
