//! Frames compared pixel by pixel, as `fpgfx compare` counts them: how many pixels differ
//! beyond a per-channel tolerance, the largest difference, and the first failing pixel.

use crate::{fpgfx_status, guard, input, put, Failure};

/// What a comparison found. `first_*` are meaningful only when `failing` > 0.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct fpgfx_compare_result {
    /// Pixels compared: width · height.
    pub pixels: u64,
    /// Pixels with some channel differing by more than the tolerance.
    pub failing: u64,
    /// Largest per-channel difference over the frame, in 8-bit levels (allowed ones too).
    pub max_difference: u8,
    /// Column of the first failing pixel in row-major order.
    pub first_x: u32,
    /// Row of the first failing pixel.
    pub first_y: u32,
    /// The expected pixel there, R, G, B.
    pub first_expected: [u8; 3],
    /// The actual pixel there, R, G, B.
    pub first_actual: [u8; 3],
}

/// The body of both comparisons: `len` bytes of RGB888 each, `width · height · 3`.
///
/// # Safety
/// As `fpgfx_compare_within`.
unsafe fn run(
    expected: *const u8,
    actual: *const u8,
    len: usize,
    width: u32,
    height: u32,
    tolerance: u8,
    out: *mut fpgfx_compare_result,
) -> fpgfx_status {
    guard(|| {
        // SAFETY: the caller's promises on the buffers and `out`.
        let e = unsafe { input(expected, len, "expected") }?;
        let a = unsafe { input(actual, len, "actual") }?;
        let frame = |bytes: &[u8]| ::compare::Frame::rgb8(width, height, bytes.to_vec());
        let opts = ::compare::Options {
            tolerance: f64::from(tolerance),
            coverage: None,
            max_listed: 1,
        };
        let report = ::compare::compare(&frame(e), &frame(a), &opts)
            .map_err(|err| Failure::size(format!("len is {len}: {err}")))?;
        let max_difference = match report.errors {
            ::compare::Errors::Levels(l) => l.max,
            // Two RGB8 frames always give level errors.
            ::compare::Errors::Float(_) => 0,
        };
        // Levels are whole numbers: the kernel holds RGB samples as f32 for both kinds.
        let level = |s: [f32; ::compare::MAX_CHANNELS]| s.map(|v| v as u8);
        let mut result = fpgfx_compare_result {
            pixels: report.pixels(),
            failing: report.failures(),
            max_difference,
            ..Default::default()
        };
        if let Some(m) = report.mismatches.first() {
            result.first_x = m.x;
            result.first_y = m.y;
            result.first_expected = level(m.expected);
            result.first_actual = level(m.actual);
        }
        unsafe { put(out, result, "out") }
    })
}

/// Compares two RGB888 frames of `width` × `height`, each `len` bytes, bit for bit:
/// `out->failing` is the number of pixels that differ at all. A frame that differs is
/// still `FPGFX_OK`; the status says whether the comparison could be made.
///
/// # Safety
/// `expected` and `actual` must address `len` bytes each; `out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn fpgfx_compare_exact(
    expected: *const u8,
    actual: *const u8,
    len: usize,
    width: u32,
    height: u32,
    out: *mut fpgfx_compare_result,
) -> fpgfx_status {
    // SAFETY: forwarded.
    unsafe { run(expected, actual, len, width, height, 0, out) }
}

/// `fpgfx_compare_exact` allowing each channel to differ by up to `tolerance` levels:
/// for a DUT whose arithmetic is not bit-identical to the model's (an HLS `hls_math`
/// build, docs/hls-testbench.md).
///
/// # Safety
/// As `fpgfx_compare_exact`.
#[no_mangle]
pub unsafe extern "C" fn fpgfx_compare_within(
    expected: *const u8,
    actual: *const u8,
    len: usize,
    width: u32,
    height: u32,
    tolerance: u8,
    out: *mut fpgfx_compare_result,
) -> fpgfx_status {
    // SAFETY: forwarded.
    unsafe { run(expected, actual, len, width, height, tolerance, out) }
}
