//! The board with the FITkit block's RTL instead of the model: the firmware's controller
//! drives [`firmware::FitkitSpi`] over the Verilated block's SPI pins ([`fitkit_rtl_sim`]), as
//! seed 000's MCU drives the FPGA.
//!
//! This is `fpgfx --port rtl` and `fpgfx-sim --fpga rtl`. Nothing here knows the block's
//! internals: the controller sees an `embedded-hal` SPI device and a delay, the same two
//! things it would get from a board's HAL, so what passes here is the driver a FITkit
//! user flashes.

use firmware::FitkitSpi;
use fitkit_rtl_sim::{Rtl, RtlDelay, RtlError, RtlSpi, SharedRtl, SpiConfig, SpiError};
use protocol::bus::FITKIT;
use protocol::fitkit_spi::{FIFO_RECORDS, FRAME_SIDE};
use protocol::frame::{Caps, NumericSet, PixelFormat};
use protocol::raster::MAX_SUBPIXEL_BITS;

use crate::in_process::BuiltIn;

/// The controller's FPGA bus when the FPGA is the Verilated RTL.
pub type RtlBus = FitkitSpi<RtlSpi, RtlDelay>;

/// Why the RTL target could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RtlTargetError {
    /// The Verilated model is missing or could not be constructed.
    #[error(transparent)]
    Rtl(#[from] RtlError),
    /// The SPI timing is outside what the block can follow.
    #[error(transparent)]
    Spi(#[from] SpiError),
}

/// What the FITkit block can do: raster only, 512 × 512 (9-bit coordinates), the
/// FITkit's 36-bit records and 512-record FIFO, read-back as RGB332 or expanded to
/// RGB888. Sub-pixel points are accepted at any precision the packer can rescale exactly:
/// whole pixels pass, fractions are refused by the layout, naming the command.
pub fn caps() -> Caps {
    Caps {
        raster: true,
        ray_trace: false,
        numeric: NumericSet::default(),
        pixel_formats: PixelFormat::Rgb888.bit() | PixelFormat::Rgb332.bit(),
        max_width: FRAME_SIDE,
        max_height: FRAME_SIDE,
        max_subpixel_bits: MAX_SUBPIXEL_BITS,
        queue_depth: firmware::INBOX as u16,
        fifo_depth: FIFO_RECORDS,
        max_objects: 0,
        max_lights: 0,
        texture_words: 0,
        // The engine fills in the layout it packs in.
        raster_layout: None,
        float_regs: NumericSet::default(),
        // no ray tracer: `ray_trace` is false, which refuses every scene first
        rt_build: protocol::frame::RtBuild::FULL,
        link_payload: 0,
    }
}

/// The controller's bus on `rtl` with `config`'s SPI timing.
pub fn bus_on(rtl: &SharedRtl, config: SpiConfig) -> Result<RtlBus, RtlTargetError> {
    let spi = RtlSpi::new(rtl.clone(), config)?;
    let delay = RtlDelay::new(rtl.clone(), config)?;
    Ok(FitkitSpi::new(spi, delay))
}

/// The built-in target on a given model, so a caller (a test, `--stats`) keeps a handle
/// to the RTL's clock and pins.
pub fn rtl_target_on(
    rtl: &SharedRtl,
    config: SpiConfig,
) -> Result<BuiltIn<RtlBus>, RtlTargetError> {
    Ok(BuiltIn::named(
        bus_on(rtl, config)?,
        caps(),
        &FITKIT,
        "fpgfx RTL target: Verilated hw/fitkit-raster/rtl/ on FITkit SPI",
    ))
}

/// `--port rtl`: a fresh Verilated block at the fastest SPI clock the block allows
/// (f_clk / 8).
pub fn rtl_target() -> Result<BuiltIn<RtlBus>, RtlTargetError> {
    rtl_target_on(&Rtl::shared()?, SpiConfig::default())
}
