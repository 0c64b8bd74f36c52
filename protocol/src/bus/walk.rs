//! The single description of every packet: one walk over its fields that encodes,
//! decodes or lists them, so the three can never disagree.

use super::bits::{mask, BitReader, BitWriter};
use super::color::{rgb24, rgb332_decode, rgb332_encode};
use super::error::BusError;
use super::layout::{
    BusLayout, Kind, FEAT_LINE_STYLE, FEAT_PER_VERTEX_COLOR, FEAT_TEXTURE, FEAT_W,
};
use super::{MAX_FIELDS, TEX_BASE_BITS};
use crate::raster::{
    Bezier, BezierPatch, Circle, Connectivity, FillRule, Filter, Line, LineAlgo, Point, Polygon,
    RasterCmd, Rgb, SeedFill, Shade, TexRef, Triangle, Wrap,
};
use heapless::Vec;

/// How the caller's values relate to the packet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PackOptions {
    /// Fraction bits of the caller's [`Point`]s and lengths (the frame's
    /// `RasterSetup::subpixel_bits`); they are rescaled to the layout's exactly or refused.
    pub subpixel_bits: u8,
    /// Set CB: clear the framebuffer before this command. [`RasterCmd::Clear`] always sets it.
    pub clear: bool,
}

/// A packet read back from records.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decoded {
    /// The CB bit: the packet asked for a clear before its command.
    pub clear: bool,
    /// The command, in the sub-pixel units asked of [`unpack`](crate::bus::unpack).
    pub cmd: RasterCmd,
}

/// One field of a packet, for documentation and efficiency figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    /// Name as used in errors.
    pub name: &'static str,
    /// Width in bits.
    pub bits: u8,
}

// ---------------------------------------------------------------------------------------
// The single description of every packet: a walk over the fields that encodes, decodes or
// lists them depending on `Io`, so the three can never disagree.

pub(super) trait Io {
    const DECODE: bool;
    fn bits(&mut self, name: &'static str, width: u8, raw: u64) -> Result<u64, BusError>;
}

pub(super) struct Enc<'a>(pub(super) BitWriter<'a>);
impl Io for Enc<'_> {
    const DECODE: bool = false;
    fn bits(&mut self, _: &'static str, width: u8, raw: u64) -> Result<u64, BusError> {
        self.0.write(raw, width).map(|()| raw)
    }
}

pub(super) struct Dec<'a>(pub(super) BitReader<'a>);
impl Io for Dec<'_> {
    const DECODE: bool = true;
    fn bits(&mut self, _: &'static str, width: u8, _: u64) -> Result<u64, BusError> {
        self.0.read(width)
    }
}

pub(super) struct Describe(pub(super) Vec<Field, MAX_FIELDS>);
impl Io for Describe {
    const DECODE: bool = true;
    fn bits(&mut self, name: &'static str, bits: u8, _: u64) -> Result<u64, BusError> {
        self.0
            .push(Field { name, bits })
            .map_err(|_| BusError::BufferTooSmall {
                capacity: MAX_FIELDS,
            })?;
        Ok(0)
    }
}

pub(super) struct Walker<'l, I> {
    pub(super) io: I,
    pub(super) layout: &'l BusLayout,
    /// The caller's sub-pixel bits.
    pub(super) sub: u8,
}

pub(super) const POINT_NAMES: [(&str, &str); 16] = [
    ("p0.x", "p0.y"),
    ("p1.x", "p1.y"),
    ("p2.x", "p2.y"),
    ("p3.x", "p3.y"),
    ("p4.x", "p4.y"),
    ("p5.x", "p5.y"),
    ("p6.x", "p6.y"),
    ("p7.x", "p7.y"),
    ("p8.x", "p8.y"),
    ("p9.x", "p9.y"),
    ("p10.x", "p10.y"),
    ("p11.x", "p11.y"),
    ("p12.x", "p12.y"),
    ("p13.x", "p13.y"),
    ("p14.x", "p14.y"),
    ("p15.x", "p15.y"),
];

impl<I: Io> Walker<'_, I> {
    pub(super) fn range(
        &self,
        field: &'static str,
        value: i64,
        min: i64,
        max: i64,
    ) -> Result<(), BusError> {
        if value < min || value > max {
            Err(BusError::OutOfRange {
                layout: self.layout.name,
                field,
                value,
                min,
                max,
            })
        } else {
            Ok(())
        }
    }

    pub(super) fn unsupported(&self, field: &'static str, value: i64) -> BusError {
        BusError::UnsupportedFeature {
            layout: self.layout.name,
            field,
            value,
        }
    }

    pub(super) fn uint(&mut self, name: &'static str, width: u8, v: u64) -> Result<u64, BusError> {
        if !I::DECODE {
            self.range(name, v as i64, 0, mask(u32::from(width)) as i64)?;
        }
        self.io.bits(name, width, v)
    }

    pub(super) fn u8f(
        &mut self,
        name: &'static str,
        width: u8,
        v: &mut u8,
    ) -> Result<(), BusError> {
        *v = self.uint(name, width, u64::from(*v))? as u8;
        Ok(())
    }

    pub(super) fn u32f(
        &mut self,
        name: &'static str,
        width: u8,
        v: &mut u32,
    ) -> Result<(), BusError> {
        *v = self.uint(name, width, u64::from(*v))? as u32;
        Ok(())
    }

    pub(super) fn i32f(&mut self, name: &'static str, v: &mut i32) -> Result<(), BusError> {
        *v = self.io.bits(name, 32, u64::from(*v as u32))? as u32 as i32;
        Ok(())
    }

    pub(super) fn flag(&mut self, name: &'static str, b: &mut bool) -> Result<(), BusError> {
        *b = self.io.bits(name, 1, u64::from(*b))? != 0;
        Ok(())
    }

    pub(super) fn code(&mut self, name: &'static str, width: u8, v: u64) -> Result<u64, BusError> {
        self.uint(name, width, v)
    }

    pub(super) fn invalid(&self, field: &'static str, value: u64) -> BusError {
        BusError::InvalidCode {
            layout: self.layout.name,
            field,
            value,
        }
    }

    /// Caller units → layout units, exactly.
    pub(super) fn to_layout(&self, field: &'static str, v: i64) -> Result<i64, BusError> {
        let (c, l) = (self.sub, self.layout.subpixel_bits);
        if c >= l {
            let d = c - l;
            if v & ((1i64 << d) - 1) != 0 {
                return Err(BusError::SubpixelPrecision {
                    layout: self.layout.name,
                    field,
                    value: v,
                    layout_bits: l,
                });
            }
            Ok(v >> d)
        } else {
            Ok(v << (l - c))
        }
    }

    /// Layout units → caller units, exactly.
    pub(super) fn to_caller(&self, field: &'static str, raw: i64) -> Result<i64, BusError> {
        let (c, l) = (self.sub, self.layout.subpixel_bits);
        if c >= l {
            Ok(raw << (c - l))
        } else {
            let d = l - c;
            if raw & ((1i64 << d) - 1) != 0 {
                return Err(BusError::SubpixelPrecision {
                    layout: self.layout.name,
                    field,
                    value: raw,
                    layout_bits: l,
                });
            }
            Ok(raw >> d)
        }
    }

    pub(super) fn coord(&mut self, name: &'static str, v: &mut i32) -> Result<(), BusError> {
        let bits = self.layout.coord_bits;
        let (min, max) = self.layout.coord_range();
        let mut raw = 0;
        if !I::DECODE {
            let l = self.to_layout(name, i64::from(*v))?;
            self.range(name, l, min, max)?;
            raw = (l as u64) & mask(u32::from(bits));
        }
        let got = self.io.bits(name, bits, raw)?;
        if I::DECODE {
            let signed = if self.layout.signed_coords && got >> (bits - 1) & 1 == 1 {
                got as i64 - (1i64 << bits)
            } else {
                got as i64
            };
            let c = self.to_caller(name, signed)?;
            *v = i32::try_from(c).map_err(|_| BusError::OutOfRange {
                layout: self.layout.name,
                field: name,
                value: c,
                min: i64::from(i32::MIN),
                max: i64::from(i32::MAX),
            })?;
        }
        Ok(())
    }

    pub(super) fn point(
        &mut self,
        names: (&'static str, &'static str),
        p: &mut Point,
    ) -> Result<(), BusError> {
        self.coord(names.0, &mut p.x)?;
        self.coord(names.1, &mut p.y)
    }

    /// An unsigned length in sub-pixel units (radius, width, tolerance).
    pub(super) fn length(&mut self, name: &'static str, v: &mut u32) -> Result<(), BusError> {
        let bits = self.layout.coord_bits;
        let mut raw = 0;
        if !I::DECODE {
            let l = self.to_layout(name, i64::from(*v))?;
            self.range(name, l, 0, mask(u32::from(bits)) as i64)?;
            raw = l as u64;
        }
        let got = self.io.bits(name, bits, raw)?;
        if I::DECODE {
            let c = self.to_caller(name, got as i64)?;
            *v = u32::try_from(c).map_err(|_| BusError::OutOfRange {
                layout: self.layout.name,
                field: name,
                value: c,
                min: 0,
                max: i64::from(u32::MAX),
            })?;
        }
        Ok(())
    }

    pub(super) fn pixel(&mut self, name: &'static str, v: &mut u16) -> Result<(), BusError> {
        let bits = self.layout.pixel_bits();
        *v = self.uint(name, bits, u64::from(*v))? as u16;
        Ok(())
    }

    pub(super) fn color(&mut self, name: &'static str, c: &mut Rgb) -> Result<(), BusError> {
        let bits = self.layout.color_bits;
        let mut raw = 0;
        if !I::DECODE {
            raw = match bits {
                8 => u64::from(rgb332_encode(*c).ok_or(BusError::ColorNotRepresentable {
                    layout: self.layout.name,
                    field: name,
                    value: rgb24(*c),
                })?),
                24 => u64::from(rgb24(*c)),
                other => return Err(BusError::BadWidth(other)),
            };
        }
        let got = self.io.bits(name, bits, raw)?;
        if I::DECODE {
            *c = match bits {
                8 => rgb332_decode(got as u8),
                _ => Rgb::new((got >> 16) as u8, (got >> 8) as u8, got as u8),
            };
        }
        Ok(())
    }

    /// A flag for an optional feature: on layouts without the feature the value must be
    /// off (and decodes as off).
    pub(super) fn feature_flag(
        &mut self,
        present: bool,
        name: &'static str,
        b: &mut bool,
    ) -> Result<(), BusError> {
        if present {
            self.flag(name, b)
        } else if !I::DECODE && *b {
            Err(self.unsupported(name, 1))
        } else {
            *b = false;
            Ok(())
        }
    }

    pub(super) fn body(&mut self, cmd: &mut RasterCmd) -> Result<(), BusError> {
        match cmd {
            RasterCmd::Clear(c) => self.color("color", c),
            RasterCmd::Line(l) => self.line(l),
            RasterCmd::Triangle(t) => self.triangle(t),
            RasterCmd::Circle(c) => self.circle(c),
            RasterCmd::Fill(f) => self.fill(f),
            RasterCmd::Polygon(p) => self.polygon(p),
            RasterCmd::Bezier(b) => self.bezier(b),
            RasterCmd::Patch(p) => self.patch(p),
        }
    }

    pub(super) fn line(&mut self, l: &mut Line) -> Result<(), BusError> {
        let style = self.layout.has(FEAT_LINE_STYLE);
        let one_px = 1u32 << self.sub;
        let mut gradient = l.color_to.is_some();
        let mut dda = l.algo == LineAlgo::Dda;
        if style {
            self.flag("gradient", &mut gradient)?;
            self.flag("aa", &mut l.aa)?;
            self.flag("algo", &mut dda)?;
            l.algo = if dda {
                LineAlgo::Dda
            } else {
                LineAlgo::Bresenham
            };
        } else if I::DECODE {
            l.aa = false;
            l.algo = LineAlgo::Bresenham;
            l.width = one_px;
        } else {
            if gradient {
                return Err(self.unsupported("color_to", 1));
            }
            if l.aa {
                return Err(self.unsupported("aa", 1));
            }
            if dda {
                return Err(self.unsupported("algo", 1));
            }
            if l.width > one_px {
                return Err(self.unsupported("width", i64::from(l.width)));
            }
        }
        self.point(("x0", "y0"), &mut l.from)?;
        self.point(("x1", "y1"), &mut l.to)?;
        if style {
            self.length("width", &mut l.width)?;
        }
        self.color("color", &mut l.color)?;
        if gradient {
            let mut c = l.color_to.unwrap_or_default();
            self.color("color_to", &mut c)?;
            l.color_to = Some(c);
        } else {
            l.color_to = None;
        }
        Ok(())
    }

    pub(super) fn triangle(&mut self, t: &mut Triangle) -> Result<(), BusError> {
        let lay = *self.layout;
        let mut gouraud = matches!(t.shade, Shade::Gouraud(_));
        let mut has_z = t.z.is_some();
        let mut has_w = t.w.is_some();
        let mut has_tex = t.tex.is_some();
        self.feature_flag(lay.has(FEAT_PER_VERTEX_COLOR), "gouraud", &mut gouraud)?;
        self.feature_flag(lay.z_bits > 0, "z", &mut has_z)?;
        self.feature_flag(lay.has(FEAT_W), "w", &mut has_w)?;
        self.feature_flag(lay.has(FEAT_TEXTURE), "tex", &mut has_tex)?;
        self.point(("x0", "y0"), &mut t.v[0])?;
        self.point(("x1", "y1"), &mut t.v[1])?;
        self.point(("x2", "y2"), &mut t.v[2])?;
        if gouraud {
            let mut cs = match t.shade {
                Shade::Gouraud(cs) => cs,
                Shade::Flat(c) => [c; 3],
            };
            self.color("color0", &mut cs[0])?;
            self.color("color1", &mut cs[1])?;
            self.color("color2", &mut cs[2])?;
            t.shade = Shade::Gouraud(cs);
        } else {
            let mut c = match t.shade {
                Shade::Flat(c) => c,
                Shade::Gouraud(cs) => cs[0],
            };
            self.color("color", &mut c)?;
            t.shade = Shade::Flat(c);
        }
        if has_z {
            let mut z = t.z.unwrap_or_default();
            self.u32f("z0", lay.z_bits, &mut z[0])?;
            self.u32f("z1", lay.z_bits, &mut z[1])?;
            self.u32f("z2", lay.z_bits, &mut z[2])?;
            t.z = Some(z);
        } else {
            t.z = None;
        }
        if has_w {
            let mut w = t.w.unwrap_or_default();
            self.u32f("w0", 32, &mut w[0])?;
            self.u32f("w1", 32, &mut w[1])?;
            self.u32f("w2", 32, &mut w[2])?;
            t.w = Some(w);
        } else {
            t.w = None;
        }
        if has_tex {
            let mut tex = t.tex.unwrap_or(TexRef {
                base: 0,
                width_log2: 0,
                height_log2: 0,
                uv: [[0; 2]; 3],
                wrap: Wrap::Repeat,
                filter: Filter::Nearest,
            });
            self.tex(&mut tex)?;
            t.tex = Some(tex);
        } else {
            t.tex = None;
        }
        Ok(())
    }

    pub(super) fn tex(&mut self, tex: &mut TexRef) -> Result<(), BusError> {
        self.u32f("tex.base", TEX_BASE_BITS, &mut tex.base)?;
        self.u8f("tex.width_log2", 4, &mut tex.width_log2)?;
        self.u8f("tex.height_log2", 4, &mut tex.height_log2)?;
        const UV: [[&str; 2]; 3] = [["u0", "v0"], ["u1", "v1"], ["u2", "v2"]];
        for (uv, names) in tex.uv.iter_mut().zip(UV) {
            self.i32f(names[0], &mut uv[0])?;
            self.i32f(names[1], &mut uv[1])?;
        }
        let mut clamp = tex.wrap == Wrap::Clamp;
        self.flag("tex.clamp", &mut clamp)?;
        tex.wrap = if clamp { Wrap::Clamp } else { Wrap::Repeat };
        let f = match tex.filter {
            Filter::Nearest => 0,
            Filter::Bilinear => 1,
            Filter::Trilinear => 2,
        };
        tex.filter = match self.code("tex.filter", 2, f)? {
            0 => Filter::Nearest,
            1 => Filter::Bilinear,
            2 => Filter::Trilinear,
            v => return Err(self.invalid("tex.filter", v)),
        };
        Ok(())
    }

    pub(super) fn circle(&mut self, c: &mut Circle) -> Result<(), BusError> {
        self.point(("cx", "cy"), &mut c.center)?;
        self.length("radius", &mut c.radius)?;
        self.flag("fill", &mut c.fill)?;
        self.color("color", &mut c.color)
    }

    pub(super) fn fill(&mut self, f: &mut SeedFill) -> Result<(), BusError> {
        self.pixel("x", &mut f.seed.x)?;
        self.pixel("y", &mut f.seed.y)?;
        let mut eight = f.connectivity == Connectivity::Eight;
        self.flag("eight_connected", &mut eight)?;
        f.connectivity = if eight {
            Connectivity::Eight
        } else {
            Connectivity::Four
        };
        self.color("color", &mut f.color)
    }

    pub(super) fn points<const N: usize>(
        &mut self,
        pts: &mut Vec<Point, N>,
        n: usize,
    ) -> Result<(), BusError> {
        if I::DECODE {
            pts.clear();
            for _ in 0..n {
                pts.push(Point::default())
                    .map_err(|_| BusError::BufferTooSmall { capacity: N })?;
            }
        }
        for (p, names) in pts.iter_mut().zip(POINT_NAMES) {
            self.point(names, p)?;
        }
        Ok(())
    }

    pub(super) fn polygon(&mut self, p: &mut Polygon) -> Result<(), BusError> {
        let max = p.points.capacity() as i64;
        let n = p.points.len() as i64;
        if !I::DECODE {
            self.range("count", n, 3, max)?;
        }
        let n = self.uint("count", 4, (n - 3).max(0) as u64)? as i64 + 3;
        if I::DECODE {
            self.range("count", n, 3, max)?;
        }
        let mut even_odd = p.rule == FillRule::EvenOdd;
        self.flag("even_odd", &mut even_odd)?;
        p.rule = if even_odd {
            FillRule::EvenOdd
        } else {
            FillRule::NonZero
        };
        self.color("color", &mut p.color)?;
        self.points(&mut p.points, n as usize)
    }

    pub(super) fn bezier(&mut self, b: &mut Bezier) -> Result<(), BusError> {
        let n = b.points.len() as i64;
        if !I::DECODE {
            self.range("points", n, 3, 4)?;
        }
        let mut cubic = n == 4;
        self.flag("cubic", &mut cubic)?;
        self.length("tolerance", &mut b.tolerance)?;
        self.color("color", &mut b.color)?;
        self.points(&mut b.points, if cubic { 4 } else { 3 })
    }

    pub(super) fn patch(&mut self, p: &mut BezierPatch) -> Result<(), BusError> {
        self.u8f("steps", 8, &mut p.steps)?;
        self.color("color", &mut p.color)?;
        for (pt, names) in p.points.iter_mut().zip(POINT_NAMES) {
            self.point(names, pt)?;
        }
        Ok(())
    }

    /// CB and opcode; returns the kind (read from the opcode when decoding).
    pub(super) fn header(&mut self, kind: Kind, clear: &mut bool) -> Result<Kind, BusError> {
        self.flag("cb", clear)?;
        if self.layout.opcode_bits == 0 {
            return Ok(kind);
        }
        let op = u64::from(kind.opcode().unwrap_or(0));
        let got = self.code("opcode", self.layout.opcode_bits, op)?;
        if I::DECODE {
            Kind::from_opcode(got)
                .filter(|k| self.layout.supports(*k))
                .ok_or(self.invalid("opcode", got))
        } else {
            Ok(kind)
        }
    }
}
