//! `fpgfx.raster`: a raster job through the golden model, as `fpgfx raster` draws it on
//! the built-in target, and on request as `fpgfx vectors raster` derives the FITkit's
//! records from it.

use numpy::ndarray::{Array2, Array3};
use numpy::prelude::*;
use numpy::{IntoPyArray, PyArray2, PyArray3};
use protocol::bus::{rgb332_encode, LayoutId};
use protocol::raster::Rgb;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList, PyTuple};
use sim_target::raster::{FbWrite, Stats};
use vectors::raster::Trace;

use crate::input::source;
use crate::BindError;

/// A raster job's frame and counters (what `fpgfx raster` writes and prints).
#[pyclass(frozen, module = "fpgfx", name = "RasterFrame")]
pub struct RasterFrame {
    /// The framebuffer, (H, W, 3) uint8 RGB: the PNG `fpgfx raster` writes.
    #[pyo3(get)]
    image: Py<PyArray3<u8>>,
    /// The block's counters after the job (see [`counters`]).
    #[pyo3(get)]
    counters: Py<PyDict>,
    /// With `records=True`: the job on the FITkit layout, else `None`.
    #[pyo3(get)]
    records: Option<Py<FitkitRecords>>,
}

#[pymethods]
impl RasterFrame {
    fn __repr__(&self, py: Python<'_>) -> String {
        let shape = self.image.bind(py).shape().to_vec();
        format!(
            "RasterFrame(image={shape:?} uint8, records={})",
            if self.records.is_some() {
                "FITkit"
            } else {
                "None"
            }
        )
    }
}

/// The job as the FITkit block takes it, from the same run `fpgfx vectors raster` writes
/// its files from: a cocotb testbench drives `spi` (or `packets` into the FIFO) and holds
/// the block's memory port to `writes` and its status counters to `counters`.
#[pyclass(frozen, module = "fpgfx", name = "FitkitRecords")]
pub struct FitkitRecords {
    /// The SPI write transactions, one `bytes` per CS_n-low period (address byte first),
    /// the set-up's first: `spi_bytes.hex` cut by `spi_frames.hex`.
    #[pyo3(get)]
    spi: Py<PyList>,
    /// The input FIFO's records per packet: `(tag, [record, ...])`, tag the SPI channel
    /// (1 line, 2 triangle, 3 clear): `fifo_records.hex`.
    #[pyo3(get)]
    packets: Py<PyList>,
    /// Every framebuffer write in order, (N, 4) uint32 rows `kind, x, y, colour`: kind 0 a
    /// clear's write (a clear expanded pixel by pixel, row-major), 1 a fragment; colour
    /// the RGB332 memory word: `expected_fragments.hex`.
    #[pyo3(get)]
    writes: Py<PyArray2<u32>>,
    /// The final framebuffer, (H, W) uint8 RGB332 words: `expected_framebuffer.hex`.
    #[pyo3(get)]
    framebuffer: Py<PyArray2<u8>>,
    /// The counters of this run (bounding-box traversal, as the RTL walks): the status
    /// block's packets, fragments and per-unit cycles are these.
    #[pyo3(get)]
    counters: Py<PyDict>,
}

#[pymethods]
impl FitkitRecords {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "FitkitRecords(spi={} transactions, packets={}, writes={})",
            self.spi.bind(py).len(),
            self.packets.bind(py).len(),
            self.writes.bind(py).shape()[0]
        )
    }
}

/// Draws a raster job on the golden model, as `fpgfx raster` does on the built-in target.
///
/// `job` is the command file's TOML text, a path to it, or a dict of the same shape;
/// `name` is what error messages call it. With `records=True` the result also carries the
/// job on the FITkit layout (`RasterFrame.records`), as `fpgfx vectors raster` derives it.
/// The model runs without the interpreter's lock.
#[pyfunction]
#[pyo3(signature = (job, *, records = false, name = None))]
pub fn raster(
    py: Python<'_>,
    job: &Bound<'_, PyAny>,
    records: bool,
    name: Option<String>,
) -> PyResult<RasterFrame> {
    let src = source(job, "job", "raster job", name)?;
    // The built-in target's layout (sim_board::in_process::sim_target), whose frame the
    // CLI reads back; the FITkit's only when its records are asked for.
    let (main, fitkit) = py.detach(|| -> Result<_, BindError> {
        let main = vectors::raster::trace(&src.text, &src.name, LayoutId::Wide)?;
        let fitkit = records
            .then(|| vectors::raster::trace(&src.text, &src.name, LayoutId::Fitkit))
            .transpose()?;
        Ok((main, fitkit))
    })?;
    let (w, h) = size(&main);
    let rgb: Vec<u8> = main.frame.iter().flat_map(|c| [c.r, c.g, c.b]).collect();
    let image = Array3::from_shape_vec((h, w, 3), rgb)
        .map_err(|e| BindError::Value(format!("internal error: frame size: {e}")))?
        .into_pyarray(py)
        .unbind();
    let records = match fitkit {
        Some(t) => Some(Py::new(py, fitkit_records(py, &t)?)?),
        None => None,
    };
    Ok(RasterFrame {
        image,
        counters: counters(py, &main.stats)?.unbind(),
        records,
    })
}

fn size(t: &Trace) -> (usize, usize) {
    (
        usize::from(t.job.setup.width),
        usize::from(t.job.setup.height),
    )
}

/// The model's counters by name, each as the `Stats` field it is (docs/raster.md):
/// `commands`, `fragments`, `pixel_tests`, `block_tests`, `cycles_<unit>` per unit,
/// `cycles` (their sum, what `fpgfx raster --stats` calls FPGA cycles), `end_cycle`,
/// `board_time_s` (at the block's clock), `fifo_records`, `fifo_stalls`, `fifo_max`,
/// `fragment_stalls`.
fn counters<'py>(py: Python<'py>, s: &Stats) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("commands", s.commands)?;
    d.set_item("fragments", s.fragments)?;
    d.set_item("pixel_tests", s.pixel_tests)?;
    d.set_item("block_tests", s.block_tests)?;
    d.set_item("cycles_triangle", s.cycles.triangle)?;
    d.set_item("cycles_line", s.cycles.line)?;
    d.set_item("cycles_circle", s.cycles.circle)?;
    d.set_item("cycles_fill", s.cycles.fill)?;
    d.set_item("cycles_clear", s.cycles.clear)?;
    d.set_item("cycles", s.total_cycles())?;
    d.set_item("end_cycle", s.end_cycle)?;
    d.set_item("board_time_s", s.board_seconds())?;
    d.set_item("fifo_records", s.fifo_records)?;
    d.set_item("fifo_stalls", s.fifo_stalls)?;
    d.set_item("fifo_max", s.fifo_max)?;
    d.set_item("fragment_stalls", s.fragment_stalls)?;
    Ok(d)
}

/// The FITkit memory word of `c`; the FITkit's packer refuses other colours before the
/// model runs, so a refusal here is a bug, reported rather than written as a wrong word.
fn word(c: Rgb) -> Result<u8, BindError> {
    rgb332_encode(c).ok_or_else(|| {
        BindError::Value(format!(
            "internal error: colour {c:?} is not an RGB332 colour on the FITkit"
        ))
    })
}

fn fitkit_records(py: Python<'_>, t: &Trace) -> PyResult<FitkitRecords> {
    let (w, h) = size(t);
    let spi = PyList::empty(py);
    for transaction in t.spi.iter().flatten() {
        spi.append(PyBytes::new(py, transaction))?;
    }
    let packets = PyList::empty(py);
    for (tag, records) in &t.records {
        packets.append(PyTuple::new(
            py,
            [
                tag.into_pyobject(py)?.into_any(),
                PyList::new(py, records)?.into_any(),
            ],
        )?)?;
    }
    let mut rows: Vec<u32> = Vec::new();
    for write in &t.writes {
        match *write {
            FbWrite::Clear(c) => {
                let c = u32::from(word(c)?);
                for y in 0..h as u32 {
                    for x in 0..w as u32 {
                        rows.extend([0, x, y, c]);
                    }
                }
            }
            FbWrite::Pixel { x, y, color } => rows.extend([1, x, y, u32::from(word(color)?)]),
        }
    }
    let n = rows.len() / 4;
    let writes = Array2::from_shape_vec((n, 4), rows)
        .map_err(|e| BindError::Value(format!("internal error: writes: {e}")))?
        .into_pyarray(py)
        .unbind();
    let words = t
        .frame
        .iter()
        .map(|&c| word(c))
        .collect::<Result<Vec<u8>, _>>()?;
    let framebuffer = Array2::from_shape_vec((h, w), words)
        .map_err(|e| BindError::Value(format!("internal error: framebuffer: {e}")))?
        .into_pyarray(py)
        .unbind();
    Ok(FitkitRecords {
        spi: spi.unbind(),
        packets: packets.unbind(),
        writes,
        framebuffer,
        counters: counters(py, &t.stats)?.unbind(),
    })
}
