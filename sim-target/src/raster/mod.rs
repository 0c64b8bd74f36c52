//! The raster block's golden model (docs/requirements.md §3): bit-exact coverage, a framebuffer the
//! device reads back, and a cycle/FIFO model for board-time estimates.
//!
//! The device calls [`Raster::new`] on a [`RasterSetup`], [`Raster::draw`] per command and
//! reads [`Raster::framebuffer`] and [`Raster::stats`]. Geometry arrives already snapped
//! to sub-pixel units (`round(px · 2^subpixel_bits)`); everything after that is integer
//! arithmetic, so every traversal produces the same pixels.
//!
//! What drives a whole frame is at this level. The block's stages ([`aa`], [`circle`],
//! [`curve`], [`line`](mod@line), [`oracle`], [`tex`], [`tri`]) are public as
//! namespaces, the way callers name them: each is checked stage by stage against an
//! independent reference (the integration tests, `fpgfx stress`), and their functions
//! read right only qualified (`tri::setup`, `aa::pattern`, `circle::octant`,
//! `oracle::covers`). The framebuffer, the fill unit and the cycle model are private;
//! what callers need of them is re-exported here.

pub mod aa;
pub mod circle;
pub mod curve;
pub mod line;
pub mod oracle;
pub mod tex;
pub mod tri;

mod fb;
mod fill;
mod hw;

pub use fb::{FbWrite, Framebuffer, Z_FAR};
pub use hw::{BlockCycles, Stats, CLOCK_HZ, FIFO_DEPTH};
pub use tri::COORD_LIMIT;

use protocol::raster::{
    AaPattern, Point, RasterCmd, RasterSetup, Rgb, Shade, Traversal, Triangle, MAX_SUBPIXEL_BITS,
};
use protocol::MAX_FRAME_SIDE;
use tri::{TravCounters, TriSetup};

/// Why a command or set-up was refused. Nothing from outside may panic the model.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RasterError {
    /// Framebuffer size zero or above [`MAX_FRAME_SIDE`].
    #[error("framebuffer {width}x{height} outside 1..={max} per side")]
    Size {
        /// Width [`Raster::new`] was asked for, in pixels.
        width: u32,
        /// Height [`Raster::new`] was asked for, in pixels.
        height: u32,
        /// Largest side the model accepts ([`MAX_FRAME_SIDE`]).
        max: u32,
    },
    /// More fractional bits than the edge-function widths were sized for.
    #[error("subpixel_bits {0} above the maximum {MAX_SUBPIXEL_BITS}")]
    SubpixelBits(u8),
    /// A coordinate beyond the guard band.
    #[error("{field} = {value} outside ±{limit} sub-pixel units", limit = tri::COORD_LIMIT)]
    Coordinate {
        /// The command field that held it (`line.from`, `circle.radius`, …).
        field: &'static str,
        /// Its value in sub-pixel units.
        value: i64,
    },
    /// A w of zero cannot be divided by.
    #[error("perspective w of vertex {0} is zero")]
    ZeroW(usize),
    /// Bézier curves need 3 or 4 control points.
    #[error("Bézier curve with {0} control points (need 3 or 4)")]
    BezierArity(usize),
    /// Seed outside the framebuffer.
    #[error("seed ({x}, {y}) outside the framebuffer")]
    SeedOutside {
        /// Seed column in pixels.
        x: u16,
        /// Seed row in pixels.
        y: u16,
    },
    /// The seed fill's bounded span stack overflowed.
    #[error("seed fill needed more than {0} stacked spans")]
    FillStack(usize),
    /// A texture reference reaches past texture memory.
    #[error("texture at {base} ({w}x{h} with MIP levels) exceeds {words} texels")]
    Texture {
        /// Index of the texture's first texel in texture memory.
        base: u32,
        /// Base-level width in texels.
        w: u32,
        /// Base-level height in texels.
        h: u32,
        /// Texels of texture memory ([`TEXTURE_WORDS`]).
        words: usize,
    },
    /// Texture write past the end of texture memory or not a whole number of texels.
    #[error("texture write at {offset} of {len} bytes does not fit {words} texels")]
    TextureWrite {
        /// Texel index the write starts at.
        offset: u32,
        /// Length of the write in bytes (4 per texel).
        len: usize,
        /// Texels of texture memory ([`TEXTURE_WORDS`]).
        words: usize,
    },
    /// A triangle unit width the RTL does not build (its `TRI_LANES`).
    #[error("triangle lanes {0}: the triangle unit builds 1, 2, 4 or 8")]
    TriLanes(u32),
    /// The small triangle unit asked for with more than one lane (the RTL refuses
    /// `TRI_SMALL` with `TRI_LANES` other than 1).
    #[error("triangle lanes {0}: the small triangle unit tests one pixel per cycle")]
    TriSmallLanes(u32),
}

/// Texels of texture memory in the model.
pub const TEXTURE_WORDS: usize = 1 << 18;

/// The raster block: set up once per frame size, then fed commands; owns the framebuffer,
/// texture memory and the cycle model.
#[derive(Debug, Clone)]
pub struct Raster {
    setup: RasterSetup,
    fb: Framebuffer,
    texture: Vec<u32>,
    stats: Stats,
    hw: hw::Model,
    /// Pixel tests per cycle of the RTL's triangle unit (its `TRI_LANES`), for the
    /// bounding-box traversal's cycle count.
    tri_lanes: u32,
    /// The RTL's triangle unit is the small one (`TRI_SMALL`), whose set-up is longer.
    tri_small: bool,
    /// The memory's wait input from the next command's first unit cycle on, when the
    /// cycles are to include the RTL's stalls ([`Raster::set_mem_wait`]).
    mem_wait: Option<Vec<bool>>,
}

/// The cycles a bounding-box walk testing `lanes` pixels of a row per step spends on a
/// covered span `[a, b)` beyond one per step: the RTL's triangle unit hands the covered
/// pixels of a step to the one-pixel-wide fragment FIFO one per cycle, so a step costs
/// max(1, covered) cycles. `x0` is the box's left column, where the steps start.
/// `lanes` is a power of two ([`Raster::set_tri_lanes`]), so the divisions are shifts by
/// `shift` = log2(lanes): this runs once per span, and two integer divisions there were
/// most of a sliver's fill time.
#[inline(always)]
fn lane_extra(a: u32, b: u32, x0: u32, shift: u32) -> u64 {
    if b <= a {
        return 0;
    }
    let steps = ((b - 1 - x0) >> shift) - ((a - x0) >> shift) + 1;
    u64::from(b - a - steps)
}

/// The bounding-box walk of a triangle unit testing `lanes` pixels of a row per step, as
/// the steps [`hw::stalled_cycles`] takes: a step with no covered pixel is one step that
/// emits nothing, one with k covered pixels is k steps that each emit (the fragments
/// leave one per cycle). `spans` holds each covered row's `(y, x0, x1)`, top to bottom.
fn box_steps(
    bbox: [u32; 4],
    lanes: u32,
    spans: &[(u32, u32, u32)],
) -> impl Iterator<Item = bool> + '_ {
    let [x0, y0, x1, y1] = bbox;
    let mut next = spans.iter().peekable();
    (y0..y1).flat_map(move |y| {
        let span = match next.peek() {
            Some(&&(sy, a, b)) if sy == y => {
                next.next();
                (a, b)
            }
            _ => (0, 0),
        };
        (x0..x1).step_by(lanes as usize).flat_map(move |sx| {
            let end = (sx + lanes).min(x1);
            let covered = span.1.min(end).saturating_sub(span.0.max(sx));
            let n = covered.max(1) as usize;
            std::iter::repeat_n(covered > 0, n)
        })
    })
}

fn check_point(p: &Point, field: &'static str) -> Result<(), RasterError> {
    for v in [p.x, p.y] {
        if v.unsigned_abs() > tri::COORD_LIMIT as u32 {
            return Err(RasterError::Coordinate {
                field,
                value: v as i64,
            });
        }
    }
    Ok(())
}

impl Raster {
    /// A block with a framebuffer of `width × height` cleared to the set-up's background.
    pub fn new(width: u32, height: u32, setup: &RasterSetup) -> Result<Self, RasterError> {
        if width == 0 || height == 0 || width > MAX_FRAME_SIDE || height > MAX_FRAME_SIDE {
            return Err(RasterError::Size {
                width,
                height,
                max: MAX_FRAME_SIDE,
            });
        }
        if setup.subpixel_bits > MAX_SUBPIXEL_BITS {
            return Err(RasterError::SubpixelBits(setup.subpixel_bits));
        }
        let mut raster = Self {
            setup: *setup,
            fb: Framebuffer::new(width, height, setup.background),
            texture: vec![0; TEXTURE_WORDS],
            stats: Stats::default(),
            hw: hw::Model::default(),
            tri_lanes: 1,
            tri_small: false,
            mem_wait: None,
        };
        // The set-up is one FIFO record, then a clear of the frame at one pixel per cycle:
        // the block is busy for it (the RTL's status counts it as clear cycles), though it
        // is not a command and writes no fragment.
        let area = u64::from(width) * u64::from(height);
        raster
            .hw
            .command(&mut raster.stats, hw::Unit::Clear, 1, area, 0, 1);
        Ok(raster)
    }

    /// Models an RTL triangle unit that tests `lanes` pixels of a row per cycle (the
    /// FITkit block's `TRI_LANES`: 1, 2, 4 or 8). With the bounding-box traversal a
    /// triangle then costs 4 + Σ over its box's rows and their ⌈width / lanes⌉ steps of
    /// max(1, covered pixels): the fragments still leave one per cycle. Other traversals
    /// and the pixels are unchanged.
    pub fn set_tri_lanes(&mut self, lanes: u32) -> Result<(), RasterError> {
        if !matches!(lanes, 1 | 2 | 4 | 8) {
            return Err(RasterError::TriLanes(lanes));
        }
        if self.tri_small && lanes != 1 {
            return Err(RasterError::TriSmallLanes(lanes));
        }
        self.tri_lanes = lanes;
        Ok(())
    }

    /// Models the RTL's small triangle unit (the FITkit block's `TRI_SMALL`, built for the
    /// XC3S50's area): the one-lane unit's pixels and walk after a set-up of
    /// [`hw::TRI_SMALL_SETUP_CYCLES`] instead of [`hw::tri_setup_cycles`]`(1)`; a rejected
    /// triangle costs the same. Refused while more than one lane is modelled.
    pub fn set_tri_small(&mut self, small: bool) -> Result<(), RasterError> {
        if small && self.tri_lanes != 1 {
            return Err(RasterError::TriSmallLanes(self.tri_lanes));
        }
        self.tri_small = small;
        Ok(())
    }

    /// The set-up cycles of the modelled triangle unit with `lanes` pixel tests per step.
    fn tri_setup(&self, lanes: u32) -> u64 {
        if self.tri_small {
            hw::TRI_SMALL_SETUP_CYCLES
        } else {
            hw::tri_setup_cycles(lanes)
        }
    }

    /// Makes the next line, clear and bounding-box triangle count the cycles the RTL's
    /// unit stalls when its memory holds the wait input high: `wait[i]` is the memory's
    /// wait on the command's i-th unit cycle (the memory's behaviour is the board's, so
    /// the caller supplies it: a test records it from the simulated memory). Used once;
    /// `None` clears it.
    pub fn set_mem_wait(&mut self, wait: Option<Vec<bool>>) {
        self.mem_wait = wait;
    }

    /// The framebuffer (read-back).
    pub fn framebuffer(&self) -> &Framebuffer {
        &self.fb
    }

    /// Mutable framebuffer, for tests that turn on write tracking.
    pub fn framebuffer_mut(&mut self) -> &mut Framebuffer {
        &mut self.fb
    }

    /// Counters and cycle model.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// Changes the traversal (the benches compare them on one block).
    pub fn set_traversal(&mut self, t: Traversal) {
        self.setup.traversal = t;
    }

    /// Cycles per record the controller needs to push into the input FIFO.
    pub fn set_push_period(&mut self, cycles: u64) {
        self.hw.push_period = cycles.max(1);
    }

    /// Writes texels (little-endian 0x00RRGGBB words) into texture memory.
    pub fn write_texture(&mut self, offset: u32, data: &[u8]) -> Result<(), RasterError> {
        let words = self.texture.len();
        let err = RasterError::TextureWrite {
            offset,
            len: data.len(),
            words,
        };
        if !data.len().is_multiple_of(4) {
            return Err(err);
        }
        let start = offset as usize;
        let end = start.checked_add(data.len() / 4).ok_or(err.clone())?;
        if end > words {
            return Err(err);
        }
        for (t, b) in self.texture[start..end]
            .iter_mut()
            .zip(data.chunks_exact(4))
        {
            *t = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        }
        Ok(())
    }

    /// Executes one command.
    pub fn draw(&mut self, cmd: &RasterCmd) -> Result<(), RasterError> {
        self.execute(cmd, true)
    }

    /// Executes a drawing command whose packet has CB set: the frame is cleared to the
    /// set-up's background first (seed 000), and the two are one packet, so one command
    /// and one packet's records, as the RTL counts them; the clear's cycles go to the
    /// clear unit.
    pub fn draw_after_clear(&mut self, cmd: &RasterCmd) -> Result<(), RasterError> {
        self.execute(&RasterCmd::Clear(self.setup.background), false)?;
        self.execute(cmd, true)
    }

    /// Draws `cmd`; `counted` says whether it is a command of its own (with its records)
    /// or part of another's packet.
    fn execute(&mut self, cmd: &RasterCmd, counted: bool) -> Result<(), RasterError> {
        let bits = self.setup.subpixel_bits;
        let before = self.fb.fragments();
        let (unit, busy) = match cmd {
            RasterCmd::Clear(c) => {
                self.fb.clear(*c);
                let area = self.fb.width() as u64 * self.fb.height() as u64;
                let busy = match self.mem_wait.take() {
                    Some(w) => hw::stalled_cycles(0, (0..area).map(|_| true), &w),
                    None => area,
                };
                (hw::Unit::Clear, busy)
            }
            RasterCmd::Triangle(t) => (hw::Unit::Triangle, self.triangle(t)?),
            RasterCmd::Line(l) => {
                check_point(&l.from, "line.from")?;
                check_point(&l.to, "line.to")?;
                let pixels = line::draw(&mut self.fb, l, bits);
                let busy = match self.mem_wait.take() {
                    Some(w) => {
                        hw::stalled_cycles(hw::LINE_SETUP_CYCLES, (0..pixels).map(|_| true), &w)
                    }
                    None => hw::LINE_SETUP_CYCLES + pixels,
                };
                (hw::Unit::Line, busy)
            }
            RasterCmd::Circle(c) => {
                check_point(&c.center, "circle.center")?;
                // The filled circle keeps one half-width per row: bound the radius to four
                // viewports so that this table stays small.
                if c.radius > tri::COORD_LIMIT as u32 || (c.radius >> bits) > 4 * MAX_FRAME_SIDE {
                    return Err(RasterError::Coordinate {
                        field: "circle.radius",
                        value: c.radius as i64,
                    });
                }
                (hw::Unit::Circle, circle::draw(&mut self.fb, c, bits))
            }
            RasterCmd::Fill(f) => (hw::Unit::Fill, fill::seed_fill(&mut self.fb, f)?),
            RasterCmd::Polygon(p) => {
                for q in &p.points {
                    check_point(q, "polygon.points")?;
                }
                (hw::Unit::Fill, fill::polygon(&mut self.fb, p, bits))
            }
            RasterCmd::Bezier(b) => {
                for q in &b.points {
                    check_point(q, "bezier.points")?;
                }
                let pts = curve::flatten(&b.points, b.tolerance)?;
                let mut busy = 0;
                for (k, w) in pts.windows(2).enumerate() {
                    let l = protocol::raster::Line {
                        from: w[0],
                        to: w[1],
                        color: b.color,
                        color_to: None,
                        width: 0,
                        aa: false,
                        algo: protocol::raster::LineAlgo::Bresenham,
                    };
                    // Joints are shared: skip each segment's first pixel after the first.
                    busy += line::draw_skip_first(&mut self.fb, &l, bits, k > 0);
                }
                (hw::Unit::Line, busy)
            }
            RasterCmd::Patch(p) => {
                for q in &p.points {
                    check_point(q, "patch.points")?;
                }
                let mut busy = 0;
                for v in curve::patch_triangles(p) {
                    let t = Triangle {
                        v,
                        shade: Shade::Flat(p.color),
                        z: None,
                        w: None,
                        tex: None,
                    };
                    busy += self.triangle(&t)?;
                }
                (hw::Unit::Triangle, busy)
            }
        };
        // a wait pattern is for one command, whichever unit ran it (or none)
        self.mem_wait = None;
        let frags = self.fb.fragments() - before;
        self.stats.fragments += frags;
        let records = if counted { records(cmd, bits) } else { 0 };
        if counted {
            self.stats.commands += 1;
        }
        let lanes = if self.setup.traversal == Traversal::Simd8 && unit == hw::Unit::Triangle {
            8
        } else {
            1
        };
        self.hw
            .command(&mut self.stats, unit, records, busy, frags, lanes);
        Ok(())
    }

    /// Draws a triangle, returns busy cycles.
    fn triangle(&mut self, t: &Triangle) -> Result<u64, RasterError> {
        for (k, v) in t.v.iter().enumerate() {
            check_point(v, ["triangle.v[0]", "triangle.v[1]", "triangle.v[2]"][k])?;
        }
        if let Some(w) = &t.w {
            if let Some(k) = w.iter().position(|&w| w == 0) {
                return Err(RasterError::ZeroW(k));
            }
        }
        if let Some(tx) = &t.tex {
            tex::check(tx, self.texture.len())?;
        }
        let (w, h) = (self.fb.width(), self.fb.height());
        let bits = self.setup.subpixel_bits;
        if self.setup.aa.pattern != AaPattern::None {
            let cull = self.setup.cull;
            // Depth and texture are evaluated once per pixel at its centre (one z-buffer
            // entry per pixel), with barycentric weights clamped to the triangle, and the
            // result is blended by the sample coverage.
            let attrs = if t.z.is_some() || t.tex.is_some() {
                tri::edges_only(&t.v, bits, cull).map(|s| (Shader::new(t, &s, &self.texture), s))
            } else {
                None
            };
            let n = aa::draw_triangle(
                &mut self.fb,
                t,
                bits,
                cull,
                self.setup.aa,
                &mut |fb, x, y, c| match &attrs {
                    Some((sh, s)) => sh.aa_color(fb, s, x, y, c),
                    None => Some(c),
                },
            );
            self.stats.pixel_tests += n;
            return Ok(self.tri_setup(1) + n);
        }
        let Some(s) = tri::setup(&t.v, bits, w, h, self.setup.cull) else {
            return Ok(hw::TRI_REJECT_CYCLES);
        };
        let mut c = TravCounters::default();
        let trav = self.setup.traversal;
        let (bx0, lanes) = (s.bbox[0], self.tri_lanes);
        // Only a multi-lane bounding-box walk is costed per span.
        let lane_shift =
            (trav == Traversal::BoundingBox && lanes > 1).then(|| lanes.trailing_zeros());
        let mut extra = 0u64;
        let wait = self.mem_wait.take();
        // the covered span of each box row, when the stalls need the walk's schedule
        let mut spans: Vec<(u32, u32, u32)> = Vec::new();
        let keep = wait.is_some() && trav == Traversal::BoundingBox;
        match (t.shade, t.z, t.tex) {
            (Shade::Flat(col), None, None) => {
                let fb = &mut self.fb;
                tri::traverse_bands(&s, trav, &mut c, &mut |y, band| {
                    if lane_shift.is_some() || keep {
                        for (j, &(x0, x1)) in (y..).zip(band) {
                            if let Some(sh) = lane_shift {
                                extra += lane_extra(x0, x1, bx0, sh);
                            }
                            if keep && x0 < x1 {
                                spans.push((j, x0, x1));
                            }
                        }
                    }
                    fb.fill_spans(y, band, col)
                });
            }
            _ => {
                let sh = Shader::new(t, &s, &self.texture);
                let fb = &mut self.fb;
                tri::traverse(&s, trav, &mut c, &mut |y, x0, x1| {
                    if let Some(sh) = lane_shift {
                        extra += lane_extra(x0, x1, bx0, sh);
                    }
                    if keep {
                        spans.push((y, x0, x1));
                    }
                    for x in x0..x1 {
                        sh.fragment(fb, &s, x, y);
                    }
                });
            }
        }
        if let (true, Some(w)) = (keep, wait) {
            self.stats.pixel_tests += c.pixel_tests;
            let steps = box_steps(s.bbox, lanes, &spans);
            return Ok(hw::stalled_cycles(self.tri_setup(lanes), steps, &w));
        }
        self.stats.pixel_tests += c.pixel_tests;
        self.stats.block_tests += c.block_tests;
        if trav == Traversal::BoundingBox && lanes > 1 {
            let [x0, y0, x1, y1] = s.bbox;
            let steps = u64::from(y1 - y0) * u64::from((x1 - x0).div_ceil(lanes));
            return Ok(self.tri_setup(lanes) + steps + extra);
        }
        let lanes = if trav == Traversal::Simd8 { 8 } else { 1 };
        Ok(self.tri_setup(1)
            + c.block_tests
            + c.wide_steps
            + (c.pixel_tests + c.accepted).div_ceil(lanes))
    }
}

/// Input FIFO records a command occupies. Lines and flat triangles whose coordinates fit
/// the FITkit layout (9-bit integer coordinates, 8-bit colour) use seed 000's 2 records;
/// anything richer is costed with 16-bit coordinates, 24-bit colours, 24-bit z, 32-bit w
/// and texture words, plus a 4-bit opcode and the CB bit.
pub fn records(cmd: &RasterCmd, subpixel_bits: u8) -> u32 {
    // Whole pixels in 0..512: the FITkit's 9-bit coordinates.
    // Both coordinates at once: for non-negative x and y, x | y is non-negative, has no
    // fractional bits and is below 512 px exactly when each of them does and is.
    let fits = |p: &Point| {
        let m = (1i32 << subpixel_bits) - 1;
        let o = p.x | p.y;
        o >= 0 && o & m == 0 && (o >> subpixel_bits) < 512
    };
    let bits: u32 = match cmd {
        RasterCmd::Clear(_) => 5 + 24,
        RasterCmd::Triangle(t)
            if matches!(t.shade, Shade::Flat(_))
                && t.z.is_none()
                && t.w.is_none()
                && t.tex.is_none()
                && t.v.iter().all(fits) =>
        {
            63
        }
        RasterCmd::Line(l) => {
            if l.color_to.is_none() && !l.aa && l.width == 0 && fits(&l.from) && fits(&l.to) {
                45
            } else {
                5 + 64 + 48 + 16 + 2
            }
        }
        RasterCmd::Triangle(t) => {
            let mut b = 5 + 96 + 24;
            if matches!(t.shade, Shade::Gouraud(_)) {
                b += 48;
            }
            if t.z.is_some() {
                b += 72;
            }
            if t.w.is_some() {
                b += 96;
            }
            if t.tex.is_some() {
                b += 32 + 8 + 192 + 2;
            }
            b
        }
        RasterCmd::Circle(_) => 5 + 32 + 16 + 24 + 1,
        RasterCmd::Fill(_) => 5 + 32 + 24 + 1,
        RasterCmd::Polygon(p) => 5 + 32 * p.points.len() as u32 + 24 + 1 + 5,
        RasterCmd::Bezier(b) => 5 + 32 * b.points.len() as u32 + 24 + 16,
        RasterCmd::Patch(_) => 5 + 32 * 16 + 8 + 24,
    };
    bits.div_ceil(hw::RECORD_BITS)
}

/// Per-fragment attribute evaluation for the non-flat paths. Everything is exact
/// integer arithmetic on the raw edge values (barycentric numerators), so the result
/// of a pixel does not depend on the traversal order.
struct Shader<'a> {
    colors: [Rgb; 3],
    z: Option<[u32; 3]>,
    /// Perspective weights w_j·w_k per vertex (so that l_i/w_i ∝ l_i·w_j·w_k).
    pw: Option<[u128; 3]>,
    tex: Option<(protocol::raster::TexRef, u32)>,
    texture: &'a [u32],
}

impl<'a> Shader<'a> {
    fn new(t: &Triangle, s: &TriSetup, texture: &'a [u32]) -> Self {
        let colors = match t.shade {
            Shade::Flat(c) => [c; 3],
            Shade::Gouraud(c) => c,
        };
        let o = s.order;
        let colors = [colors[o[0]], colors[o[1]], colors[o[2]]];
        let z = t.z.map(|z| [z[o[0]], z[o[1]], z[o[2]]]);
        let pw = t.w.map(|w| {
            let w = [w[o[0]] as u128, w[o[1]] as u128, w[o[2]] as u128];
            [w[1] * w[2], w[0] * w[2], w[0] * w[1]]
        });
        let tex = t.tex.map(|mut tx| {
            tx.uv = [tx.uv[o[0]], tx.uv[o[1]], tx.uv[o[2]]];
            let lod = tex::lod(&tx, s);
            (tx, lod)
        });
        Self {
            colors,
            z,
            pw,
            tex,
            texture,
        }
    }

    #[inline]
    fn fragment(&self, fb: &mut Framebuffer, s: &TriSetup, x: u32, y: u32) {
        let l = weights(s, x, y);
        if let Some(zv) = self.depth(&l) {
            if !fb.depth_test(x, y, zv) {
                return;
            }
        }
        if let Some(c) = self.color(&l) {
            fb.put(x, y, c);
        }
    }

    /// The anti-aliased path's pixel: depth test at the pixel centre, then the texture
    /// colour (or `base`, the path's flat/Gouraud colour, when untextured). `None` when
    /// the depth test fails.
    fn aa_color(
        &self,
        fb: &mut Framebuffer,
        s: &TriSetup,
        x: u32,
        y: u32,
        base: Rgb,
    ) -> Option<Rgb> {
        let l = weights(s, x, y);
        if let Some(zv) = self.depth(&l) {
            if !fb.depth_test(x, y, zv) {
                return None;
            }
        }
        if self.tex.is_some() {
            self.color(&l)
        } else {
            Some(base)
        }
    }

    /// Interpolated depth, or `None` without z. Depth is affine in screen space (z/w is
    /// what the projection makes linear). The weights are normalised by their sum: for
    /// centres inside the triangle that sum is the area, and for the anti-aliased path's
    /// edge pixels (centre outside, weights clamped at 0) it keeps z a convex combination
    /// of the vertices' depths instead of an extrapolation.
    #[inline]
    fn depth(&self, l: &[u128; 3]) -> Option<u32> {
        let z = self.z?;
        let sum: u128 = l.iter().sum();
        let num: u128 = (0..3).map(|k| z[k] as u128 * l[k]).sum();
        if sum == 0 {
            // Unreachable for a non-degenerate triangle (the weights sum to its area).
            return Some(z[0]);
        }
        Some(((num + sum / 2) / sum) as u32)
    }

    /// Gouraud or perspective-correct colour, or the texture sample.
    #[inline]
    fn color(&self, l: &[u128; 3]) -> Option<Rgb> {
        let q = match self.pw {
            Some(pw) => [l[0] * pw[0], l[1] * pw[1], l[2] * pw[2]],
            None => *l,
        };
        // Keep 96 significant bits so that i32 texture coordinates × weights fit i128.
        let sum: u128 = q.iter().sum();
        let shift = (128 - sum.leading_zeros()).saturating_sub(96);
        let q = q.map(|v| v >> shift);
        let den: u128 = q.iter().sum();
        if den == 0 {
            return None;
        }
        Some(if let Some((tx, lod)) = &self.tex {
            let interp = |k: usize| -> i64 {
                let num: i128 = (0..3).map(|v| tx.uv[v][k] as i128 * q[v] as i128).sum();
                let d = den as i128;
                // ⌊num/d + ½⌋ without doubling num: |num| < 2^127 (i32 × the 96 kept
                // bits), so 2·num could overflow i128; for integer d, ⌊(2n + d)/2d⌋ =
                // ⌊(n + ⌊d/2⌋)/d⌋ (for odd d, 2n + d is odd and never a multiple of 2d).
                (num + d / 2).div_euclid(d) as i64
            };
            tex::sample(self.texture, tx, interp(0), interp(1), *lod)
        } else {
            let ch = |f: fn(&Rgb) -> u8| -> u8 {
                let num: u128 = (0..3).map(|k| f(&self.colors[k]) as u128 * q[k]).sum();
                ((num + den / 2) / den) as u8
            };
            Rgb::new(ch(|c| c.r), ch(|c| c.g), ch(|c| c.b))
        })
    }
}

/// Raw edge values at the centre of pixel (x, y), clamped at 0: barycentric weights
/// times the area inside the triangle.
#[inline]
fn weights(s: &TriSetup, x: u32, y: u32) -> [u128; 3] {
    s.edges.map(|e| e.raw(x as i64, y as i64).max(0) as u128)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_costs_its_covered_pixels_or_one() {
        // one lane: every pixel its own step, nothing beyond one per step
        assert_eq!(lane_extra(3, 11, 0, 0), 0);
        // eight lanes (shift 3) from column 0: [3, 8) is 5 pixels in one step, [8, 11) 3 in the next
        assert_eq!(lane_extra(3, 11, 0, 3), 4 + 2);
        // steps start at the box's left column
        assert_eq!(lane_extra(5, 13, 5, 3), 7);
        // two lanes: [5, 13) from column 4 is steps [4,6) [6,8) [8,10) [10,12) [12,14)
        assert_eq!(lane_extra(5, 13, 4, 1), 8 - 5);
        assert_eq!(lane_extra(4, 4, 0, 3), 0);
        let setup = RasterSetup {
            width: 8,
            height: 8,
            subpixel_bits: 0,
            background: Rgb::new(0, 0, 0),
            aa: Default::default(),
            cull: Default::default(),
            traversal: Traversal::BoundingBox,
        };
        let mut r = Raster::new(8, 8, &setup).expect("raster");
        assert_eq!(r.set_tri_lanes(3), Err(RasterError::TriLanes(3)));
        assert_eq!(r.set_tri_lanes(8), Ok(()));
        assert_eq!(r.set_tri_small(true), Err(RasterError::TriSmallLanes(8)));
        assert_eq!(r.set_tri_lanes(1), Ok(()));
        assert_eq!(r.set_tri_small(true), Ok(()));
        assert_eq!(r.set_tri_lanes(2), Err(RasterError::TriSmallLanes(2)));
    }
}
