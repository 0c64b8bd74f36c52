//! The packers a testbench needs to drive a block itself, and the maps it needs to read
//! one back: `fpgfx.pack` (a raster job's packets, on the FITkit with the SPI
//! transaction of each), `fpgfx.axi_writes` (a scene's AXI4-Lite write sequence), and the
//! submodules `fpgfx.fitkit` and `fpgfx.axi` (every address, bit and code of the two
//! maps, from the tables the Verilog headers are generated from, and the FITkit's
//! transaction builders and status decoder).

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use protocol::axi_lite;
use protocol::bus::LayoutId;
use protocol::fitkit_spi::{self, ErrorCode, Status};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::input::source;
use crate::render::registers;
use crate::BindError;

/// One packet of a raster job as the controller pushes it.
#[pyclass(frozen, module = "fpgfx", name = "Packet")]
pub struct Packet {
    /// Index of the job's command this packet carries; `None` for the FITkit's set-up.
    #[pyo3(get)]
    command: Option<usize>,
    /// The command's `op` as the job file spells it (`"setup"` for the set-up).
    #[pyo3(get)]
    op: &'static str,
    /// On the FITkit the SPI address (the FIFO tag: `fitkit.ADDR_*`); on the other
    /// layouts the controller's channel.
    #[pyo3(get)]
    address: u8,
    /// The input FIFO's records, in push order (36-bit on the FITkit).
    #[pyo3(get)]
    records: Vec<u64>,
    /// On the FITkit, the whole CS_n-low write transaction, address byte first; `None`
    /// on layouts without SPI framing.
    #[pyo3(get)]
    spi: Option<Py<PyBytes>>,
}

#[pymethods]
impl Packet {
    fn __repr__(&self, py: Python<'_>) -> String {
        let records: Vec<String> = self.records.iter().map(|r| format!("{r:#x}")).collect();
        format!(
            "Packet(command={}, op={:?}, address={:#04x}, records=[{}], spi={})",
            self.command
                .map_or_else(|| "None".to_string(), |c| c.to_string()),
            self.op,
            self.address,
            records.join(", "),
            self.spi.as_ref().map_or_else(
                || "None".to_string(),
                |b| format!("{} bytes", b.bind(py).as_bytes().len())
            )
        )
    }
}

/// Packs a raster job for `layout` as the controller packs it, without running the model.
///
/// `job` is the command file's TOML text, a path to it, or a dict of the same shape; a
/// command the layout cannot carry raises `fpgfx.Error` naming it. On the FITkit the
/// first packet is the set-up (`command` None) and every packet carries its SPI
/// transaction; a testbench polls the status block for `len(records)` free records
/// before each one, as the controller does.
#[pyfunction]
#[pyo3(signature = (job, *, layout = "fitkit", name = None))]
pub fn pack(
    py: Python<'_>,
    job: &Bound<'_, PyAny>,
    layout: &str,
    name: Option<String>,
) -> PyResult<Vec<Packet>> {
    let src = source(job, "job", "raster job", name)?;
    let id = layout_id(layout)?;
    let packing = vectors::raster::pack(&src.text, &src.name, id).map_err(BindError::from)?;
    let ops = packing.job.cmds.iter().map(jobs::raster::op_name);
    let mut out = Vec::new();
    match &packing.spi {
        Some(transactions) => {
            // The driver's set-up first, then one transaction per packet.
            if transactions.len() != packing.packets.len() + 1 {
                return Err(BindError::Value(format!(
                    "internal error: {} SPI transactions for {} packets",
                    transactions.len(),
                    packing.packets.len()
                ))
                .into());
            }
            let commands = std::iter::once((None, "setup"))
                .chain(ops.enumerate().map(|(i, op)| (Some(i), op)));
            for ((command, op), t) in commands.zip(transactions) {
                let (address, records) = vectors::raster::decoder_records(t);
                out.push(Packet {
                    command,
                    op,
                    address,
                    records,
                    spi: Some(PyBytes::new(py, t).unbind()),
                });
            }
        }
        None => {
            for ((i, op), (channel, records)) in ops.enumerate().zip(&packing.packets) {
                out.push(Packet {
                    command: Some(i),
                    op,
                    address: *channel,
                    records: records.to_vec(),
                    spi: None,
                });
            }
        }
    }
    Ok(out)
}

/// The layout a name means: `fitkit`, `extended` or `wide` (the built-in target's).
fn layout_id(name: &str) -> Result<LayoutId, BindError> {
    LayoutId::ALL
        .into_iter()
        .find(|id| id.layout().name.eq_ignore_ascii_case(name))
        .ok_or_else(|| {
            let names: Vec<&str> = LayoutId::ALL.iter().map(|id| id.layout().name).collect();
            BindError::Value(format!(
                "layout: {name:?} is not one of {}",
                names.join(", ")
            ))
        })
}

/// The AXI4-Lite writes that render `scene` on the ray-casting core: the register image
/// word by word from `axi.SCENE_BASE`, then `NUMERIC`, `AOVS` and `AP_CTRL` with
/// `ap_start`, as (N, 2) uint32 rows `address, data` in bus order. The image is the one
/// `render(scene, numeric, size=, spp=)` renders from (`RenderFrame.regs`); nothing is
/// rendered here. `scene` is what `render` takes, a register image included.
#[pyfunction]
#[pyo3(signature = (scene, numeric = "q16.16", *, size = None, spp = None, name = None))]
pub fn axi_writes<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    numeric: &str,
    size: Option<(u32, u32)>,
    spp: Option<u32>,
    name: Option<String>,
) -> PyResult<Bound<'py, PyArray2<u32>>> {
    let regs = registers(py, scene, numeric, size, spp, name)?;
    Ok(writes_array(&regs.writes())?.into_pyarray(py))
}

/// `(address, data)` pairs as an (N, 2) uint32 array.
pub(crate) fn writes_array(writes: &[(u32, u32)]) -> Result<Array2<u32>, BindError> {
    let flat: Vec<u32> = writes.iter().flat_map(|&(a, d)| [a, d]).collect();
    Array2::from_shape_vec((writes.len(), 2), flat)
        .map_err(|e| BindError::Value(format!("internal error: writes: {e}")))
}

/// The FITkit's write transaction for one packet: `address`, then the records' 36-bit
/// strings MSB first, zero-padded to whole bytes.
#[pyfunction(name = "packet")]
fn fitkit_packet<'py>(
    py: Python<'py>,
    address: u8,
    records: Vec<u64>,
) -> PyResult<Bound<'py, PyBytes>> {
    let mut buf = [0u8; 1 + fitkit_spi::MAX_PACKET_BYTES];
    let n = fitkit_spi::packet(address, &records, &mut buf).map_err(|e| BindError::chain(&e))?;
    Ok(PyBytes::new(py, &buf[..n]))
}

/// The bytes that open a read-back from pixel `(x, y)`: address, the pixel address in
/// three bytes and the turnaround byte; the pixels follow, one RGB332 byte per byte
/// clocked, row-major with rows of 512.
#[pyfunction]
fn read_header<'py>(py: Python<'py>, x: u32, y: u32) -> PyResult<Bound<'py, PyBytes>> {
    let h = fitkit_spi::read_header(x, y).map_err(|e| BindError::chain(&e))?;
    Ok(PyBytes::new(py, &h))
}

/// The framebuffer address of pixel `(x, y)` on the block's memory port.
#[pyfunction]
fn pixel_address(x: u32, y: u32) -> PyResult<u32> {
    Ok(fitkit_spi::pixel_address(x, y).map_err(|e| BindError::chain(&e))?)
}

/// Decodes the status block (the `STATUS_BYTES` bytes after the address byte of a read
/// at `ADDR_STATUS`), refusing bytes the block never sends (a floating MISO line).
#[pyfunction]
fn status<'py>(py: Python<'py>, data: &[u8]) -> PyResult<Bound<'py, PyDict>> {
    let block: &[u8; fitkit_spi::STATUS_BYTES] = data.try_into().map_err(|_| {
        BindError::Value(format!(
            "data: {} bytes, a status block is {}",
            data.len(),
            fitkit_spi::STATUS_BYTES
        ))
    })?;
    let s = Status::decode(block).map_err(|e| BindError::chain(&e))?;
    let d = PyDict::new(py);
    d.set_item("free", s.free)?;
    d.set_item("flags", s.flags)?;
    // The flags by name: the map's FLAG_* are bit numbers (as the Verilog header has
    // them), so a caller testing `flags & FLAG_BUSY` would test bit 0's number, not bit 0.
    for (key, mask) in [
        ("busy", fitkit_spi::FLAG_BUSY),
        ("fifo_empty", fitkit_spi::FLAG_FIFO_EMPTY),
        ("setup_done", fitkit_spi::FLAG_SETUP_DONE),
        ("no_line", fitkit_spi::FLAG_NO_LINE),
        ("no_triangle", fitkit_spi::FLAG_NO_TRIANGLE),
    ] {
        d.set_item(key, s.flags & mask != 0)?;
    }
    match s.error {
        Some(e) => {
            let err = PyDict::new(py);
            err.set_item("code", e.code.code())?;
            err.set_item("name", e.code.verilog_name())?;
            err.set_item("message", e.code.to_string())?;
            err.set_item("channel", e.channel)?;
            err.set_item("packet", e.packet)?;
            d.set_item("error", err)?;
        }
        None => d.set_item("error", py.None())?,
    }
    d.set_item("packets", s.packets)?;
    d.set_item("fragments", s.fragments)?;
    d.set_item("line_cycles", s.line_cycles)?;
    d.set_item("triangle_cycles", s.triangle_cycles)?;
    d.set_item("clear_cycles", s.clear_cycles)?;
    d.set_item("end_cycle", s.end_cycle)?;
    d.set_item("fifo_max_pairs", s.fifo_max_pairs)?;
    Ok(d)
}

/// The name of the AXI4-Lite register (or window) at byte address `addr`.
#[pyfunction]
fn register_name(addr: u32) -> &'static str {
    axi_lite::register_name(addr)
}

/// `fpgfx.fitkit`: the FITkit raster block's SPI map (`protocol::fitkit_spi::MAP` and
/// its error codes, the source of `fitkit_map.vh`) and its transaction helpers.
pub(crate) fn fitkit_module<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyModule>> {
    let m = PyModule::new(py, "fitkit")?;
    for e in fitkit_spi::MAP {
        m.add(e.name, e.value)?;
    }
    for e in ErrorCode::ALL {
        m.add(format!("ERR_{}", e.verilog_name()), e.code())?;
    }
    m.add_function(wrap_pyfunction!(fitkit_packet, &m)?)?;
    m.add_function(wrap_pyfunction!(read_header, &m)?)?;
    m.add_function(wrap_pyfunction!(pixel_address, &m)?)?;
    m.add_function(wrap_pyfunction!(status, &m)?)?;
    without_all(m)
}

/// `fpgfx.axi`: the ray tracer's AXI4-Lite map (`protocol::axi_lite::MAP` and the plane,
/// format and counter codes: every define of `rt_axi_map.vh`), the register table by name, the device counters' addresses and
/// the register-name lookup.
pub(crate) fn axi_module<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyModule>> {
    let m = PyModule::new(py, "axi")?;
    for e in axi_lite::MAP {
        m.add(e.name, e.value)?;
    }
    // The codes the header names after their variants, spelled as it spells them.
    let name = |prefix: &str, variant: std::fmt::Arguments<'_>| -> PyResult<String> {
        let mut s = prefix.to_string();
        axi_lite::screaming(&mut s, variant)
            .map_err(|e| BindError::Value(format!("internal error: {e}")))?;
        Ok(s)
    };
    for p in axi_lite::PLANES {
        m.add(
            name("PLANE_", format_args!("{p:?}"))?,
            axi_lite::plane_code(p),
        )?;
    }
    for f in axi_lite::FORMATS {
        m.add(
            name("FORMAT_", format_args!("{f:?}"))?,
            axi_lite::format_code(f),
        )?;
        m.add(name("BPP_", format_args!("{f:?}"))?, f.bytes_per_pixel())?;
    }
    for (i, c) in axi_lite::COUNTERS.iter().enumerate() {
        m.add(format!("COUNTER_{}", c.name.to_ascii_uppercase()), i)?;
    }
    let regs = PyDict::new(py);
    for r in axi_lite::REGISTERS {
        regs.set_item(r.name, r.addr)?;
    }
    m.add("REGISTERS", regs)?;
    let counters = PyDict::new(py);
    for (i, c) in axi_lite::COUNTERS.iter().enumerate() {
        counters.set_item(c.name, axi_lite::counter_addr(i))?;
    }
    m.add("COUNTERS", counters)?;
    m.add_function(wrap_pyfunction!(register_name, &m)?)?;
    without_all(m)
}

/// The module without the `__all__` PyO3 keeps: a star import takes every public name
/// anyway, and without it the type stubs need not list every constant a second time.
fn without_all(m: Bound<'_, PyModule>) -> PyResult<Bound<'_, PyModule>> {
    if m.hasattr("__all__")? {
        m.delattr("__all__")?;
    }
    Ok(m)
}
