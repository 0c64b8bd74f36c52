//! The raster block's vocabulary: the commands a raster job is made of ([`RasterCmd`] and
//! its primitives), the frame-wide set-up ([`RasterSetup`]) and the values they carry
//! (colours, points, anti-aliasing, culling, traversal).
//!
//! These are words, not messages: [`crate::frame`] carries them from the host to the
//! controller, [`crate::bus`] packs them into FPGA records, and the model and the files
//! users write speak them too. Geometry is already snapped to the sub-pixel grid
//! (`x · 2^subpixel_bits`, rounded half up), so everything after the host is exact
//! integer arithmetic.

use heapless::Vec;
use postcard_schema::Schema;
use serde::{Deserialize, Serialize};

/// Vertices of one scanline-filled polygon. Larger polygons are split by the host.
pub const MAX_POLYGON: usize = 16;
/// Largest [`RasterSetup::subpixel_bits`] a target accepts: the raster block's
/// edge-function bound is proven for this many fractional bits at [`crate::MAX_FRAME_SIDE`].
/// Not [`crate::bus::MAX_CALLER_SUBPIXEL_BITS`], which only bounds the bus packer's
/// rescaling.
pub const MAX_SUBPIXEL_BITS: u8 = 8;

/// An 8-bit-per-channel colour. The FITkit bus layout narrows it to RGB332 or a palette
/// index; everything before the bus keeps full precision.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct Rgb {
    /// Red, 0 (none) … 255 (full).
    pub r: u8,
    /// Green, 0 … 255.
    pub g: u8,
    /// Blue, 0 … 255.
    pub b: u8,
}

impl Rgb {
    /// Builds a colour from its three channels.
    pub const fn new(r: u8, g: u8, b: u8) -> Self {
        Self { r, g, b }
    }
}

/// A vertex position in sub-pixel units: pixel coordinate × 2^`subpixel_bits` (set by
/// [`RasterSetup`]). Signed so that geometry partly outside the viewport can be clipped by
/// the device rather than distorted by the host.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct Point {
    /// Horizontal position, growing to the right.
    pub x: i32,
    /// Vertical position, growing downwards (docs/requirements.md §0).
    pub y: i32,
}

/// A whole pixel, for commands that address pixels rather than geometry (seed fill,
/// read-back rectangles).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct Pixel {
    /// Column, 0 at the left edge.
    pub x: u16,
    /// Row, 0 at the top edge (y grows downwards).
    pub y: u16,
}

/// Sample pattern for supersampling anti-aliasing (seed 001).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub enum AaPattern {
    /// One sample at the pixel centre.
    #[default]
    None,
    /// An n × n regular grid.
    Regular,
    /// One random sample per stratum of an n × n grid (deterministic seed).
    Jitter,
    /// A regular grid rotated so that no two samples share a row or column (RGSS).
    Rotated,
    /// Poisson-disc samples (precomputed, deterministic).
    Poisson,
    /// Analytic coverage mask on triangle edges.
    Coverage,
}

impl AaPattern {
    /// Every pattern, in declaration order: the numbering of the C library's
    /// `FPGFX_AA_*` codes and of raster test vectors' set-up words.
    pub const ALL: [AaPattern; 6] = [
        AaPattern::None,
        AaPattern::Regular,
        AaPattern::Jitter,
        AaPattern::Rotated,
        AaPattern::Poisson,
        AaPattern::Coverage,
    ];
}

crate::named! {
    AaPattern, what = "pattern", ignore_case = false, values = AaPattern::ALL,
    {
        None => ["none"],
        Regular => ["regular"],
        Jitter => ["jitter"],
        Rotated => ["rotated"],
        Poisson => ["poisson"],
        Coverage => ["coverage"],
    }
}

/// Anti-aliasing settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct Aa {
    /// Where in the pixel the samples lie.
    pub pattern: AaPattern,
    /// Samples per pixel (ignored for [`AaPattern::None`]).
    pub samples: u8,
}

/// Which triangles to discard by winding, after snapping.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub enum Cull {
    /// Draw both windings.
    #[default]
    None,
    /// Discard triangles that are clockwise on screen (y down).
    Clockwise,
    /// Discard triangles that are counter-clockwise on screen (y down).
    CounterClockwise,
}

impl Cull {
    /// Every mode, in declaration order: the numbering of the C library's `FPGFX_CULL_*`
    /// codes and of raster test vectors' set-up words.
    pub const ALL: [Cull; 3] = [Cull::None, Cull::Clockwise, Cull::CounterClockwise];
}

crate::named! {
    Cull, what = "culling", ignore_case = false, values = Cull::ALL,
    {
        None => ["none"],
        Clockwise => ["cw", "clockwise"],
        CounterClockwise => ["ccw", "counter-clockwise"],
    }
}

/// How the triangle block walks the pixels of a triangle. All strategies must give
/// identical coverage; they differ in cycles and in how much of the bounding box they
/// touch, which is what a hardware designer is choosing between.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub enum Traversal {
    /// Every pixel of the bounding box.
    BoundingBox,
    /// Span per scanline between the edges.
    Scanline,
    /// Seed 004's zigzag block scan (with the corrected trivial reject).
    Zigzag,
    /// Hierarchical tiles with trivial accept and reject.
    #[default]
    Tiles,
    /// Seed 000's eight pixels per step.
    Simd8,
}

impl Traversal {
    /// Every strategy, in the order raster files and `--traversal` list them.
    pub const ALL: [Traversal; 5] = [
        Traversal::BoundingBox,
        Traversal::Scanline,
        Traversal::Zigzag,
        Traversal::Tiles,
        Traversal::Simd8,
    ];
}

crate::named! {
    Traversal, what = "traversal", ignore_case = false, values = Traversal::ALL,
    {
        BoundingBox => ["bbox"],
        Scanline => ["scanline"],
        Zigzag => ["zigzag"],
        Tiles => ["tiles"],
        Simd8 => ["simd8"],
    }
}

/// Frame-wide raster state. Sent before the first raster command of a frame; a new one
/// resets the framebuffer size and clears it to `background`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct RasterSetup {
    /// Framebuffer width in pixels.
    pub width: u16,
    /// Framebuffer height in pixels.
    pub height: u16,
    /// Fractional bits of every [`Point`] in the following commands.
    pub subpixel_bits: u8,
    /// Colour the framebuffer is cleared to when this set-up arrives.
    pub background: Rgb,
    /// Anti-aliasing for every primitive of the frame.
    pub aa: Aa,
    /// Which triangles to discard by their winding on screen.
    pub cull: Cull,
    /// Triangle traversal strategy.
    pub traversal: Traversal,
}

/// How a triangle is coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum Shade {
    /// One colour for the whole primitive.
    Flat(Rgb),
    /// One colour per vertex, interpolated barycentrically (Gouraud).
    Gouraud([Rgb; 3]),
}

/// Texture coordinates and sampler of a textured triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct TexRef {
    /// First texel of the texture in texture memory.
    pub base: u32,
    /// log2 of the texture width (textures are powers of two, as MIP maps need).
    pub width_log2: u8,
    /// log2 of the texture height.
    pub height_log2: u8,
    /// Per-vertex (u, v) in Q16.16 texture units (1.0 = the whole texture).
    pub uv: [[i32; 2]; 3],
    /// Repeat or clamp outside [0, 1).
    pub wrap: Wrap,
    /// Nearest, bilinear or trilinear.
    pub filter: Filter,
}

/// Texture addressing outside [0, 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum Wrap {
    /// Tile the texture.
    Repeat,
    /// Use the edge texel.
    Clamp,
}

/// How the raster block samples a texture between texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum Filter {
    /// Nearest texel.
    Nearest,
    /// Bilinear between the four nearest texels (centres at +0.5).
    Bilinear,
    /// Bilinear in the two nearest MIP levels, blended (MIP levels follow the base
    /// texture in memory, each a quarter of the previous).
    Trilinear,
}

/// A triangle with optional depth, perspective and texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct Triangle {
    /// Vertices in sub-pixel units.
    pub v: [Point; 3],
    /// Flat or per-vertex (Gouraud) colour.
    pub shade: Shade,
    /// Per-vertex depth as unsigned 24-bit normalised values (0 = near, 2^24 − 1 = far);
    /// when present the z test "less" applies against a z-buffer cleared to far.
    pub z: Option<[u32; 3]>,
    /// Per-vertex clip-space w in Q16.16 for perspective-correct interpolation; absent
    /// means affine (screen-space linear) interpolation.
    pub w: Option<[u32; 3]>,
    /// Texture coordinates and sampler; `None` draws the shade alone.
    pub tex: Option<TexRef>,
}

/// How a line is rasterized.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub enum LineAlgo {
    /// Bresenham with p₁ = 2Δy − Δx (seed 000).
    #[default]
    Bresenham,
    /// Digital differential analyser.
    Dda,
}

impl LineAlgo {
    /// Every algorithm, in the order raster files list them.
    pub const ALL: [LineAlgo; 2] = [LineAlgo::Bresenham, LineAlgo::Dda];
}

crate::named! {
    LineAlgo, what = "line algorithm", ignore_case = false, values = LineAlgo::ALL,
    { Bresenham => ["bresenham"], Dda => ["dda"] }
}

/// A line segment, end points inclusive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct Line {
    /// Start in sub-pixel units.
    pub from: Point,
    /// End in sub-pixel units.
    pub to: Point,
    /// Colour at `from`.
    pub color: Rgb,
    /// Colour at `to` when interpolated along the line; `None` = flat.
    pub color_to: Option<Rgb>,
    /// Width in sub-pixel units; one pixel or less draws a thin line.
    pub width: u32,
    /// Anti-aliased (coverage) rather than aliased.
    pub aa: bool,
    /// How a thin, aliased line is stepped; wide and anti-aliased lines ignore it.
    pub algo: LineAlgo,
}

/// A circle by the midpoint algorithm (seed 000).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct Circle {
    /// Centre in sub-pixel units.
    pub center: Point,
    /// Radius in sub-pixel units.
    pub radius: u32,
    /// Outline or fill colour.
    pub color: Rgb,
    /// Filled by spans rather than outlined.
    pub fill: bool,
}

/// Seed-fill connectivity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum Connectivity {
    /// Up, down, left, right.
    Four,
    /// The four plus the diagonals.
    Eight,
}

/// Fill the region of equal colour connected to a seed pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct SeedFill {
    /// Where the fill starts; its colour is the one the region is made of.
    pub seed: Pixel,
    /// Colour the region is painted.
    pub color: Rgb,
    /// Which neighbours count as connected.
    pub connectivity: Connectivity,
}

/// Which points a self-intersecting polygon covers; the two rules agree on simple
/// polygons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum FillRule {
    /// Inside where a ray crosses an odd number of edges.
    EvenOdd,
    /// Inside where the winding number is not zero.
    NonZero,
}

impl FillRule {
    /// Both rules, in the order raster files list them.
    pub const ALL: [FillRule; 2] = [FillRule::EvenOdd, FillRule::NonZero];
}

crate::named! {
    FillRule, what = "fill rule", ignore_case = false, values = FillRule::ALL,
    { EvenOdd => ["even-odd"], NonZero => ["non-zero"] }
}

/// A closed polygon filled by scanlines.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct Polygon {
    /// Vertices in sub-pixel units; the last connects back to the first.
    pub points: Vec<Point, MAX_POLYGON>,
    /// How self-intersections are filled.
    pub rule: FillRule,
    /// Fill colour.
    pub color: Rgb,
}

/// A quadratic (3 points) or cubic (4 points) Bézier curve.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct Bezier {
    /// Control points in sub-pixel units.
    pub points: Vec<Point, 4>,
    /// Colour of the lines the curve is flattened into.
    pub color: Rgb,
    /// Largest allowed distance between the curve and its polyline, in sub-pixel units.
    pub tolerance: u32,
}

/// A bicubic Bézier patch, tessellated by the device into `steps × steps × 2` triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct BezierPatch {
    /// The 4 × 4 control net, row by row, in sub-pixel units.
    pub points: [Point; 16],
    /// Subdivisions per side.
    pub steps: u8,
    /// Flat colour of every triangle of the tessellation.
    pub color: Rgb,
}

/// One raster command. The controller packs each into the FPGA's bus words
/// ([`crate::bus`]) in order.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum RasterCmd {
    /// Clear the framebuffer (and the z-buffer) to a colour.
    Clear(Rgb),
    /// A line segment, thin or wide.
    Line(Line),
    /// A filled triangle: flat, Gouraud or textured, optionally depth-tested.
    Triangle(Triangle),
    /// A circle outline or disc by the midpoint algorithm.
    Circle(Circle),
    /// A flood fill from a seed pixel; it reads the framebuffer, so it sees what the
    /// commands before it drew.
    Fill(SeedFill),
    /// A scanline-filled polygon.
    Polygon(Polygon),
    /// A curve the device flattens into lines within its tolerance.
    Bezier(Bezier),
    /// A bicubic surface patch the device tessellates into triangles.
    Patch(BezierPatch),
}
