//! The board with the ray-casting core's RTL for the FPGA: the firmware's register-bus
//! driver ([`firmware::MmioBus`]) on the Verilated `rt_device`'s AXI4-Lite pins
//! ([`rt_core_rtl_sim::Device`]), as seed 002's MicroBlaze drives its ray tracer.
//!
//! This is `fpgfx --port rtl:rt` and `fpgfx-sim --fpga rtl:rt`. Nothing here knows the
//! core's internals: the driver sees 32-bit reads and writes, each a whole AXI4-Lite
//! handshake on the RTL's clock, and the frame comes back through the device's own
//! read-back window (`rt_readback`) from the memory its write port filled. So what passes
//! here is the driver a MicroBlaze runs, against the RTL an FPGA would be built from.

use firmware::{MmioBus, MmioError, Registers};
use protocol::bus::WIDE;
use protocol::frame::{Caps, Numeric, NumericSet};
use protocol::scene::SceneRegs;
use rt_core_rtl_sim::{AxiError, Device, Jitter, RtlError};

use crate::in_process::BuiltIn;

/// The register map's default capacities, which the Verilated core's parameters take.
type Capacity = SceneRegs;

/// The controller's FPGA bus when the FPGA is the Verilated core.
pub type RtRtlBus = MmioBus<RtlRegisters>;

/// The Verilated device as the register space the driver reads and writes.
pub struct RtlRegisters(pub Device);

/// A bus access the device did not complete, with the register's name from the map.
#[derive(Debug, thiserror::Error)]
#[error("{register}: {source}")]
pub struct RtlAccessError {
    /// The register's name in `protocol::axi_lite`'s map, or which window or range.
    pub register: &'static str,
    /// What the bus said.
    #[source]
    pub source: AxiError,
}

impl RtlRegisters {
    fn named<T>(addr: u32, r: Result<T, AxiError>) -> Result<T, RtlAccessError> {
        use protocol::axi_lite::{locate, Location};
        let register = match locate(addr) {
            Some(Location::Register(r)) => r.name,
            Some(Location::Scene(_)) => "the scene window",
            Some(Location::ReadBack(_)) => "the read-back window",
            Some(Location::Counter { .. }) => "a device counter",
            Some(Location::Texture(_)) => "the texture window",
            None => "no register of the map",
        };
        r.map_err(|source| RtlAccessError { register, source })
    }
}

impl Registers for RtlRegisters {
    type Error = RtlAccessError;

    fn read(&mut self, addr: u32) -> Result<u32, RtlAccessError> {
        Self::named(addr, self.0.read(addr))
    }

    fn write(&mut self, addr: u32, value: u32) -> Result<(), RtlAccessError> {
        Self::named(addr, self.0.write(addr, value))
    }
}

/// Why the core's target could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RtRtlTargetError {
    /// The Verilated model is missing or could not be constructed.
    #[error(transparent)]
    Rtl(#[from] RtlError),
    /// The driver's probe did not find the device on the pins.
    #[error("the driver's probe of the Verilated core: {0}")]
    Probe(MmioError<RtlAccessError>),
}

/// What the core can do: ray tracing in Q16.16 only, the terms it builds
/// ([`sim_target::rt::core::BUILD`]), the register map's objects and lights, every
/// read-back format, frames up to the protocol's side.
pub fn caps() -> Caps {
    let mut caps = sim_target::Device::new(&WIDE).caps();
    caps.raster = false;
    caps.numeric = NumericSet::default().with(Numeric::Q16_16);
    caps.float_regs = NumericSet::default();
    caps.texture_words = 0;
    caps.rt_build = sim_target::rt::core::BUILD;
    caps
}

/// Polls of one wait: enough for the longest frame [`caps`] allows (every pixel a slot
/// of `OBJ_CAPACITY` primary pairs and as many shadow pairs per light lane) at the three
/// clocks a read of `AP_CTRL` takes at the least, so only a core that has stopped runs
/// out.
pub fn poll_limit() -> u32 {
    let side = u64::from(protocol::MAX_FRAME_SIDE);
    let lanes = u64::from(sim_target::rt::core::BUILD.lights);
    let slot = Capacity::OBJ_CAPACITY as u64 * (1 + lanes);
    let clocks = side * side * slot + 1_000;
    u32::try_from(clocks / 3 + 1).unwrap_or(u32::MAX)
}

/// The identity the controller reports for this target (within the hello's
/// [`protocol::frame::IDENT_LEN`] bytes).
pub const IDENT: &str = "fpgfx RTL: rt_device, AXI4-Lite";
const _: () = assert!(IDENT.len() <= protocol::frame::IDENT_LEN);

/// The controller's register driver on `device`, probed.
pub fn bus_on(device: Device) -> Result<RtRtlBus, RtRtlTargetError> {
    let mut bus = MmioBus::new(RtlRegisters(device));
    bus.poll_limit = poll_limit();
    bus.probe().map_err(RtRtlTargetError::Probe)?;
    Ok(bus)
}

/// The driver on a fresh Verilated core whose bus and memory answer without delay.
pub fn bus() -> Result<RtRtlBus, RtRtlTargetError> {
    bus_on(Device::new(Jitter::NONE)?)
}

/// The built-in target with the controller's register driver on `device`.
pub fn rt_rtl_target_on(device: Device) -> Result<BuiltIn<RtRtlBus>, RtRtlTargetError> {
    Ok(BuiltIn::named(bus_on(device)?, caps(), &WIDE, IDENT))
}

/// `--port rtl:rt`: a fresh Verilated core, its bus and memory answering without delay.
pub fn rt_rtl_target() -> Result<BuiltIn<RtRtlBus>, RtRtlTargetError> {
    Ok(BuiltIn::named(bus()?, caps(), &WIDE, IDENT))
}
