//! The raster block: a framebuffer set up like the `RasterSetup` the controller sends,
//! input-FIFO packets run into it (`(channel, records)`, as the controller pushes them
//! and as `fpgfx vectors raster` lists them), and the pixels read back.

use protocol::bus::LayoutId;
use protocol::frame::{PixelFormat, Plane, ReadRequest, Rect};
use protocol::raster::{Aa, AaPattern, Cull, RasterSetup, Rgb, Traversal};
use sim_target::{Device, DeviceError};

use crate::{fpgfx_status, guard, input, output, put, Failure};

/// Bus layout code: seed 000's FITkit FIFO (36-bit records, RGB332, whole pixels).
pub const FPGFX_LAYOUT_FITKIT: u32 = 0;
/// Bus layout code: the 36-bit FIFO with opcodes, 12.4 coordinates and RGB888.
pub const FPGFX_LAYOUT_EXTENDED: u32 = 1;
/// Bus layout code: the 64-bit FIFO with 16.8 coordinates (the built-in target's).
pub const FPGFX_LAYOUT_WIDE: u32 = 2;

/// Bus channel of FITkit line packets (its SPI address for the line unit's FIFO).
pub const FPGFX_CHANNEL_LINE: u8 = 0x01;
/// Bus channel of FITkit triangle packets.
pub const FPGFX_CHANNEL_TRIANGLE: u8 = 0x02;
/// Bus channel of FITkit clear (command) packets.
pub const FPGFX_CHANNEL_COMMAND: u8 = 0x03;
/// The one bus channel of the layouts with an opcode (extended, wide): their FIFO tag in
/// `fifo_records.hex` is 0, their packets go to this channel.
pub const FPGFX_CHANNEL_STREAM: u8 = 0x04;
const _: () = assert!(
    FPGFX_CHANNEL_LINE == protocol::fitkit_spi::ADDR_LINE
        && FPGFX_CHANNEL_TRIANGLE == protocol::fitkit_spi::ADDR_TRIANGLE
        && FPGFX_CHANNEL_COMMAND == protocol::fitkit_spi::ADDR_CLEAR
        && FPGFX_CHANNEL_STREAM == protocol::bus::CHANNEL_STREAM
);

/// Anti-aliasing pattern code: one sample at the pixel centre.
pub const FPGFX_AA_NONE: u32 = 0;
/// Anti-aliasing pattern code: an n × n regular grid.
pub const FPGFX_AA_REGULAR: u32 = 1;
/// Anti-aliasing pattern code: one random sample per stratum of an n × n grid.
pub const FPGFX_AA_JITTER: u32 = 2;
/// Anti-aliasing pattern code: rotated grid (RGSS).
pub const FPGFX_AA_ROTATED: u32 = 3;
/// Anti-aliasing pattern code: Poisson-disc samples.
pub const FPGFX_AA_POISSON: u32 = 4;
/// Anti-aliasing pattern code: analytic coverage on triangle edges.
pub const FPGFX_AA_COVERAGE: u32 = 5;

/// Culling code: draw both windings.
pub const FPGFX_CULL_NONE: u32 = 0;
/// Culling code: discard triangles clockwise on screen (y down).
pub const FPGFX_CULL_CLOCKWISE: u32 = 1;
/// Culling code: discard triangles counter-clockwise on screen (y down).
pub const FPGFX_CULL_COUNTER_CLOCKWISE: u32 = 2;

/// Traversal code: every pixel of the bounding box.
pub const FPGFX_TRAVERSAL_BOUNDING_BOX: u32 = 0;
/// Traversal code: a span per scanline.
pub const FPGFX_TRAVERSAL_SCANLINE: u32 = 1;
/// Traversal code: seed 004's zigzag block scan.
pub const FPGFX_TRAVERSAL_ZIGZAG: u32 = 2;
/// Traversal code: hierarchical tiles (the default of raster files).
pub const FPGFX_TRAVERSAL_TILES: u32 = 3;
/// Traversal code: seed 000's eight pixels per step.
pub const FPGFX_TRAVERSAL_SIMD8: u32 = 4;

/// Read-back format code: three bytes per pixel, R, G, B.
pub const FPGFX_PIXEL_RGB888: u32 = 0;
/// Read-back format code: one byte per pixel, RRRGGGBB (the FITkit's memory word).
pub const FPGFX_PIXEL_RGB332: u32 = 1;

// A code's meaning is its position in protocol's `ALL` table of the enum (`LayoutId::ALL`,
// `AaPattern::ALL`, `Cull::ALL`, `Traversal::ALL`), so that raster test vectors (`fpgfx
// vectors raster`'s `raster_setup.hex`) and this library number them alike.

const FORMATS: [(PixelFormat, usize); 2] = [(PixelFormat::Rgb888, 3), (PixelFormat::Rgb332, 1)];

/// The frame-wide raster state, as `RasterSetup` carries it: size, sub-pixel bits,
/// background, anti-aliasing, culling and traversal.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct fpgfx_raster_setup {
    /// Framebuffer width in pixels.
    pub width: u16,
    /// Framebuffer height in pixels.
    pub height: u16,
    /// Fraction bits of the packets' coordinates (0 on the FITkit).
    pub subpixel_bits: u8,
    /// Colour the framebuffer is cleared to, R, G, B.
    pub background: [u8; 3],
    /// An `FPGFX_AA_*` code.
    pub aa_pattern: u32,
    /// Samples per pixel of the pattern (ignored for `FPGFX_AA_NONE`).
    pub aa_samples: u8,
    /// An `FPGFX_CULL_*` code.
    pub cull: u32,
    /// An `FPGFX_TRAVERSAL_*` code.
    pub traversal: u32,
}

/// A raster block with its framebuffer, made by `fpgfx_raster_new`, freed by
/// `fpgfx_raster_free`. Opaque to C.
pub struct fpgfx_raster {
    device: Device,
    setup: RasterSetup,
}

fn position<T: PartialEq>(table: &[T], value: &T) -> u32 {
    // Every variant is in its table (tests::every_variant_has_a_code).
    table.iter().position(|t| t == value).unwrap_or(0) as u32
}

/// The C set-up for `setup`: what `fpgfx_raster_new` decodes back into it, for Rust code
/// that writes raster vectors for a C testbench.
pub fn c_setup(setup: &RasterSetup) -> fpgfx_raster_setup {
    let bg = setup.background;
    fpgfx_raster_setup {
        width: setup.width,
        height: setup.height,
        subpixel_bits: setup.subpixel_bits,
        background: [bg.r, bg.g, bg.b],
        aa_pattern: position(&AaPattern::ALL, &setup.aa.pattern),
        aa_samples: setup.aa.samples,
        cull: position(&Cull::ALL, &setup.cull),
        traversal: position(&Traversal::ALL, &setup.traversal),
    }
}

/// The `FPGFX_LAYOUT_*` code of `layout`.
pub fn layout_code(layout: LayoutId) -> u32 {
    position(&LayoutId::ALL, &layout)
}

fn code<T: Copy>(table: &[T], value: u32, name: &str, family: &str) -> Result<T, Failure> {
    table.get(value as usize).copied().ok_or_else(|| {
        Failure::argument(format!(
            "{name} is {value}, not an {family} code (0..={})",
            table.len() - 1
        ))
    })
}

fn device_error(e: DeviceError) -> Failure {
    let status = match e {
        DeviceError::Setup(_) => fpgfx_status::FPGFX_BAD_ARGUMENT,
        _ => fpgfx_status::FPGFX_DEVICE_ERROR,
    };
    Failure::new(status, e.to_string())
}

/// Makes a raster block for bus layout `layout` (an `FPGFX_LAYOUT_*` code) and programs
/// it with `setup`: the framebuffer is cleared to the background. On success `*out`
/// holds the block; free it with `fpgfx_raster_free`.
///
/// # Safety
/// `setup` must point to a readable `fpgfx_raster_setup`, `out` to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn fpgfx_raster_new(
    layout: u32,
    setup: *const fpgfx_raster_setup,
    out: *mut *mut fpgfx_raster,
) -> fpgfx_status {
    guard(|| {
        // SAFETY: the caller's promises on `setup` and `out`. `*out` is NULL until the
        // block exists, so a failed call leaves nothing to free.
        unsafe { put(out, std::ptr::null_mut(), "out") }?;
        let s = unsafe { input(setup, 1, "setup") }?[0];
        let layout = code(&LayoutId::ALL, layout, "layout", "FPGFX_LAYOUT_*")?;
        let setup = RasterSetup {
            width: s.width,
            height: s.height,
            subpixel_bits: s.subpixel_bits,
            background: Rgb::new(s.background[0], s.background[1], s.background[2]),
            aa: Aa {
                pattern: code(
                    &AaPattern::ALL,
                    s.aa_pattern,
                    "setup->aa_pattern",
                    "FPGFX_AA_*",
                )?,
                samples: s.aa_samples,
            },
            cull: code(&Cull::ALL, s.cull, "setup->cull", "FPGFX_CULL_*")?,
            traversal: code(
                &Traversal::ALL,
                s.traversal,
                "setup->traversal",
                "FPGFX_TRAVERSAL_*",
            )?,
        };
        let mut device = Device::new(layout.layout());
        device.raster_setup(&setup).map_err(device_error)?;
        let raster = Box::new(fpgfx_raster { device, setup });
        // SAFETY: `out` was checked above; the box is handed over only on success.
        unsafe { put(out, Box::into_raw(raster), "out") }
    })
}

/// Pushes one input-FIFO packet, `n_records` records for bus channel `channel`, and runs
/// it: when this returns the framebuffer shows it. A packet that does not decode with the
/// layout, or that the block refuses, is `FPGFX_DEVICE_ERROR` naming it; the block stays
/// usable.
///
/// # Safety
/// `raster` must come from `fpgfx_raster_new` and not be freed; `records` must address
/// `n_records` words.
#[no_mangle]
pub unsafe extern "C" fn fpgfx_raster_push(
    raster: *mut fpgfx_raster,
    channel: u8,
    records: *const u64,
    n_records: usize,
) -> fpgfx_status {
    guard(|| {
        // SAFETY: the caller's promises on `raster` and `records`.
        let r = &mut unsafe { output(raster, 1, "raster") }?[0];
        let records = unsafe { input(records, n_records, "records") }?;
        r.device
            .push_packet(channel, records)
            .map_err(device_error)?;
        r.device.drain().map_err(device_error)
    })
}

/// Reads the whole framebuffer, row-major, in `format` (an `FPGFX_PIXEL_*` code):
/// `out_len` must be width · height · 3 for RGB888, width · height for RGB332.
///
/// # Safety
/// `raster` must come from `fpgfx_raster_new`; `out` must address `out_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn fpgfx_raster_read(
    raster: *mut fpgfx_raster,
    format: u32,
    out: *mut u8,
    out_len: usize,
) -> fpgfx_status {
    guard(|| {
        // SAFETY: the caller's promises on `raster` and `out`.
        let r = &mut unsafe { output(raster, 1, "raster") }?[0];
        let (format, bytes) = code(&FORMATS, format, "format", "FPGFX_PIXEL_*")?;
        let (w, h) = (r.setup.width, r.setup.height);
        let need = usize::from(w) * usize::from(h) * bytes;
        if out_len != need {
            return Err(Failure::size(format!(
                "out_len is {out_len}, the {w}x{h} framebuffer needs {need} bytes in this format"
            )));
        }
        let out = unsafe { output(out, out_len, "out") }?;
        let req = ReadRequest {
            plane: Plane::Color,
            rect: Rect { x: 0, y: 0, w, h },
            format,
        };
        r.device.read(&req, 0, out);
        Ok(())
    })
}

/// Frees a raster block; NULL is allowed and does nothing.
///
/// # Safety
/// `raster` must be NULL or come from `fpgfx_raster_new`, and not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn fpgfx_raster_free(raster: *mut fpgfx_raster) -> fpgfx_status {
    guard(|| {
        if !raster.is_null() {
            // SAFETY: it came from `Box::into_raw` in `fpgfx_raster_new` (caller's promise).
            drop(unsafe { Box::from_raw(raster) });
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_index_their_tables() {
        assert_eq!(
            LayoutId::ALL[FPGFX_LAYOUT_FITKIT as usize],
            LayoutId::Fitkit
        );
        assert_eq!(LayoutId::ALL[FPGFX_LAYOUT_WIDE as usize], LayoutId::Wide);
        assert_eq!(
            AaPattern::ALL[FPGFX_AA_COVERAGE as usize],
            AaPattern::Coverage
        );
        assert_eq!(
            Cull::ALL[FPGFX_CULL_COUNTER_CLOCKWISE as usize],
            Cull::CounterClockwise
        );
        assert_eq!(
            Traversal::ALL[FPGFX_TRAVERSAL_BOUNDING_BOX as usize],
            Traversal::BoundingBox
        );
        assert_eq!(
            Traversal::ALL[FPGFX_TRAVERSAL_TILES as usize],
            Traversal::Tiles
        );
        assert_eq!(
            Traversal::ALL[FPGFX_TRAVERSAL_SIMD8 as usize],
            Traversal::Simd8
        );
        assert_eq!(FORMATS[FPGFX_PIXEL_RGB332 as usize].0, PixelFormat::Rgb332);
    }

    #[test]
    fn every_variant_has_a_code() {
        // A new variant must get a row, or `c_setup` would map it to code 0.
        for p in AaPattern::ALL {
            match p {
                AaPattern::None
                | AaPattern::Regular
                | AaPattern::Jitter
                | AaPattern::Rotated
                | AaPattern::Poisson
                | AaPattern::Coverage => {}
            }
        }
        for c in Cull::ALL {
            match c {
                Cull::None | Cull::Clockwise | Cull::CounterClockwise => {}
            }
        }
        for l in LayoutId::ALL {
            assert_eq!(LayoutId::ALL[layout_code(l) as usize], l);
        }
        let setup = RasterSetup {
            width: 3,
            height: 2,
            subpixel_bits: 4,
            background: Rgb::new(1, 2, 3),
            aa: Aa {
                pattern: AaPattern::Jitter,
                samples: 4,
            },
            cull: Cull::Clockwise,
            traversal: Traversal::Zigzag,
        };
        let c = c_setup(&setup);
        assert_eq!(
            (c.aa_pattern, c.cull, c.traversal),
            (
                FPGFX_AA_JITTER,
                FPGFX_CULL_CLOCKWISE,
                FPGFX_TRAVERSAL_ZIGZAG
            )
        );
        assert_eq!(c.background, [1, 2, 3]);
    }
}
