//! fpgfx's golden model as a Python extension module (`fpgfx._fpgfx`, re-exported by the
//! `fpgfx` package), so that a cocotb testbench can use the model as its scoreboard:
//!
//! * `raster`: a raster job (the TOML `fpgfx raster` reads, or a dict of the same shape)
//!   to the frame and the block's counters, and on request the FITkit's SPI stream, FIFO
//!   records and ordered framebuffer writes;
//! * `render`: a ray-tracer scene to the frame and its depth and normal planes;
//! * `compare`: two frames to the figures `fpgfx compare` reports;
//! * `pack` and `axi_writes`: what a testbench drives into a block itself (a raster
//!   job's packets with their FITkit SPI transactions; a scene's AXI4-Lite writes), and
//!   the submodules `fitkit` and `axi`, the two blocks' maps from the tables their
//!   Verilog headers are generated from.
//!
//! Nothing here models anything: each function hands its input to the library the `fpgfx`
//! tool runs (`vectors::raster::trace`, `vectors::render::render`, `compare::compare`), so
//! a frame from Python is the tool's frame bit for bit. What this crate adds is the
//! boundary: Python objects in, numpy arrays out, every refusal a Python exception
//! ([`Error`], a `ValueError`) carrying the library's message (file, line, key), wrong
//! arrays refused naming the argument, and the interpreter's lock released while the model
//! runs, so other Python threads (a cocotb simulator's) keep going.
//!
//! The crate is a workspace member built as a `cdylib`; maturin adds PyO3's
//! `extension-module` feature (pyproject.toml), so that plain cargo builds and lints never
//! need libpython (docs/python.md).
#![warn(missing_docs)]

mod compare;
mod input;
mod pack;
mod raster;
mod render;

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

create_exception!(
    fpgfx,
    Error,
    PyValueError,
    "A refusal by fpgfx: a job or scene that does not parse or that the model cannot run, \
     or an argument of the right type with an unusable value (an array's shape). The \
     message is the library's, naming the file, line and key where it can."
);

/// Why a call failed on the Rust side: each variant becomes one Python exception.
#[derive(Debug, thiserror::Error)]
pub(crate) enum BindError {
    /// The argument has the wrong Python type (becomes `TypeError`): a job that is
    /// neither text, a path nor a dict, an array that is no numpy `uint8` array.
    #[error("{0}")]
    Type(String),
    /// Anything else the caller can fix (becomes [`Error`]).
    #[error("{0}")]
    Value(String),
}

impl BindError {
    /// A refusal whose message is the error's own followed by each cause it does not
    /// already contain: a chained library error prints as one line, as the CLI prints it.
    pub(crate) fn chain(e: &(dyn std::error::Error + 'static)) -> Self {
        let mut text = e.to_string();
        let mut cause = e.source();
        while let Some(c) = cause {
            let s = c.to_string();
            if !text.contains(&s) {
                text.push_str(": ");
                text.push_str(&s);
            }
            cause = c.source();
        }
        BindError::Value(text)
    }
}

impl From<BindError> for PyErr {
    fn from(e: BindError) -> PyErr {
        match e {
            BindError::Type(m) => pyo3::exceptions::PyTypeError::new_err(m),
            BindError::Value(m) => Error::new_err(m),
        }
    }
}

impl From<vectors::VectorsError> for BindError {
    fn from(e: vectors::VectorsError) -> Self {
        Self::chain(&e)
    }
}

/// The module: the functions, their result classes, the two maps' submodules and the
/// exception.
#[pymodule]
fn _fpgfx(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("Error", m.py().get_type::<Error>())?;
    m.add_function(wrap_pyfunction!(raster::raster, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    m.add_function(wrap_pyfunction!(pack::pack, m)?)?;
    m.add_function(wrap_pyfunction!(pack::axi_writes, m)?)?;
    m.add_submodule(&pack::fitkit_module(m.py())?)?;
    m.add_submodule(&pack::axi_module(m.py())?)?;
    m.add_class::<raster::RasterFrame>()?;
    m.add_class::<raster::FitkitRecords>()?;
    m.add_class::<render::RenderFrame>()?;
    m.add_class::<compare::Comparison>()?;
    m.add_class::<pack::Packet>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
