//! The comparison itself: one pass over both frames that classifies every pixel, sums the
//! error figures and paints the error mask.

use std::collections::HashMap;

use thiserror::Error;

use crate::edge::{centre_near, Edge};

/// Float frames carry at most this many planes (PFM holds one or three).
pub const MAX_CHANNELS: usize = 3;

/// Error-mask colour of a pixel that differs beyond what the options allow.
pub const MASK_FAIL: [u8; 3] = [255, 0, 0];

/// Error-mask colour of a pixel that differs, but within the tolerance or near an edge.
pub const MASK_ALLOWED: [u8; 3] = [255, 255, 0];

/// Brightness (in tenths) of the expected frame under the mask: dim enough that the
/// pure red and yellow markers stand out on any image, bright enough to recognise it.
const MASK_DIM_TENTHS: u16 = 3;

/// A frame as the comparison sees it: decoded, with no file format left.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// The samples, row-major.
    pub pixels: Pixels,
}

/// What a frame's pixels hold.
#[derive(Debug, Clone, PartialEq)]
pub enum Pixels {
    /// 8-bit RGB, three bytes per pixel: PNGs, and `$readmemh` framebuffers after
    /// [`memh::PixelFormat::to_rgb8`](crate::memh::PixelFormat::to_rgb8) (so RGB332 and
    /// RGB888 compare on one scale).
    Rgb8(Vec<u8>),
    /// Floats, `channels` per pixel interleaved: a depth plane (1) or a normal (3), as PFM
    /// stores them. Non-finite samples mean "nothing there" (the ray tracer writes +∞
    /// where no ray hit).
    Float {
        /// Samples per pixel, 1..=[`MAX_CHANNELS`].
        channels: u8,
        /// `width · height · channels` samples.
        samples: Vec<f32>,
    },
}

impl Frame {
    /// An 8-bit RGB frame.
    pub fn rgb8(width: u32, height: u32, rgb: Vec<u8>) -> Self {
        Frame {
            width,
            height,
            pixels: Pixels::Rgb8(rgb),
        }
    }

    /// A float frame of `channels` planes.
    pub fn float(width: u32, height: u32, channels: u8, samples: Vec<f32>) -> Self {
        Frame {
            width,
            height,
            pixels: Pixels::Float { channels, samples },
        }
    }

    fn channels(&self) -> usize {
        match &self.pixels {
            Pixels::Rgb8(_) => 3,
            Pixels::Float { channels, .. } => usize::from(*channels),
        }
    }

    fn describe(&self) -> String {
        match &self.pixels {
            Pixels::Rgb8(_) => "8-bit RGB".into(),
            Pixels::Float { channels, .. } => format!("{channels}-channel float"),
        }
    }

    /// Refuses a buffer whose length does not match its size, so the pass never indexes
    /// out of bounds on a caller's mistake.
    fn check(&self, side: Side) -> Result<(), CompareError> {
        let channels = self.channels();
        if let Pixels::Float { channels: c, .. } = self.pixels {
            if c == 0 || usize::from(c) > MAX_CHANNELS {
                return Err(CompareError::Channels { side, channels: c });
            }
        }
        let len = match &self.pixels {
            Pixels::Rgb8(v) => v.len(),
            Pixels::Float { samples, .. } => samples.len(),
        };
        // Checked: a size whose product overflows describes no buffer (it used to
        // panic on the multiplication instead of refusing the length).
        let want = (self.width as usize)
            .checked_mul(self.height as usize)
            .and_then(|n| n.checked_mul(channels));
        if want != Some(len) {
            return Err(CompareError::Length {
                side,
                width: self.width,
                height: self.height,
                channels,
                got: len,
            });
        }
        Ok(())
    }
}

/// Which of the two frames an error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The reference.
    Expected,
    /// The frame under test.
    Actual,
}

impl core::fmt::Display for Side {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Side::Expected => "expected",
            Side::Actual => "actual",
        })
    }
}

/// Two frames that cannot be compared, or options that make no sense: unusable input,
/// as opposed to a comparison that found differences.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CompareError {
    /// The frames' sizes differ.
    #[error("sizes differ: expected is {}×{}, actual is {}×{}", expected.0, expected.1, actual.0, actual.1)]
    Size {
        /// Width and height of the expected frame.
        expected: (u32, u32),
        /// Width and height of the actual frame.
        actual: (u32, u32),
    },
    /// One frame is 8-bit RGB and the other float, or their plane counts differ.
    #[error("kinds differ: expected is {expected}, actual is {actual}")]
    Kind {
        /// What the expected frame holds.
        expected: String,
        /// What the actual frame holds.
        actual: String,
    },
    /// A buffer whose length does not match its size.
    #[error("{side} frame: {width}×{height}×{channels} needs {} samples, the buffer holds {got}", u128::from(*width) * u128::from(*height) * *channels as u128)]
    Length {
        /// Which frame.
        side: Side,
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// Samples per pixel.
        channels: usize,
        /// Samples in the buffer.
        got: usize,
    },
    /// A float frame with no planes or more than [`MAX_CHANNELS`].
    #[error("{side} frame: {channels} channels (1..={MAX_CHANNELS} allowed)")]
    Channels {
        /// Which frame.
        side: Side,
        /// Its channel count.
        channels: u8,
    },
    /// A negative or non-finite tolerance.
    #[error("tolerance {0} is not a finite number ≥ 0")]
    Tolerance(f64),
}

/// The sub-pixel allowance: where a rasteriser may legitimately disagree.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Coverage {
    /// The stated sub-pixel precision: a pixel whose centre lies within 2^-bits px of an
    /// edge may differ.
    pub bits: u8,
    /// Every primitive boundary of the frame, in pixel units.
    pub edges: Vec<Edge>,
}

impl Coverage {
    /// The allowance distance, 2^-bits pixels.
    pub fn radius(&self) -> f64 {
        0.5f64.powi(i32::from(self.bits))
    }
}

/// How strict the comparison is.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Largest per-channel absolute difference that still counts as equal: 8-bit levels
    /// for RGB frames, the samples' own unit for float frames. Closed: a difference of
    /// exactly `tolerance` is allowed.
    pub tolerance: f64,
    /// The edge allowance; `None` compares every pixel alike.
    pub coverage: Option<Coverage>,
    /// How many failing pixels [`Report::mismatches`] lists (all are counted).
    pub max_listed: usize,
}

impl Default for Options {
    /// Exact, no allowance, ten listed: what a bit-exact golden model is held to.
    fn default() -> Self {
        Options {
            tolerance: 0.0,
            coverage: None,
            max_listed: 10,
        }
    }
}

/// Why a pixel failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Class {
    /// Expected shows something there, the actual frame shows background.
    Missing,
    /// Expected shows background there, the actual frame shows something.
    Unexpected,
    /// Both show something (or both background-like), but not the same.
    Differing,
}

impl Class {
    /// The word reports use.
    pub fn name(self) -> &'static str {
        match self {
            Class::Missing => "missing",
            Class::Unexpected => "unexpected",
            Class::Differing => "differing",
        }
    }
}

/// One failing pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mismatch {
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
    /// Why it failed.
    pub class: Class,
    /// The expected samples, [`Report::channels`] of them used (8-bit levels for RGB).
    pub expected: [f32; MAX_CHANNELS],
    /// The actual samples, likewise.
    pub actual: [f32; MAX_CHANNELS],
}

/// Error magnitudes of an 8-bit RGB comparison, over every pixel (allowed ones too: they
/// describe how far the frames are apart, the counts say whether that is acceptable).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevelErrors {
    /// Largest per-channel absolute difference, in levels.
    pub max: u8,
    /// Mean per-channel absolute difference over all `3 · pixels` samples, in levels.
    pub mean: f64,
    /// PSNR in dB over the RGB8 samples ([`psnr`]): +∞ for identical frames.
    pub psnr_db: f64,
}

/// Error magnitudes of a float comparison, over the samples finite in both frames (one
/// side non-finite is a missing or unexpected pixel, not a number to average).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloatErrors {
    /// Largest `|actual − expected|`.
    pub max_abs: f64,
    /// Mean `|actual − expected|`.
    pub mean_abs: f64,
    /// Largest `|actual − expected| / |expected|`, over samples with `expected ≠ 0`
    /// (relative error is undefined at zero; the absolute figures cover those).
    pub max_rel: f64,
    /// Mean relative error over the same samples.
    pub mean_rel: f64,
}

/// Error magnitudes, by the kind of frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Errors {
    /// 8-bit RGB frames.
    Levels(LevelErrors),
    /// Float frames.
    Float(FloatErrors),
}

/// What the comparison found.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Samples per pixel (3 for RGB).
    pub channels: usize,
    /// The background colour missing/unexpected are judged against (RGB frames): the
    /// most common colour of the expected frame, ties to the first met in row-major
    /// order. `None` for float frames, whose background is "non-finite".
    pub background: Option<[u8; 3]>,
    /// Pixels identical in every sample.
    pub equal: u64,
    /// Pixels that differ by at most the tolerance.
    pub within_tolerance: u64,
    /// Pixels beyond the tolerance whose centre lies within the coverage allowance of an
    /// edge: allowed.
    pub near_edge: u64,
    /// Failing pixels: expected drawn, actual background.
    pub missing: u64,
    /// Failing pixels: expected background, actual drawn.
    pub unexpected: u64,
    /// Failing pixels: any other difference beyond the tolerance.
    pub differing: u64,
    /// Error magnitudes.
    pub errors: Errors,
    /// The first [`Options::max_listed`] failing pixels in row-major order.
    pub mismatches: Vec<Mismatch>,
    /// The error mask, RGB8 row-major, the frames' size: the expected frame at 30 %
    /// brightness, [`MASK_FAIL`] where a pixel fails, [`MASK_ALLOWED`] where it differs
    /// but is allowed.
    pub mask: Vec<u8>,
}

impl Report {
    /// Pixels compared.
    pub fn pixels(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// Failing pixels: missing + unexpected + differing.
    pub fn failures(&self) -> u64 {
        self.missing + self.unexpected + self.differing
    }

    /// Whether the actual frame is within what the options allow.
    pub fn passed(&self) -> bool {
        self.failures() == 0
    }
}

/// PSNR in dB of 8-bit samples against a reference, over the common length: +∞ when
/// identical, so a caller decides how to show or cap it (a JSON number cannot be ∞).
pub fn psnr(reference: &[u8], test: &[u8]) -> f64 {
    let n = reference.len().min(test.len()).max(1);
    let mse: f64 = reference
        .iter()
        .zip(test)
        .map(|(a, b)| {
            let d = *a as f64 - *b as f64;
            d * d
        })
        .sum::<f64>()
        / n as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0 * 255.0 / mse).log10()
    }
}

/// One pixel's difference, before the allowance is applied.
struct Verdict {
    /// Some sample differs at all.
    differs: bool,
    /// Some sample differs beyond the tolerance.
    beyond: bool,
    /// What kind of failure it would be.
    class: Class,
}

/// Compares `actual` against `expected`. Errors only for unusable input (sizes, kinds,
/// buffer lengths, the tolerance); differences are the [`Report`]'s business.
pub fn compare(expected: &Frame, actual: &Frame, opts: &Options) -> Result<Report, CompareError> {
    expected.check(Side::Expected)?;
    actual.check(Side::Actual)?;
    let kind_error = || CompareError::Kind {
        expected: expected.describe(),
        actual: actual.describe(),
    };
    // Kinds first: "a depth plane is not a colour frame" says more than their sizes.
    let same_kind = match (&expected.pixels, &actual.pixels) {
        (Pixels::Rgb8(_), Pixels::Rgb8(_)) => true,
        (Pixels::Float { channels: a, .. }, Pixels::Float { channels: b, .. }) => a == b,
        _ => false,
    };
    if !same_kind {
        return Err(kind_error());
    }
    if (expected.width, expected.height) != (actual.width, actual.height) {
        return Err(CompareError::Size {
            expected: (expected.width, expected.height),
            actual: (actual.width, actual.height),
        });
    }
    if !(opts.tolerance.is_finite() && opts.tolerance >= 0.0) {
        return Err(CompareError::Tolerance(opts.tolerance));
    }
    let (w, h) = (expected.width, expected.height);
    let n = w as usize * h as usize;
    let channels = expected.channels();
    let mut report = Report {
        width: w,
        height: h,
        channels,
        background: None,
        equal: 0,
        within_tolerance: 0,
        near_edge: 0,
        missing: 0,
        unexpected: 0,
        differing: 0,
        errors: Errors::Levels(LevelErrors {
            max: 0,
            mean: 0.0,
            psnr_db: f64::INFINITY,
        }),
        mismatches: Vec::new(),
        mask: Vec::new(),
    };
    let tol = opts.tolerance;
    match (&expected.pixels, &actual.pixels) {
        (Pixels::Rgb8(e), Pixels::Rgb8(a)) => {
            let bg = background(e);
            report.background = Some(bg);
            report.mask = dim(e);
            let (mut max, mut sum) = (0u8, 0u64);
            let is_bg = |p: &[u8]| max_diff(p, &bg) as f64 <= tol;
            run(&mut report, opts, |i| {
                let (pe, pa) = (&e[3 * i..3 * i + 3], &a[3 * i..3 * i + 3]);
                let d = max_diff(pe, pa);
                max = max.max(d);
                sum += pe
                    .iter()
                    .zip(pa)
                    .map(|(x, y)| u64::from(x.abs_diff(*y)))
                    .sum::<u64>();
                let class = match (is_bg(pe), is_bg(pa)) {
                    (false, true) => Class::Missing,
                    (true, false) => Class::Unexpected,
                    _ => Class::Differing,
                };
                let value = |p: &[u8]| [f32::from(p[0]), f32::from(p[1]), f32::from(p[2])];
                (
                    Verdict {
                        differs: d > 0,
                        beyond: d as f64 > tol,
                        class,
                    },
                    value(pe),
                    value(pa),
                )
            });
            report.errors = Errors::Levels(LevelErrors {
                max,
                mean: sum as f64 / (3 * n).max(1) as f64,
                psnr_db: psnr(e, a),
            });
        }
        (Pixels::Float { samples: e, .. }, Pixels::Float { samples: a, .. }) => {
            report.mask = dim(&float_to_rgb8(e, channels));
            let mut stats = FloatStats::default();
            run(&mut report, opts, |i| {
                let (pe, pa) = (
                    &e[channels * i..channels * (i + 1)],
                    &a[channels * i..channels * (i + 1)],
                );
                let mut v = Verdict {
                    differs: false,
                    beyond: false,
                    class: Class::Differing,
                };
                let (mut missing, mut unexpected) = (false, false);
                for (&x, &y) in pe.iter().zip(pa) {
                    match (x.is_finite(), y.is_finite()) {
                        // Both "nothing there", whichever non-finite value says so.
                        (false, false) => {}
                        (true, false) => missing = true,
                        (false, true) => unexpected = true,
                        (true, true) => {
                            let d = (f64::from(y) - f64::from(x)).abs();
                            stats.add(d, f64::from(x));
                            v.differs |= d > 0.0;
                            v.beyond |= d > tol;
                        }
                    }
                }
                if missing || unexpected {
                    v.differs = true;
                    v.beyond = true;
                    v.class = if missing {
                        Class::Missing
                    } else {
                        Class::Unexpected
                    };
                }
                let value = |p: &[f32]| {
                    let mut out = [0.0; MAX_CHANNELS];
                    out[..p.len()].copy_from_slice(p);
                    out
                };
                (v, value(pe), value(pa))
            });
            report.errors = Errors::Float(stats.finish());
        }
        // Refused above; kept so a new kind cannot slip through unhandled.
        _ => return Err(kind_error()),
    }
    Ok(report)
}

/// The pass shared by both kinds of frame: `judge(i)` says how pixel `i` differs, this
/// applies the allowance, counts, lists and marks the mask.
fn run(
    report: &mut Report,
    opts: &Options,
    mut judge: impl FnMut(usize) -> (Verdict, [f32; MAX_CHANNELS], [f32; MAX_CHANNELS]),
) {
    let w = report.width as usize;
    let n = w * report.height as usize;
    let allowance = opts
        .coverage
        .as_ref()
        .map(|c| (c.edges.as_slice(), c.radius()));
    for i in 0..n {
        let (v, expected, actual) = judge(i);
        let (x, y) = ((i % w) as u32, (i / w) as u32);
        let mark = if !v.differs {
            report.equal += 1;
            None
        } else if !v.beyond {
            report.within_tolerance += 1;
            Some(MASK_ALLOWED)
        } else if allowance.is_some_and(|(edges, r)| centre_near(edges, r, x, y)) {
            report.near_edge += 1;
            Some(MASK_ALLOWED)
        } else {
            match v.class {
                Class::Missing => report.missing += 1,
                Class::Unexpected => report.unexpected += 1,
                Class::Differing => report.differing += 1,
            }
            if report.mismatches.len() < opts.max_listed {
                report.mismatches.push(Mismatch {
                    x,
                    y,
                    class: v.class,
                    expected,
                    actual,
                });
            }
            Some(MASK_FAIL)
        };
        if let Some(c) = mark {
            report.mask[3 * i..3 * i + 3].copy_from_slice(&c);
        }
    }
}

fn max_diff(a: &[u8], b: &[u8]) -> u8 {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

/// The most common colour, ties to the first met: the clear colour of a typical frame
/// without needing the job that drew it (which a seed fill may have repainted anyway).
fn background(rgb: &[u8]) -> [u8; 3] {
    let mut counts: HashMap<[u8; 3], (u64, usize)> = HashMap::new();
    for (i, p) in rgb.chunks_exact(3).enumerate() {
        let e = counts.entry([p[0], p[1], p[2]]).or_insert((0, i));
        e.0 += 1;
    }
    counts
        .into_iter()
        .max_by(|a, b| a.1 .0.cmp(&b.1 .0).then(b.1 .1.cmp(&a.1 .1)))
        .map_or([0; 3], |(c, _)| c)
}

fn dim(rgb: &[u8]) -> Vec<u8> {
    rgb.iter()
        .map(|&v| (u16::from(v) * MASK_DIM_TENTHS / 10) as u8)
        .collect()
}

/// A float frame shown as RGB8 for the mask: each plane stretched from its finite
/// minimum to its maximum, one plane as grey, three as RGB; non-finite samples black.
fn float_to_rgb8(samples: &[f32], channels: usize) -> Vec<u8> {
    let mut range = [(f32::INFINITY, f32::NEG_INFINITY); MAX_CHANNELS];
    for px in samples.chunks_exact(channels) {
        for (r, &v) in range.iter_mut().zip(px) {
            if v.is_finite() {
                *r = (r.0.min(v), r.1.max(v));
            }
        }
    }
    let level = |c: usize, v: f32| -> u8 {
        let (lo, hi) = range[c];
        if !v.is_finite() {
            0
        } else if hi > lo {
            ((v - lo) / (hi - lo) * 255.0).round() as u8
        } else {
            255
        }
    };
    samples
        .chunks_exact(channels)
        .flat_map(|px| {
            let mut out = [0u8; 3];
            for (k, o) in out.iter_mut().enumerate() {
                let c = if channels == 1 { 0 } else { k };
                *o = level(c, px[c]);
            }
            out
        })
        .collect()
}

#[derive(Default)]
struct FloatStats {
    max_abs: f64,
    sum_abs: f64,
    n_abs: u64,
    max_rel: f64,
    sum_rel: f64,
    n_rel: u64,
}

impl FloatStats {
    fn add(&mut self, d: f64, expected: f64) {
        self.max_abs = self.max_abs.max(d);
        self.sum_abs += d;
        self.n_abs += 1;
        if expected != 0.0 {
            let r = d / expected.abs();
            self.max_rel = self.max_rel.max(r);
            self.sum_rel += r;
            self.n_rel += 1;
        }
    }

    fn finish(self) -> FloatErrors {
        FloatErrors {
            max_abs: self.max_abs,
            mean_abs: self.sum_abs / self.n_abs.max(1) as f64,
            max_rel: self.max_rel,
            mean_rel: self.sum_rel / self.n_rel.max(1) as f64,
        }
    }
}
