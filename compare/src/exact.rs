//! Pixel-by-pixel comparison of two 8-bit RGB frames held in the caller's buffers: how
//! many pixels differ by more than a per-channel tolerance, by how much at most, and
//! where the first one is.
//!
//! It reads borrowed slices and allocates nothing, so the C library can run it on a
//! testbench's arrays in place and a C caller gets the same count as a Rust one.

use thiserror::Error;

/// Bytes per pixel of the frames compared: R, G, B.
pub const CHANNELS: usize = 3;

/// Why two buffers could not be compared as frames of the stated size.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum ExactError {
    /// A buffer's length is not `width · height · 3`.
    #[error(
        "the {side} frame holds {got} bytes, a {width}x{height} RGB888 frame needs {expected}"
    )]
    Length {
        /// `"expected"` or `"actual"`: which buffer.
        side: &'static str,
        /// Pixels per row.
        width: u32,
        /// Rows.
        height: u32,
        /// Bytes the size needs.
        expected: u64,
        /// Bytes the buffer holds.
        got: u64,
    },
}

/// The first pixel, in row-major order, that differs beyond the tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mismatch {
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
    /// The reference pixel, R, G, B.
    pub expected: [u8; CHANNELS],
    /// The pixel under test.
    pub actual: [u8; CHANNELS],
}

/// What [`differences`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Differences {
    /// Pixels compared.
    pub pixels: u64,
    /// Pixels with some channel differing by more than the tolerance.
    pub failing: u64,
    /// Largest per-channel absolute difference over the whole frame (allowed ones too):
    /// how far apart the frames are, whatever the tolerance.
    pub max_difference: u8,
    /// The first failing pixel, `None` when none fails.
    pub first: Option<Mismatch>,
}

impl Differences {
    /// Whether no pixel differs beyond the tolerance.
    pub fn passed(&self) -> bool {
        self.failing == 0
    }
}

/// Compares `actual` against `expected`, both `width × height` RGB888 row-major, and
/// counts the pixels where some channel differs by more than `tolerance` levels (0 is
/// bit-exact, what the golden model is held to).
pub fn differences(
    expected: &[u8],
    actual: &[u8],
    width: u32,
    height: u32,
    tolerance: u8,
) -> Result<Differences, ExactError> {
    let need = u64::from(width) * u64::from(height) * CHANNELS as u64;
    for (side, buf) in [("expected", expected), ("actual", actual)] {
        if buf.len() as u64 != need {
            return Err(ExactError::Length {
                side,
                width,
                height,
                expected: need,
                got: buf.len() as u64,
            });
        }
    }
    let mut out = Differences {
        pixels: u64::from(width) * u64::from(height),
        failing: 0,
        max_difference: 0,
        first: None,
    };
    let pixels = expected
        .chunks_exact(CHANNELS)
        .zip(actual.chunks_exact(CHANNELS));
    for (i, (e, a)) in pixels.enumerate() {
        let diff = e.iter().zip(a).map(|(e, a)| e.abs_diff(*a)).max();
        let diff = diff.unwrap_or(0);
        out.max_difference = out.max_difference.max(diff);
        if diff > tolerance {
            out.failing += 1;
            if out.first.is_none() {
                // `i < width · height`, so both fit the u32 sides.
                let w = width.max(1) as usize;
                out.first = Some(Mismatch {
                    x: (i % w) as u32,
                    y: (i / w) as u32,
                    expected: [e[0], e[1], e[2]],
                    actual: [a[0], a[1], a[2]],
                });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_beyond_the_tolerance_and_names_the_first() {
        let expected = [10, 10, 10, 20, 20, 20, 30, 30, 30, 40, 40, 40];
        let actual = [10, 10, 10, 20, 21, 20, 30, 30, 33, 40, 40, 40];
        let exact = differences(&expected, &actual, 2, 2, 0).unwrap();
        assert_eq!(exact.pixels, 4);
        assert_eq!(exact.failing, 2);
        assert_eq!(exact.max_difference, 3);
        assert_eq!(
            exact.first,
            Some(Mismatch {
                x: 1,
                y: 0,
                expected: [20, 20, 20],
                actual: [20, 21, 20],
            })
        );
        let within = differences(&expected, &actual, 2, 2, 1).unwrap();
        assert_eq!(within.failing, 1);
        assert_eq!(within.first.map(|m| (m.x, m.y)), Some((0, 1)));
        assert!(differences(&expected, &actual, 2, 2, 3).unwrap().passed());
    }

    #[test]
    fn a_wrong_length_names_the_buffer() {
        let e = differences(&[0; 12], &[0; 9], 2, 2, 0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "the actual frame holds 9 bytes, a 2x2 RGB888 frame needs 12"
        );
    }
}
