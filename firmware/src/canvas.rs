//! embedded-graphics on the FPGA: a [`DrawTarget`] whose primitives are FPGA commands.
//!
//! embedded-graphics draws everything as pixels through `draw_iter`, which on a display
//! behind a bus means one bus transaction per pixel. Its [`DrawTarget`] lets a target
//! override `fill_solid` and `clear`; here they are one command each (two triangles for a
//! rectangle on a layout without a rectangle fill). Lines, triangles, circles and filled
//! rectangles go further: [`Canvas::draw`] takes them styled, as embedded-graphics'
//! [`Styled`] primitives, and sends one command for each instead of its pixels. A style
//! the FPGA cannot draw (a wide or dashed stroke, a stroked triangle) falls back to
//! embedded-graphics' own drawing, pixel by pixel, so every drawing still appears.
//!
//! Coordinates: an embedded-graphics point names a pixel; the raster block samples pixel
//! centres at (x + ½, y + ½) (docs/requirements.md §0). A triangle's vertices are sent at
//! pixel centres when the layout has a sub-pixel bit, so both libraries mean the same
//! triangle; edge pixels still differ where embedded-graphics includes both sides of an
//! edge and the block's top-left rule includes one (docs/embedded-graphics.md).

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{
    Circle as EgCircle, Line as EgLine, PrimitiveStyle, Rectangle, Styled, Triangle as EgTriangle,
};
use protocol::bus::{BusError, BusLayout, PackOptions};
use protocol::raster::{
    Circle, Cull, Line, LineAlgo, Point as FpgaPoint, RasterCmd, RasterSetup, Rgb, Shade,
    Traversal, Triangle,
};

use crate::fpga::{push_command, FpgaBus, PushError};

/// Why the canvas could not draw.
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CanvasError<E: core::fmt::Debug> {
    /// The bus failed.
    #[error("FPGA bus: {0:?}")]
    Bus(E),
    /// The layout cannot carry a command the canvas needed (e.g. a circle on the FITkit,
    /// whose block has no circle unit: draw it with [`Canvas::draw_pixels`]).
    #[error("the FPGA's bus layout cannot carry it: {0}")]
    Layout(BusError),
    /// The frame set-up is one the bus layout cannot address.
    #[error("a {width} x {height} frame is larger than the layout addresses")]
    FrameTooLarge {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
}

impl<E: core::fmt::Debug> From<PushError<E>> for CanvasError<E> {
    fn from(e: PushError<E>) -> Self {
        match e {
            PushError::Bus(e) => CanvasError::Bus(e),
            PushError::Pack(e) => CanvasError::Layout(e),
        }
    }
}

/// What crossed the bus, so a caller can compare accelerated and pixel-by-pixel drawing.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct CanvasCounters {
    /// Commands pushed.
    pub commands: u64,
    /// FIFO records pushed.
    pub records: u64,
    /// Bits those records occupy on the bus (records × the layout's record width).
    pub bits: u64,
}

/// The FPGA's framebuffer as an embedded-graphics target.
pub struct Canvas<B: FpgaBus> {
    bus: B,
    layout: &'static BusLayout,
    size: Size,
    /// Sub-pixel bits the commands are written in: 1 where the layout has one (vertices
    /// at pixel centres), else 0.
    subpixel_bits: u8,
    counters: CanvasCounters,
}

fn rgb(c: Rgb888) -> Rgb {
    Rgb::new(c.r(), c.g(), c.b())
}

impl<B: FpgaBus> Canvas<B>
where
    B::Error: core::fmt::Debug,
{
    /// Sets up a `width` × `height` frame cleared to `background` and draws on it.
    pub fn new(
        mut bus: B,
        layout: &'static BusLayout,
        width: u16,
        height: u16,
        background: Rgb888,
    ) -> Result<Self, CanvasError<B::Error>> {
        let limit = 1u32
            << layout
                .coord_bits
                .saturating_sub(layout.subpixel_bits)
                .min(31);
        if u32::from(width) > limit || u32::from(height) > limit {
            return Err(CanvasError::FrameTooLarge {
                width: width.into(),
                height: height.into(),
            });
        }
        let subpixel_bits = u8::from(layout.subpixel_bits > 0);
        let setup = RasterSetup {
            width,
            height,
            subpixel_bits,
            background: rgb(background),
            aa: Default::default(),
            cull: Cull::None,
            traversal: Traversal::default(),
        };
        bus.raster_setup(&setup).map_err(CanvasError::Bus)?;
        Ok(Self {
            bus,
            layout,
            size: Size::new(width.into(), height.into()),
            subpixel_bits,
            counters: CanvasCounters::default(),
        })
    }

    /// The bus, e.g. to read the framebuffer back.
    pub fn bus(&mut self) -> &mut B {
        &mut self.bus
    }

    /// What has crossed the bus so far.
    pub fn counters(&self) -> CanvasCounters {
        self.counters
    }

    /// Sends one raster command.
    pub fn command(&mut self, cmd: &RasterCmd) -> Result<(), CanvasError<B::Error>> {
        let opts = PackOptions {
            subpixel_bits: self.subpixel_bits,
            clear: false,
        };
        let (records, _) = push_command(&mut self.bus, self.layout, cmd, opts)?;
        self.counters.commands += 1;
        self.counters.records += records as u64;
        self.counters.bits += records as u64 * u64::from(self.layout.record_bits);
        Ok(())
    }

    /// Waits until every command has been drawn (bounded by the bus's own waits).
    pub fn finish(&mut self) -> Result<(), CanvasError<B::Error>> {
        while !self.bus.idle().map_err(CanvasError::Bus)? {
            self.bus.wait().map_err(CanvasError::Bus)?;
        }
        Ok(())
    }

    /// A pixel `p` (its top-left corner), or its centre, in command units.
    fn at(&self, p: Point, centre: bool) -> FpgaPoint {
        let s = self.subpixel_bits;
        let half = i32::from(centre && s > 0);
        FpgaPoint {
            x: (p.x << s) + half,
            y: (p.y << s) + half,
        }
    }

    /// Draws `item` with one FPGA command where the FPGA can draw it in its style, else
    /// with embedded-graphics, pixel by pixel.
    pub fn draw<T: Accelerated>(&mut self, item: &T) -> Result<(), CanvasError<B::Error>> {
        match item.command(self) {
            Some(cmds) => cmds.iter().try_for_each(|c| self.command(c)),
            None => item.draw_pixels(self),
        }
    }

    /// Draws `item` pixel by pixel as embedded-graphics does on a target with no
    /// acceleration (even `fill_solid` becomes pixels): the comparison point for
    /// [`Canvas::draw`], and the way to draw what the layout cannot carry.
    pub fn draw_pixels<T: Drawable<Color = Rgb888> + ?Sized>(
        &mut self,
        item: &T,
    ) -> Result<(), CanvasError<B::Error>> {
        item.draw(&mut PixelsOnly(self)).map(|_| ())
    }

    /// The rectangle as two triangles with corners on pixel corners: the top-left rule
    /// gives exactly its pixels, the shared diagonal's once.
    fn rectangle(&self, r: &Rectangle, color: Rgb888) -> Option<[RasterCmd; 2]> {
        let r = r.intersection(&self.bounding_box());
        let br = r.bottom_right()? + Point::new(1, 1);
        let (a, b) = (self.at(r.top_left, false), self.at(br, false));
        let (tr, bl) = (FpgaPoint { x: b.x, y: a.y }, FpgaPoint { x: a.x, y: b.y });
        let tri = |v| {
            RasterCmd::Triangle(Triangle {
                v,
                shade: Shade::Flat(rgb(color)),
                z: None,
                w: None,
                tex: None,
            })
        };
        Some([tri([a, tr, b]), tri([a, b, bl])])
    }
}

impl<B: FpgaBus> OriginDimensions for Canvas<B> {
    fn size(&self) -> Size {
        self.size
    }
}

impl<B: FpgaBus> DrawTarget for Canvas<B>
where
    B::Error: core::fmt::Debug,
{
    type Color = Rgb888;
    type Error = CanvasError<B::Error>;

    /// One one-pixel line per pixel: what any pixel-addressed display costs, kept so that
    /// every embedded-graphics drawable works on the canvas.
    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Self::Color>>,
    {
        let area = self.bounding_box();
        for Pixel(p, c) in pixels {
            if !area.contains(p) {
                continue;
            }
            let at = self.at(p, true);
            self.command(&RasterCmd::Line(Line {
                from: at,
                to: at,
                color: rgb(c),
                color_to: None,
                width: 0,
                aa: false,
                algo: LineAlgo::Bresenham,
            }))?;
        }
        Ok(())
    }

    fn fill_solid(&mut self, area: &Rectangle, color: Self::Color) -> Result<(), Self::Error> {
        if area.intersection(&self.bounding_box()) == self.bounding_box() {
            return self.clear(color);
        }
        match self.rectangle(area, color) {
            Some(cmds) => cmds.iter().try_for_each(|c| self.command(c)),
            None => Ok(()),
        }
    }

    fn clear(&mut self, color: Self::Color) -> Result<(), Self::Error> {
        self.command(&RasterCmd::Clear(rgb(color)))
    }
}

/// The canvas with only `draw_iter`: embedded-graphics' defaults turn every fill into
/// pixels.
struct PixelsOnly<'a, B: FpgaBus>(&'a mut Canvas<B>);

impl<B: FpgaBus> OriginDimensions for PixelsOnly<'_, B> {
    fn size(&self) -> Size {
        self.0.size
    }
}

impl<B: FpgaBus> DrawTarget for PixelsOnly<'_, B>
where
    B::Error: core::fmt::Debug,
{
    type Color = Rgb888;
    type Error = CanvasError<B::Error>;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Self::Color>>,
    {
        self.0.draw_iter(pixels)
    }
}

/// A styled embedded-graphics primitive the FPGA can draw as commands.
pub trait Accelerated: Drawable<Color = Rgb888> {
    /// The commands that draw it (at most two), or `None` when the style needs pixels.
    fn command<B: FpgaBus>(&self, canvas: &Canvas<B>) -> Option<heapless::Vec<RasterCmd, 2>>
    where
        B::Error: core::fmt::Debug;

    /// Draws it pixel by pixel through embedded-graphics.
    fn draw_pixels<B: FpgaBus>(&self, canvas: &mut Canvas<B>) -> Result<(), CanvasError<B::Error>>
    where
        B::Error: core::fmt::Debug,
    {
        canvas.draw_pixels(self)
    }
}

/// A plain stroke the block's one-pixel line draws: width 1, no fill.
fn thin_stroke(style: &PrimitiveStyle<Rgb888>) -> Option<Rgb888> {
    match (style.stroke_color, style.stroke_width, style.fill_color) {
        (Some(c), 1, None) => Some(c),
        _ => None,
    }
}

/// A fill without a stroke: a stroke would add pixels outside the fill's edges.
fn plain_fill(style: &PrimitiveStyle<Rgb888>) -> Option<Rgb888> {
    match (style.fill_color, style.stroke_width) {
        (Some(c), 0) => Some(c),
        _ => None,
    }
}

fn one(cmd: RasterCmd) -> heapless::Vec<RasterCmd, 2> {
    let mut v = heapless::Vec::new();
    // Capacity 2 holds one.
    let _ = v.push(cmd);
    v
}

impl Accelerated for Styled<EgLine, PrimitiveStyle<Rgb888>> {
    fn command<B: FpgaBus>(&self, canvas: &Canvas<B>) -> Option<heapless::Vec<RasterCmd, 2>>
    where
        B::Error: core::fmt::Debug,
    {
        let c = thin_stroke(&self.style)?;
        Some(one(RasterCmd::Line(Line {
            from: canvas.at(self.primitive.start, true),
            to: canvas.at(self.primitive.end, true),
            color: rgb(c),
            color_to: None,
            width: 0,
            aa: false,
            algo: LineAlgo::Bresenham,
        })))
    }
}

impl Accelerated for Styled<EgTriangle, PrimitiveStyle<Rgb888>> {
    fn command<B: FpgaBus>(&self, canvas: &Canvas<B>) -> Option<heapless::Vec<RasterCmd, 2>>
    where
        B::Error: core::fmt::Debug,
    {
        let c = plain_fill(&self.style)?;
        let [a, b, d] = self.primitive.vertices;
        Some(one(RasterCmd::Triangle(Triangle {
            v: [canvas.at(a, true), canvas.at(b, true), canvas.at(d, true)],
            shade: Shade::Flat(rgb(c)),
            z: None,
            w: None,
            tex: None,
        })))
    }
}

impl Accelerated for Styled<EgCircle, PrimitiveStyle<Rgb888>> {
    /// The block's midpoint circle has a whole-pixel centre, so only odd diameters (a
    /// centre pixel) map; an even one is drawn pixel by pixel.
    fn command<B: FpgaBus>(&self, canvas: &Canvas<B>) -> Option<heapless::Vec<RasterCmd, 2>>
    where
        B::Error: core::fmt::Debug,
    {
        let d = self.primitive.diameter;
        if d.is_multiple_of(2) {
            return None;
        }
        let (color, fill) = match (plain_fill(&self.style), thin_stroke(&self.style)) {
            (Some(c), _) => (c, true),
            (None, Some(c)) => (c, false),
            (None, None) => return None,
        };
        let r = (d - 1) / 2;
        let centre = self.primitive.top_left + Point::new(r as i32, r as i32);
        Some(one(RasterCmd::Circle(Circle {
            center: canvas.at(centre, false),
            radius: r << canvas.subpixel_bits,
            color: rgb(color),
            fill,
        })))
    }
}

impl Accelerated for Styled<Rectangle, PrimitiveStyle<Rgb888>> {
    fn command<B: FpgaBus>(&self, canvas: &Canvas<B>) -> Option<heapless::Vec<RasterCmd, 2>>
    where
        B::Error: core::fmt::Debug,
    {
        let c = plain_fill(&self.style)?;
        let cmds = canvas.rectangle(&self.primitive, c)?;
        Some(heapless::Vec::from_iter(cmds))
    }
}
