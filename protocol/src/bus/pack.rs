//! Commands to records and back, and the channel each kind travels on.

use super::bits::{BitReader, BitWriter};
use super::error::BusError;
use super::fragment::{walk_fragment, Fragment};
use super::layout::{BusLayout, Kind};
use super::walk::{Dec, Decoded, Describe, Enc, Field, PackOptions, Walker};
use super::{CHANNEL_STREAM, MAX_FIELDS, MAX_RECORDS};
use crate::fitkit_spi::{ADDR_CLEAR, ADDR_LINE, ADDR_TRIANGLE};
use crate::raster::{
    Bezier, BezierPatch, Circle, Connectivity, FillRule, Line, LineAlgo, Pixel, Point, Polygon,
    RasterCmd, Rgb, SeedFill, Shade, Triangle,
};
use heapless::Vec;

/// Largest [`PackOptions::subpixel_bits`] (and `subpixel_bits` of [`unpack`]): the
/// precision of the caller's values that the packer rescales to and from a layout's, kept
/// low enough that every rescaled coordinate fits an i64. It bounds this conversion only;
/// what a target accepts is [`crate::raster::MAX_SUBPIXEL_BITS`].
pub const MAX_CALLER_SUBPIXEL_BITS: u8 = 24;

pub(super) fn check(layout: &BusLayout, subpixel_bits: u8) -> Result<(), BusError> {
    layout.validate()?;
    if subpixel_bits > MAX_CALLER_SUBPIXEL_BITS {
        return Err(BusError::OutOfRange {
            layout: layout.name,
            field: "subpixel_bits",
            value: i64::from(subpixel_bits),
            min: 0,
            max: i64::from(MAX_CALLER_SUBPIXEL_BITS),
        });
    }
    Ok(())
}

/// A command of `kind` with every field zero: what decoding fills in.
pub(super) fn template(kind: Kind) -> RasterCmd {
    let black = Rgb::default();
    let p = Point::default();
    match kind {
        Kind::Line => RasterCmd::Line(Line {
            from: p,
            to: p,
            color: black,
            color_to: None,
            width: 0,
            aa: false,
            algo: LineAlgo::Bresenham,
        }),
        Kind::Triangle => RasterCmd::Triangle(Triangle {
            v: [p; 3],
            shade: Shade::Flat(black),
            z: None,
            w: None,
            tex: None,
        }),
        Kind::Circle => RasterCmd::Circle(Circle {
            center: p,
            radius: 0,
            color: black,
            fill: false,
        }),
        Kind::Fill => RasterCmd::Fill(SeedFill {
            seed: Pixel::default(),
            color: black,
            connectivity: Connectivity::Four,
        }),
        Kind::Polygon => RasterCmd::Polygon(Polygon {
            points: Vec::new(),
            rule: FillRule::NonZero,
            color: black,
        }),
        Kind::Bezier => RasterCmd::Bezier(Bezier {
            points: Vec::new(),
            color: black,
            tolerance: 0,
        }),
        Kind::Patch => RasterCmd::Patch(BezierPatch {
            points: [p; 16],
            steps: 0,
            color: black,
        }),
        Kind::Clear | Kind::Fragment => RasterCmd::Clear(black),
    }
}

pub(super) fn unsupported(layout: &BusLayout, kind: Kind) -> BusError {
    BusError::UnsupportedCommand {
        layout: layout.name,
        command: kind.name(),
    }
}

/// The SPI address a command of `kind` is written to on `layout`.
pub fn channel(layout: &BusLayout, kind: Kind) -> Result<u8, BusError> {
    if !layout.supports(kind) || kind == Kind::Fragment {
        return Err(unsupported(layout, kind));
    }
    if layout.opcode_bits > 0 {
        return Ok(CHANNEL_STREAM);
    }
    match kind {
        Kind::Line => Ok(ADDR_LINE),
        Kind::Triangle => Ok(ADDR_TRIANGLE),
        Kind::Clear => Ok(ADDR_CLEAR),
        _ => Err(unsupported(layout, kind)),
    }
}

pub(super) fn kind_of_channel(layout: &BusLayout, ch: u8) -> Result<Option<Kind>, BusError> {
    let unknown = BusError::UnknownChannel {
        layout: layout.name,
        channel: ch,
    };
    if layout.opcode_bits > 0 {
        return if ch == CHANNEL_STREAM {
            Ok(None)
        } else {
            Err(unknown)
        };
    }
    let kind = match ch {
        ADDR_LINE => Kind::Line,
        ADDR_TRIANGLE => Kind::Triangle,
        ADDR_CLEAR => Kind::Clear,
        _ => return Err(unknown),
    };
    if layout.supports(kind) {
        Ok(Some(kind))
    } else {
        Err(unknown)
    }
}

/// Packs one command into `out` and returns the number of records used (the rest of `out`
/// is zeroed). Nothing is truncated: a value that does not fit is an error naming it.
pub fn pack_into(
    layout: &BusLayout,
    cmd: &RasterCmd,
    opts: PackOptions,
    out: &mut [u64],
) -> Result<usize, BusError> {
    check(layout, opts.subpixel_bits)?;
    let kind = Kind::of(cmd);
    if !layout.supports(kind) {
        return Err(unsupported(layout, kind));
    }
    let mut w = Walker {
        io: Enc(BitWriter::new(out, layout.record_bits, 0)?),
        layout,
        sub: opts.subpixel_bits,
    };
    let mut clear = opts.clear || kind == Kind::Clear;
    w.header(kind, &mut clear)?;
    let mut c = cmd.clone();
    w.body(&mut c)?;
    Ok(w.io.0.records_used())
}

/// Packs one command into a new record vector (see [`pack_into`]).
pub fn pack(
    layout: &BusLayout,
    cmd: &RasterCmd,
    opts: PackOptions,
) -> Result<Vec<u64, MAX_RECORDS>, BusError> {
    let mut buf = [0u64; MAX_RECORDS];
    let n = pack_into(layout, cmd, opts, &mut buf)?;
    Vec::from_slice(&buf[..n]).map_err(|_| BusError::BufferTooSmall {
        capacity: MAX_RECORDS,
    })
}

/// Decodes the records of exactly one packet received on `channel`, giving points and
/// lengths in `subpixel_bits` units. Trailing records, non-zero padding, unknown opcodes
/// and enumeration codes are errors.
pub fn unpack(
    layout: &BusLayout,
    channel: u8,
    records: &[u64],
    subpixel_bits: u8,
) -> Result<Decoded, BusError> {
    check(layout, subpixel_bits)?;
    let fixed = kind_of_channel(layout, channel)?;
    let mut w = Walker {
        io: Dec(BitReader::new(records, layout.record_bits, 0)?),
        layout,
        sub: subpixel_bits,
    };
    let mut clear = false;
    let kind = w.header(fixed.unwrap_or(Kind::Clear), &mut clear)?;
    if kind == Kind::Clear && !clear {
        return Err(w.invalid("cb", 0));
    }
    let mut cmd = template(kind);
    w.body(&mut cmd)?;
    let pos = w.io.0.position();
    let rb = usize::from(layout.record_bits);
    let used = pos.div_ceil(rb);
    if used != records.len() {
        return Err(BusError::TrailingRecords {
            used,
            given: records.len(),
        });
    }
    let pad = used * rb - pos;
    if pad > 0 {
        let value = w.io.0.read(pad as u8)?;
        if value != 0 {
            return Err(BusError::NonZeroPadding { bits: pad, value });
        }
    }
    Ok(Decoded { clear, cmd })
}

/// The fields of the base form of a `kind` packet on `layout` (every optional flag off;
/// a polygon with 3 vertices, a quadratic Bézier), header included.
pub fn fields(layout: &BusLayout, kind: Kind) -> Result<Vec<Field, MAX_FIELDS>, BusError> {
    layout.validate()?;
    if !layout.supports(kind) {
        return Err(unsupported(layout, kind));
    }
    let mut w = Walker {
        io: Describe(Vec::new()),
        layout,
        sub: layout.subpixel_bits,
    };
    if kind == Kind::Fragment {
        walk_fragment(&mut w, &mut Fragment::default())?;
    } else {
        let mut clear = false;
        w.header(kind, &mut clear)?;
        w.body(&mut template(kind))?;
    }
    Ok(w.io.0)
}
