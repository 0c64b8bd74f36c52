//! `fpgfx.render`: a ray-tracer scene through the golden model, as `fpgfx render` renders
//! it on the built-in target (`vectors::render::render`, which `fpgfx vectors render`
//! writes its expected planes from).

use std::ffi::CString;

use numpy::ndarray::{Array1, Array2, Array3};
use numpy::prelude::*;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use protocol::frame::Numeric;
use protocol::names::Named;
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vectors::render::RenderCounters;

use crate::input::{register_image, source};
use crate::BindError;

/// A rendered frame with its planes and the register image it was rendered from.
#[pyclass(frozen, module = "fpgfx", name = "RenderFrame")]
pub struct RenderFrame {
    /// The frame, (H, W, 3) uint8 RGB: the PNG `fpgfx render` writes.
    #[pyo3(get)]
    image: Py<PyArray3<u8>>,
    /// Distance to the first hit per pixel, (H, W) float32, +inf where the primary ray
    /// missed: `fpgfx render --aov depth=…`'s plane.
    #[pyo3(get)]
    depth: Py<PyArray2<f32>>,
    /// World-space normal per pixel, (H, W, 3) float32, 0 where the ray missed.
    #[pyo3(get)]
    normal: Py<PyArray3<f32>>,
    /// The register image (uint32, scene memory order) the block was given: what a
    /// testbench writes over AXI4-Lite from `SCENE_BASE` on before `ap_start`.
    #[pyo3(get)]
    regs: Py<PyArray1<u32>>,
    /// The AXI4-Lite writes of the frame, (N, 2) uint32 rows `address, data` in bus
    /// order: the image from `SCENE_BASE` on, then `NUMERIC`, `AOVS` and `AP_CTRL`.
    #[pyo3(get)]
    writes: Py<PyArray2<u32>>,
    /// What the frame cost: `rays_traced`, `rays_nominal`, `cycles` (the model's
    /// `RT_CYCLES`), `board_time_s`, `core_cycles` (the ray-casting core's `RT_CYCLES`
    /// for this image) and `saturations`.
    #[pyo3(get)]
    counters: Py<PyDict>,
    /// The number format the frame was rendered in, spelled as `--numeric` takes it.
    #[pyo3(get)]
    numeric: &'static str,
}

#[pymethods]
impl RenderFrame {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "RenderFrame(image={:?} uint8, numeric={:?})",
            self.image.bind(py).shape(),
            self.numeric
        )
    }
}

/// Renders a ray-tracer scene on the golden model, as `fpgfx render --numeric NUMERIC`
/// does on the built-in target (`size` as `--size WxH`, `spp` as `--spp`).
///
/// `scene` is the scene file's TOML text, a path to it, a dict of the same shape, or a
/// register image (1-D uint32, as `RenderFrame.regs`) decoded as the device decodes it;
/// `name` is what error messages call it. Fields whose magnitudes `numeric` cannot hold
/// are reported as `UserWarning`s, as the CLI warns. The model runs without the
/// interpreter's lock.
#[pyfunction]
#[pyo3(signature = (scene, numeric = "q16.16", *, size = None, spp = None, name = None))]
pub fn render(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    numeric: &str,
    size: Option<(u32, u32)>,
    spp: Option<u32>,
    name: Option<String>,
) -> PyResult<RenderFrame> {
    let regs = registers(py, scene, numeric, size, spp, name)?;
    let v = py.detach(|| vectors::render::render_registers(&regs).map_err(BindError::from))?;
    let (w, h) = (v.width as usize, v.height as usize);
    let shape = |e: numpy::ndarray::ShapeError| {
        BindError::Value(format!("internal error: plane size: {e}"))
    };
    let writes = crate::pack::writes_array(&v.writes())?
        .into_pyarray(py)
        .unbind();
    Ok(RenderFrame {
        image: Array3::from_shape_vec((h, w, 3), v.rgb888)
            .map_err(shape)?
            .into_pyarray(py)
            .unbind(),
        depth: Array2::from_shape_vec((h, w), v.depth)
            .map_err(shape)?
            .into_pyarray(py)
            .unbind(),
        normal: Array3::from_shape_vec((h, w, 3), v.normal)
            .map_err(shape)?
            .into_pyarray(py)
            .unbind(),
        regs: Array1::from_vec(v.regs.to_vec()).into_pyarray(py).unbind(),
        writes,
        counters: counters(py, &v.counters)?.unbind(),
        numeric: regs.start.numeric.spellings()[0],
    })
}

/// The frame's counters by name (`vectors::render::RenderCounters`), plus `board_time_s`
/// at the HLS block's clock.
fn counters<'py>(py: Python<'py>, c: &RenderCounters) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("rays_traced", c.rays_traced)?;
    d.set_item("rays_nominal", c.rays_nominal)?;
    d.set_item("cycles", c.cycles)?;
    d.set_item(
        "board_time_s",
        c.cycles as f64 / sim_target::rt::BOARD_CLOCK_HZ,
    )?;
    d.set_item("core_cycles", c.core_cycles)?;
    d.set_item("saturations", c.saturations)?;
    Ok(d)
}

/// The scene argument as the register image the block is given: a scene (text, path or
/// dict) parsed and written into an image as the CLI does (`numeric` as `--numeric`,
/// `size` as `--size`, `spp` as `--spp`), warning about fields the format cannot hold; or
/// a register image (a numpy uint32 array) decoded as the device decodes it. Shared by
/// `render` and `axi_writes`, so both give a testbench the same image.
pub(crate) fn registers(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    numeric: &str,
    size: Option<(u32, u32)>,
    spp: Option<u32>,
    name: Option<String>,
) -> PyResult<vectors::render::Registers> {
    let format: Numeric = numeric
        .parse()
        .map_err(|e| BindError::Value(format!("numeric: {numeric:?}: {e}")))?;
    if let Some(image) = register_image(scene, "scene")? {
        // The image carries its frame size and samples; changing them is a new image.
        if let Some((w, h)) = size {
            return Err(BindError::Value(format!(
                "size: {w}x{h} given with a register image, which carries its own frame size"
            ))
            .into());
        }
        if let Some(spp) = spp {
            return Err(BindError::Value(format!(
                "spp: {spp} given with a register image, which carries its own samples per pixel"
            ))
            .into());
        }
        let regs = vectors::render::decode(&image, format).map_err(BindError::from)?;
        let what = name.unwrap_or_else(|| "<register image>".into());
        warn_out_of_range(py, &what, &regs.scene, format)?;
        return Ok(regs);
    }
    let src = source(scene, "scene", "scene", name)?;
    let max = protocol::MAX_FRAME_SIDE;
    if let Some((w, h)) = size {
        if w == 0 || h == 0 || w > max || h > max {
            return Err(
                BindError::Value(format!("size: {w}x{h} is outside 1..={max} per side")).into(),
            );
        }
    }
    let mut parsed = jobs::scene::parse(&src.text, &src.name).map_err(|e| BindError::chain(&e))?;
    if let Some(spp) = spp {
        if !(1..=256).contains(&spp) {
            return Err(BindError::Value(format!("spp: {spp} is outside 1..=256")).into());
        }
        parsed.spp = spp;
    }
    warn_out_of_range(py, &src.name, &parsed, format)?;
    let opts = vectors::render::Options {
        numeric: format,
        size,
    };
    Ok(vectors::render::registers(&parsed, &opts).map_err(BindError::from)?)
}

/// The CLI's warning (host-cli's `warn_out_of_range`) as a Python `UserWarning`: a
/// fixed-point datapath saturates silently, so the caller hears it field by field.
fn warn_out_of_range(
    py: Python<'_>,
    name: &str,
    scene: &sim_target::rt::Scene,
    numeric: Numeric,
) -> PyResult<()> {
    use jobs::scene::range::{format_max, out_of_range};
    let format = numeric.spellings()[0];
    for d in out_of_range(scene, numeric) {
        let text = format!(
            "{name}: {}: the {} reaches {:.1}, beyond {format}'s range of ±{}: that part of \
             the frame will saturate; render in a wider format",
            d.field,
            d.what,
            d.value,
            format_max(numeric)
        );
        let text = CString::new(text.replace('\0', "")).unwrap_or_default();
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &text, 2)?;
    }
    Ok(())
}
