//! `fpgfx.compare`: two RGB frames through the `compare` kernel, with the figures
//! `fpgfx compare` reports (docs/compare.md), as attributes.

use ::compare::{Coverage, Errors, Frame, Options};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::input::{rgb_frame, source};
use crate::BindError;

/// What a comparison found: every figure of `fpgfx compare --json` for a colour frame.
#[pyclass(frozen, module = "fpgfx", name = "Comparison")]
pub struct Comparison {
    /// Frame width in pixels.
    #[pyo3(get)]
    width: u32,
    /// Frame height in pixels.
    #[pyo3(get)]
    height: u32,
    /// Pixels compared: width · height.
    #[pyo3(get)]
    pixels: u64,
    /// Pixels identical in every channel.
    #[pyo3(get)]
    equal: u64,
    /// Pixels that differ, but by no more than the tolerance in any channel.
    #[pyo3(get)]
    within_tolerance: u64,
    /// Pixels beyond the tolerance allowed by the edge allowance (`raster=`).
    #[pyo3(get)]
    near_edge: u64,
    /// Failing pixels where `expected` shows something and `actual` the background.
    #[pyo3(get)]
    missing: u64,
    /// Failing pixels where `expected` shows the background and `actual` something.
    #[pyo3(get)]
    unexpected: u64,
    /// Other failing pixels.
    #[pyo3(get)]
    differing: u64,
    /// missing + unexpected + differing.
    #[pyo3(get)]
    failures: u64,
    /// Whether no pixel failed: `fpgfx compare`'s exit status 0.
    #[pyo3(get)]
    passed: bool,
    /// Largest per-channel difference, in 8-bit levels.
    #[pyo3(get)]
    max_error: u8,
    /// Mean per-channel difference, in 8-bit levels.
    #[pyo3(get)]
    mean_error: f64,
    /// PSNR in dB over all channels; `inf` for identical frames.
    #[pyo3(get)]
    psnr_db: f64,
    /// The most common colour of `expected` as `#rrggbb`, which missing and unexpected
    /// are told by; `None` when no colour dominates.
    #[pyo3(get)]
    background: Option<String>,
    /// The first failing pixels (up to `max_listed`), each a dict with `x`, `y`,
    /// `expected` and `actual` (RGB tuples) and `class`.
    #[pyo3(get)]
    mismatches: Py<PyList>,
    /// The error mask, (H, W, 3) uint8: `expected` at 30 % brightness, red where a pixel
    /// fails, yellow where it differs but is allowed (`--mask`).
    #[pyo3(get)]
    mask: Py<PyArray3<u8>>,
}

#[pymethods]
impl Comparison {
    /// True when the frames passed, so that `assert fpgfx.compare(a, b)` reads as meant.
    fn __bool__(&self) -> bool {
        self.passed
    }

    fn __repr__(&self) -> String {
        format!(
            "Comparison({}×{}, {}, failures={}, max_error={})",
            self.width,
            self.height,
            if self.passed { "passed" } else { "FAILED" },
            self.failures,
            self.max_error
        )
    }
}

/// Compares `actual` with `expected`, two (H, W, 3) uint8 RGB frames, as `fpgfx compare`
/// does: pixels differing by more than `tolerance` levels (a whole number, 0..=255) in
/// some channel fail. `raster` (a raster job as `fpgfx.raster` takes it) turns on the
/// dEQP-style edge allowance measured from its edges, at `coverage_precision` bits or
/// the job's `subpixel_bits` (`--raster`, `--coverage-precision`).
#[pyfunction]
#[pyo3(signature = (expected, actual, tolerance = 0.0, *, raster = None, coverage_precision = None, max_listed = 10))]
pub fn compare(
    py: Python<'_>,
    expected: &Bound<'_, PyAny>,
    actual: &Bound<'_, PyAny>,
    tolerance: f64,
    raster: Option<&Bound<'_, PyAny>>,
    coverage_precision: Option<u8>,
    max_listed: usize,
) -> PyResult<Comparison> {
    let (ew, eh, e) = rgb_frame(expected, "expected")?;
    let (aw, ah, a) = rgb_frame(actual, "actual")?;
    // The CLI's own checks on --tolerance for colour frames.
    if !(tolerance.is_finite()
        && tolerance >= 0.0
        && tolerance.fract() == 0.0
        && tolerance <= 255.0)
    {
        return Err(BindError::Value(format!(
            "tolerance: {tolerance}: colour frames take whole 8-bit levels, 0..=255"
        ))
        .into());
    }
    if let Some(bits) = coverage_precision {
        if bits > 32 {
            return Err(
                BindError::Value(format!("coverage_precision: {bits} is outside 0..=32")).into(),
            );
        }
    }
    let coverage = match raster {
        Some(job) => {
            let src = source(job, "raster", "raster job", None)?;
            let parsed =
                jobs::raster::parse(&src.text, &src.name).map_err(|e| BindError::chain(&e))?;
            let size = (
                u32::from(parsed.setup.width),
                u32::from(parsed.setup.height),
            );
            if size != (ew, eh) {
                return Err(BindError::Value(format!(
                    "{} draws {}×{}, but expected is {ew}×{eh}",
                    src.name, size.0, size.1
                ))
                .into());
            }
            Some(Coverage {
                bits: coverage_precision.unwrap_or(parsed.setup.subpixel_bits),
                edges: ::compare::raster_edges(&parsed.setup, &parsed.cmds),
            })
        }
        None if coverage_precision.is_some() => return Err(BindError::Value(
            "coverage_precision: the edge allowance needs the frame's geometry: give raster=JOB"
                .into(),
        )
        .into()),
        None => None,
    };
    let opts = Options {
        tolerance,
        coverage,
        max_listed,
    };
    let report = py.detach(|| {
        ::compare::compare(&Frame::rgb8(ew, eh, e), &Frame::rgb8(aw, ah, a), &opts)
            .map_err(|err| BindError::chain(&err))
    })?;
    let (max_error, mean_error, psnr_db) = match report.errors {
        Errors::Levels(l) => (l.max, l.mean, l.psnr_db),
        // Two RGB8 frames always give level errors.
        Errors::Float(_) => (0, 0.0, f64::INFINITY),
    };
    let mismatches = PyList::empty(py);
    let level = |s: &[f32; ::compare::MAX_CHANNELS]| (s[0] as u8, s[1] as u8, s[2] as u8);
    for m in &report.mismatches {
        let d = PyDict::new(py);
        d.set_item("x", m.x)?;
        d.set_item("y", m.y)?;
        d.set_item("expected", level(&m.expected))?;
        d.set_item("actual", level(&m.actual))?;
        d.set_item("class", m.class.name())?;
        mismatches.append(d)?;
    }
    let (w, h) = (report.width as usize, report.height as usize);
    let mask = Array3::from_shape_vec((h, w, 3), report.mask.clone())
        .map_err(|e| BindError::Value(format!("internal error: mask size: {e}")))?
        .into_pyarray(py)
        .unbind();
    Ok(Comparison {
        width: report.width,
        height: report.height,
        pixels: report.pixels(),
        equal: report.equal,
        within_tolerance: report.within_tolerance,
        near_edge: report.near_edge,
        missing: report.missing,
        unexpected: report.unexpected,
        differing: report.differing,
        failures: report.failures(),
        passed: report.passed(),
        max_error,
        mean_error,
        psnr_db,
        background: report
            .background
            .map(|c| format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])),
        mismatches: mismatches.unbind(),
        mask,
    })
}
