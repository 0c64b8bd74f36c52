//! Triangle setup (edge functions, fill rule, orientation) and the five traversals.
//!
//! # Integer widths (docs/requirements.md §0)
//! Vertices arrive in sub-pixel units with at most [`MAX_SUBPIXEL_BITS`] fractional bits
//! and `|x|, |y| ≤` [`COORD_LIMIT`] = 2^23 (a ±32 768-pixel guard band at 8 bits). The
//! block works in *doubled* units so that pixel centres `(2i + 1)·2^b` are integers for
//! every `b`, hence `|X| ≤ 2^24`, edge deltas `|A|, |B| ≤ 2^25`, the per-pixel steps
//! `a = 2^(b+1)·A` are below 2^34, the constant term below 2^51 and any value of the edge
//! function at a pixel of a viewport up to [`MAX_FRAME_SIDE`] = 4096 below 2^52. All of it fits
//! `i64` with 11 bits to spare, so the hot loops never widen; the exact reference in the
//! tests uses `i128` and `tests/raster_tri.rs` checks vertices at the limits.
//!
//! [`MAX_FRAME_SIDE`]: protocol::frame::MAX_FRAME_SIDE
//! [`MAX_SUBPIXEL_BITS`]: protocol::frame::MAX_SUBPIXEL_BITS

use protocol::frame::{Cull, Point, Traversal};

/// Largest magnitude of a vertex coordinate in sub-pixel units.
pub const COORD_LIMIT: i32 = 1 << 23;
/// Zigzag block side in pixels.
pub const ZIGZAG_BLOCK: u32 = 8;
/// Hierarchical tile sides, coarse to fine.
pub(crate) const TILE_SIZES: [u32; 2] = [32, 8];

/// One edge function in pixel-index form, fill-rule bias folded in: the pixel `(i, j)`
/// is inside this edge iff `a·i + b·j + c ≥ 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// Step per pixel in x (+A in the terms of docs/requirements.md §3, scaled to a pixel).
    pub a: i64,
    /// Step per pixel in y.
    pub b: i64,
    /// Value at pixel (0, 0), minus the bias.
    pub c: i64,
    /// 0 for top-left edges, 1 otherwise: what turns `E > 0` into `E' ≥ 0`.
    pub bias: i64,
}

impl Edge {
    /// Biased value at a pixel.
    #[inline]
    pub fn at(&self, i: i64, j: i64) -> i64 {
        self.a * i + self.b * j + self.c
    }
    /// Unbiased edge function at a pixel centre (the barycentric weight numerator).
    #[inline]
    pub fn raw(&self, i: i64, j: i64) -> i64 {
        self.at(i, j) + self.bias
    }
}

/// Everything the traversal and the shader need, computed once per triangle.
#[derive(Debug, Clone, Copy)]
pub struct TriSetup {
    /// `edges[k]` is the edge opposite normalised vertex `k`, so its raw value is that
    /// vertex's barycentric weight times `area`.
    pub edges: [Edge; 3],
    /// Doubled-unit edge function of the third vertex: twice the area in (2·sub-pixel)².
    pub area: i64,
    /// Original vertex index of each normalised vertex (orientation swaps 1 and 2).
    pub order: [usize; 3],
    /// Pixel bounding box clipped to the viewport: x0, y0, x1, y1 (exclusive).
    pub bbox: [u32; 4],
}

/// Edge functions were built from clockwise input (before normalisation).
pub(crate) fn is_clockwise(v: &[Point; 3]) -> Option<bool> {
    let (x0, y0) = (v[0].x as i64, v[0].y as i64);
    let area =
        (v[2].x as i64 - x0) * (v[1].y as i64 - y0) - (v[2].y as i64 - y0) * (v[1].x as i64 - x0);
    match area {
        0 => None,
        a => Some(a < 0),
    }
}

/// Triangle setup. `None` when the triangle is degenerate, culled or misses the viewport.
pub fn setup(v: &[Point; 3], bits: u8, width: u32, height: u32, cull: Cull) -> Option<TriSetup> {
    let s = edges_only(v, bits, cull)?;
    let h = 1i64 << bits;
    let (mut minx, mut maxx, mut miny, mut maxy) = (i64::MAX, i64::MIN, i64::MAX, i64::MIN);
    for q in v {
        let (x, y) = (2 * q.x as i64, 2 * q.y as i64);
        minx = minx.min(x);
        maxx = maxx.max(x);
        miny = miny.min(y);
        maxy = maxy.max(y);
    }
    // Divisions by the power of two 2h are arithmetic shifts (floor for negatives too).
    let sh = bits as u32 + 1;
    let lo = |m: i64| (-((h - m) >> sh)).max(0);
    let hi = |m: i64, lim: u32| (((m - h) >> sh) + 1).min(lim as i64);
    let bbox = [lo(minx), lo(miny), hi(maxx, width), hi(maxy, height)];
    if bbox[0] >= bbox[2] || bbox[1] >= bbox[3] {
        return None;
    }
    Some(TriSetup {
        bbox: bbox.map(|x| x as u32),
        ..s
    })
}

/// Edge functions, area and vertex order without the viewport bounding box (left
/// empty): what the anti-aliased path needs to interpolate depth and texture
/// coordinates at pixels whose centre may lie outside the triangle. `None` when the
/// triangle is degenerate or culled.
#[inline]
pub(crate) fn edges_only(v: &[Point; 3], bits: u8, cull: Cull) -> Option<TriSetup> {
    let cw = is_clockwise(v)?;
    match (cull, cw) {
        (Cull::Clockwise, true) | (Cull::CounterClockwise, false) => return None,
        _ => {}
    }
    // Normalise: inside positive for all three edges (seed 000 uses the third vertex).
    let order = if cw { [0, 2, 1] } else { [0, 1, 2] };
    let p: [(i64, i64); 3] =
        core::array::from_fn(|k| (2 * v[order[k]].x as i64, 2 * v[order[k]].y as i64));
    let h = 1i64 << bits;
    let edge = |from: usize, to: usize| {
        let (xp, yp) = p[from];
        let (xq, yq) = p[to];
        let a = yq - yp;
        let b = -(xq - xp);
        let top_left = a > 0 || (a == 0 && b > 0);
        let bias = if top_left { 0 } else { 1 };
        Edge {
            a: 2 * h * a,
            b: 2 * h * b,
            c: a * (h - xp) + b * (h - yp) - bias,
            bias,
        }
    };
    let edges = [edge(1, 2), edge(2, 0), edge(0, 1)];
    let area = {
        let ((x0, y0), (x1, y1), (x2, y2)) = (p[0], p[1], p[2]);
        (x2 - x0) * (y1 - y0) - (y2 - y0) * (x1 - x0)
    };
    Some(TriSetup {
        edges,
        area,
        order,
        bbox: [0; 4],
    })
}

/// Work counters of one traversal, for the cycle model and the benches' analysis.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TravCounters {
    /// Single-pixel inside tests.
    pub pixel_tests: u64,
    /// Block or tile classifications (4 corners × 3 edges each).
    pub block_tests: u64,
    /// Pixels emitted without a test (trivially accepted blocks, exact spans).
    pub accepted: u64,
    /// Steps of 8 pixels (simd8) or span set-ups (scanline): one cycle each.
    pub wide_steps: u64,
}

/// Block classification against the triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// All four corners outside one edge: no pixel of the block can be inside.
    Reject,
    /// All four corners inside all edges: every pixel is inside (convexity).
    Accept,
    /// Needs per-pixel tests.
    Partial,
}

/// Classifies the pixel rectangle `[x0, x1] × [y0, y1]` (inclusive pixel indices) by the
/// edge values at its four corner pixel centres — 12 values, as in seed 004 — with the
/// correct reject rule: all four corners outside the *same* edge.
#[inline]
pub fn classify(edges: &[Edge; 3], x0: u32, y0: u32, x1: u32, y1: u32) -> Class {
    let mut accept = true;
    for e in edges {
        let c00 = e.at(x0 as i64, y0 as i64);
        let c10 = e.at(x1 as i64, y0 as i64);
        let c01 = e.at(x0 as i64, y1 as i64);
        let c11 = e.at(x1 as i64, y1 as i64);
        if (c00 & c10 & c01 & c11) < 0 {
            return Class::Reject;
        }
        if (c00 | c10 | c01 | c11) < 0 {
            accept = false;
        }
    }
    if accept {
        Class::Accept
    } else {
        Class::Partial
    }
}

/// Seed 004's rule, kept only to demonstrate its flaw in the tests: a block is "outside"
/// when each of its four corners is outside the triangle — possibly by different edges,
/// which loses thin triangles passing between the corners.
pub fn seed004_rejects(edges: &[Edge; 3], x0: u32, y0: u32, x1: u32, y1: u32) -> bool {
    [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
        .iter()
        .all(|&(x, y)| edges.iter().any(|e| e.at(x as i64, y as i64) < 0))
}

/// Emits runs of inside pixels of row `j` in `[x0, x1)` by per-pixel incremental tests.
#[inline]
fn test_row<F: FnMut(u32, u32, u32)>(s: &TriSetup, j: u32, x0: u32, x1: u32, emit: &mut F) {
    let [e0, e1, e2] = &s.edges;
    let (mut v0, mut v1, mut v2) = (
        e0.at(x0 as i64, j as i64),
        e1.at(x0 as i64, j as i64),
        e2.at(x0 as i64, j as i64),
    );
    let mut start = None;
    for i in x0..x1 {
        let inside = (v0 | v1 | v2) >= 0;
        match (inside, start) {
            (true, None) => start = Some(i),
            (false, Some(s0)) => {
                emit(j, s0, i);
                start = None;
            }
            _ => {}
        }
        v0 += e0.a;
        v1 += e1.a;
        v2 += e2.a;
    }
    if let Some(s0) = start {
        emit(j, s0, x1);
    }
}

/// One edge's span bound walked down the rows exactly: the quotient and remainder of
/// `N(j) / d` are stepped with additions only (the divisions happen once, at set-up).
/// Lower and upper bounds are both kept in floor form (a ceiling is a floor of
/// `n + d − 1`) with the column offset folded into `q`, so a row costs one
/// add-compare-carry per bound and no branch on the edge's kind.
#[derive(Clone, Copy)]
struct Step {
    q: i64,
    r: i64,
    d: i64,
    dq: i64,
    dr: i64,
}

impl Step {
    /// A bound that never binds: `q` stays at `at`.
    const fn neutral(at: i64) -> Self {
        Self {
            q: at,
            r: 0,
            d: 1,
            dq: 0,
            dr: 0,
        }
    }

    /// `offset + floor(n / d)` stepped by `dn` per row (`d > 0`).
    fn new(offset: i64, n: i64, d: i64, dn: i64) -> Self {
        let (q, dq) = (n.div_euclid(d), dn.div_euclid(d));
        Self {
            q: offset + q,
            r: n - q * d,
            d,
            dq,
            dr: dn - dq * d,
        }
    }

    #[inline(always)]
    fn advance(&mut self) {
        self.r += self.dr;
        let carry = (self.r >= self.d) as i64;
        self.q += self.dq + carry;
        self.r -= self.d & -carry;
    }
}

/// Scanline spans without per-row divisions. A triangle has at most two edges with
/// `a > 0` (they bound the span from the left) and two with `a < 0` (from the right),
/// because the three `a` sum to zero; missing ones are padded with neutral bounds. A
/// horizontal edge (`a = 0`) does not depend on the column: it only trims the row range,
/// which is decided here once.
struct EdgeWalk {
    x0: i64,
    x1: i64,
    lo: [Step; 2],
    hi: [Step; 2],
    /// Rows `[y0, y1)` left after the horizontal edge, if any.
    rows: (u32, u32),
}

impl EdgeWalk {
    fn new(s: &TriSetup) -> Self {
        let [x0, mut y0, x1, mut y1] = s.bbox;
        for e in &s.edges {
            if e.a != 0 {
                continue;
            }
            // Inside iff v + b·k ≥ 0 at row y0 + k, monotone in k.
            let v = e.at(x0 as i64, y0 as i64);
            let span = (y1 - y0) as i64;
            if e.b > 0 {
                let k = (-v).div_euclid(e.b) + ((-v).rem_euclid(e.b) > 0) as i64;
                y0 += k.clamp(0, span) as u32;
            } else if e.b < 0 {
                let k = v.div_euclid(-e.b) + 1;
                y1 = y0 + k.clamp(0, span) as u32;
            } else if v < 0 {
                y1 = y0;
            }
        }
        let (xa, xb) = (x0 as i64, x1 as i64);
        let mut lo = [Step::neutral(xa); 2];
        let mut hi = [Step::neutral(xb); 2];
        let (mut nl, mut nh) = (0, 0);
        for e in &s.edges {
            let v = e.at(x0 as i64, y0 as i64);
            if e.a > 0 {
                // First inside column: k ≥ ceil(−v / a) = floor((a − 1 − v) / a).
                if let Some(slot) = lo.get_mut(nl) {
                    *slot = Step::new(xa, e.a - 1 - v, e.a, -e.b);
                }
                nl += 1;
            } else if e.a < 0 {
                // One past the last inside column: k ≤ floor(v / −a).
                if let Some(slot) = hi.get_mut(nh) {
                    *slot = Step::new(xa + 1, v, -e.a, e.b);
                }
                nh += 1;
            }
        }
        Self {
            x0: xa,
            x1: xb,
            lo,
            hi,
            rows: (y0, y1.max(y0)),
        }
    }

    /// The span of the current row (possibly empty: `lo ≥ hi`), then steps to the next row.
    #[inline(always)]
    fn next_row(&mut self) -> (i64, i64) {
        let lo = self.lo[0].q.max(self.lo[1].q).max(self.x0);
        let hi = self.hi[0].q.min(self.hi[1].q).min(self.x1);
        self.lo[0].advance();
        self.lo[1].advance();
        self.hi[0].advance();
        self.hi[1].advance();
        (lo, hi)
    }
}

/// Rows of spans the scanline traversal computes before handing them out.
const SPAN_BAND: usize = 32;

/// Joins spans that touch within a band of rows, so that block traversals hand the
/// framebuffer one long span per row instead of one per block (the SDRAM burst model).
struct Merger {
    y0: u32,
    rows: [(u32, u32); MERGE_ROWS],
}

/// Rows a [`Merger`] holds: the tallest block.
const MERGE_ROWS: usize = 32;
const _: () = assert!(TILE_SIZES[0] as usize <= MERGE_ROWS && ZIGZAG_BLOCK as usize <= MERGE_ROWS);

impl Merger {
    fn new(y0: u32) -> Self {
        Self {
            y0,
            rows: [(0, 0); MERGE_ROWS],
        }
    }

    #[inline]
    fn push<F: FnMut(u32, u32, u32)>(&mut self, y: u32, a: u32, b: u32, emit: &mut F) {
        let Some(p) = self.rows.get_mut((y - self.y0) as usize) else {
            emit(y, a, b);
            return;
        };
        if p.0 == p.1 {
            *p = (a, b);
        } else if p.1 == a {
            p.1 = b;
        } else if b == p.0 {
            p.0 = a;
        } else {
            emit(y, p.0, p.1);
            *p = (a, b);
        }
    }

    fn flush<F: FnMut(u32, u32, u32)>(&mut self, emit: &mut F) {
        for (k, p) in self.rows.iter_mut().enumerate() {
            if p.0 == p.1 {
                continue;
            }
            if p.0 < p.1 {
                emit(self.y0 + k as u32, p.0, p.1);
            }
            *p = (0, 0);
        }
    }
}

/// Walks the triangle with `t`, calling `emit(y, x0, x1)` for runs of covered pixels.
/// All traversals emit exactly the same pixel set (each pixel once); order differs.
pub fn traverse<F: FnMut(u32, u32, u32)>(
    s: &TriSetup,
    t: Traversal,
    c: &mut TravCounters,
    emit: &mut F,
) {
    let [x0, y0, x1, y1] = s.bbox;
    match t {
        Traversal::BoundingBox => {
            for j in y0..y1 {
                test_row(s, j, x0, x1, emit);
            }
            c.pixel_tests += (x1 - x0) as u64 * (y1 - y0) as u64;
        }
        Traversal::Scanline => {
            // One span set-up per bounding-box row, as the hardware walks them all.
            c.wide_steps += (y1 - y0) as u64;
            let mut walk = EdgeWalk::new(s);
            let (mut ya, yb) = walk.rows;
            let mut accepted = 0;
            // Spans are computed a band of rows at a time with no call in the loop, so
            // the walk's state stays in registers instead of being spilled around `emit`.
            let mut band = [(0i64, 0i64); SPAN_BAND];
            while ya < yb {
                let n = ((yb - ya) as usize).min(SPAN_BAND);
                for sp in &mut band[..n] {
                    *sp = walk.next_row();
                }
                for (j, &(a, b)) in (ya..).zip(&band[..n]) {
                    if a < b {
                        accepted += (b - a) as u64;
                        emit(j, a as u32, b as u32);
                    }
                }
                ya += n as u32;
            }
            c.accepted += accepted;
        }
        Traversal::Simd8 => simd8(s, c, emit),
        Traversal::Tiles => tiles(s, c, emit),
        Traversal::Zigzag => zigzag_merged(s, c, emit),
    }
}

// Separate functions keep each traversal's state (the span merger) out of the others'
// stack frames: inlined together, LLVM initialised it for every triangle.
#[inline(never)]
fn tiles<F: FnMut(u32, u32, u32)>(s: &TriSetup, c: &mut TravCounters, emit: &mut F) {
    let [x0, y0, x1, y1] = s.bbox;
    let t0 = TILE_SIZES[0];
    let mut ty = y0;
    let mut m = Merger::new(y0);
    while ty < y1 {
        m.y0 = ty;
        let mut tx = x0;
        while tx < x1 {
            tile(s, tx, ty, 0, c, &mut |y, a, b| m.push(y, a, b, emit));
            tx += t0;
        }
        m.flush(emit);
        ty += t0;
    }
}

#[inline(never)]
fn zigzag_merged<F: FnMut(u32, u32, u32)>(s: &TriSetup, c: &mut TravCounters, emit: &mut F) {
    let [_, y0, _, _] = s.bbox;
    let mut m = Merger::new(y0);
    zigzag(s, c, &mut |y, a, b| {
        if y >= m.y0 + ZIGZAG_BLOCK {
            m.flush(emit);
            m.y0 = y - (y - y0) % ZIGZAG_BLOCK;
        }
        m.push(y, a, b, emit)
    });
    m.flush(emit);
}

fn simd8<F: FnMut(u32, u32, u32)>(s: &TriSetup, c: &mut TravCounters, emit: &mut F) {
    let [x0, y0, x1, y1] = s.bbox;
    let [e0, e1, e2] = s.edges;
    // Lane offsets a·l, computed once: the eight units then only add and test signs.
    let o0: [i64; 8] = core::array::from_fn(|l| e0.a * l as i64);
    let o1: [i64; 8] = core::array::from_fn(|l| e1.a * l as i64);
    let o2: [i64; 8] = core::array::from_fn(|l| e2.a * l as i64);
    for j in y0..y1 {
        let mut start: Option<u32> = None;
        let mut x = x0;
        let (mut v0, mut v1, mut v2) = (
            e0.at(x0 as i64, j as i64),
            e1.at(x0 as i64, j as i64),
            e2.at(x0 as i64, j as i64),
        );
        while x < x1 {
            let mut mask = 0u32;
            for l in 0..8 {
                let out = ((v0 + o0[l]) | (v1 + o1[l]) | (v2 + o2[l])) < 0;
                mask |= (!out as u32) << l;
            }
            let lanes = (x1 - x).min(8);
            let full = (1u32 << lanes) - 1;
            mask &= full;
            c.wide_steps += 1;
            if mask == full {
                if start.is_none() {
                    start = Some(x);
                }
            } else if mask == 0 {
                if let Some(s0) = start.take() {
                    emit(j, s0, x);
                }
            } else {
                for l in 0..lanes {
                    let inside = mask >> l & 1 == 1;
                    match (inside, start) {
                        (true, None) => start = Some(x + l),
                        (false, Some(s0)) => {
                            emit(j, s0, x + l);
                            start = None;
                        }
                        _ => {}
                    }
                }
            }
            x += lanes;
            v0 += e0.a * 8;
            v1 += e1.a * 8;
            v2 += e2.a * 8;
        }
        if let Some(s0) = start {
            emit(j, s0, x1);
        }
    }
}

fn emit_block<F: FnMut(u32, u32, u32)>(x: u32, y: u32, xe: u32, ye: u32, emit: &mut F) {
    for j in y..ye {
        emit(j, x, xe);
    }
}

fn tile<F: FnMut(u32, u32, u32)>(
    s: &TriSetup,
    x: u32,
    y: u32,
    level: usize,
    c: &mut TravCounters,
    emit: &mut F,
) {
    let size = TILE_SIZES[level];
    let xe = (x + size).min(s.bbox[2]);
    let ye = (y + size).min(s.bbox[3]);
    c.block_tests += 1;
    match classify(&s.edges, x, y, xe - 1, ye - 1) {
        Class::Reject => {}
        Class::Accept => {
            c.accepted += (xe - x) as u64 * (ye - y) as u64;
            emit_block(x, y, xe, ye, emit);
        }
        Class::Partial => {
            if level + 1 < TILE_SIZES.len() {
                let sub = TILE_SIZES[level + 1];
                let mut ty = y;
                while ty < ye {
                    let mut tx = x;
                    while tx < xe {
                        tile(s, tx, ty, level + 1, c, emit);
                        tx += sub;
                    }
                    ty += sub;
                }
            } else {
                c.pixel_tests += (xe - x) as u64 * (ye - y) as u64;
                for j in y..ye {
                    test_row(s, j, x, xe, emit);
                }
            }
        }
    }
}

/// Seed 004's zigzag: block rows in alternating directions, each row walked from where
/// the previous one ended. A row's non-rejected blocks are contiguous (the reject test of
/// each edge is monotone along a row, and three intervals intersect in one), so a row
/// ends at its first rejected block after the run — with the *correct* reject rule.
fn zigzag<F: FnMut(u32, u32, u32)>(s: &TriSetup, c: &mut TravCounters, emit: &mut F) {
    let [x0, y0, x1, y1] = s.bbox;
    let bs = ZIGZAG_BLOCK;
    let bw = (x1 - x0).div_ceil(bs) as i64;
    let bh = (y1 - y0).div_ceil(bs);
    let mut col: i64 = 0;
    let mut dir: i64 = 1;
    for row in 0..bh {
        let by = y0 + row * bs;
        let bye = (by + bs).min(y1);
        let class = |cl: i64, c: &mut TravCounters| {
            let bx = x0 + cl as u32 * bs;
            let bxe = (bx + bs).min(x1);
            c.block_tests += 1;
            (classify(&s.edges, bx, by, bxe - 1, bye - 1), bx, bxe)
        };
        let visit = |cl: i64, c: &mut TravCounters, emit: &mut F| -> bool {
            let (k, bx, bxe) = class(cl, c);
            match k {
                Class::Reject => false,
                Class::Accept => {
                    c.accepted += (bxe - bx) as u64 * (bye - by) as u64;
                    emit_block(bx, by, bxe, bye, emit);
                    true
                }
                Class::Partial => {
                    c.pixel_tests += (bxe - bx) as u64 * (bye - by) as u64;
                    for j in by..bye {
                        test_row(s, j, bx, bxe, emit);
                    }
                    true
                }
            }
        };
        // Find a live block: forward from `col`, then backward.
        let mut found = None;
        let mut k = col;
        while (0..bw).contains(&k) {
            if visit(k, c, emit) {
                found = Some(k);
                break;
            }
            k += dir;
        }
        if found.is_none() {
            let mut k = col - dir;
            while (0..bw).contains(&k) {
                if visit(k, c, emit) {
                    found = Some(k);
                    // Continue in this direction: the run lies on this side.
                    let mut m = k - dir;
                    while (0..bw).contains(&m) && visit(m, c, emit) {
                        m -= dir;
                    }
                    col = m + dir;
                    break;
                }
                k -= dir;
            }
            // Travel was -dir; the next row reverses it, i.e. goes +dir: keep `dir`.
            if found.is_none() {
                dir = -dir;
            }
            continue;
        }
        let Some(f) = found else { continue };
        // Finish the run forward, then backward behind the start.
        let mut m = f + dir;
        let mut last = f;
        while (0..bw).contains(&m) && visit(m, c, emit) {
            last = m;
            m += dir;
        }
        let mut m = f - dir;
        while f == col && (0..bw).contains(&m) && visit(m, c, emit) {
            m -= dir;
        }
        col = last;
        dir = -dir;
    }
}
