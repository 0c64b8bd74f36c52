//! Triangle setup (edge functions, fill rule, orientation), the exact edge walk that fills
//! every triangle, and what each of the five traversals would cost walking it.
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
//! [`MAX_FRAME_SIDE`]: protocol::MAX_FRAME_SIDE
//! [`MAX_SUBPIXEL_BITS`]: protocol::raster::MAX_SUBPIXEL_BITS

use protocol::raster::{Cull, Point, Traversal};

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

/// One edge's span bound walked down the rows exactly: the quotient and remainder of
/// `N(j) / d` are stepped with additions only (the divisions happen once, at set-up).
/// Lower and upper bounds are both kept in floor form (a ceiling is a floor of
/// `n + d − 1`) with the column offset folded into `q`, so a row costs one
/// add-carry per bound and no branch on the edge's kind. The remainder is kept minus
/// `d` (in `[−d, 0)`), so that the carry is its sign bit: an arithmetic shift, where a
/// 64-bit compare costs several instructions once LLVM vectorises the four bounds.
#[derive(Clone, Copy)]
struct Step<T> {
    q: T,
    /// Remainder − d.
    r: T,
    d: T,
    dq: T,
    dr: T,
}

/// The integer an edge walk steps its bounds in. `i64` holds every walk the set-up
/// admits; `i32` holds most (pixel-sized edges, bounds near the box), and four `i32`
/// bounds step in one SSE2 register with a native arithmetic shift, where `i64` needs
/// two registers and an emulated one.
trait WalkInt:
    Copy
    + core::ops::Add<Output = Self>
    + core::ops::Sub<Output = Self>
    + core::ops::BitAnd<Output = Self>
    + core::ops::Not<Output = Self>
    + core::ops::Shr<u32, Output = Self>
    + Into<i64>
    + TryFrom<i64>
{
    /// The sign bit's position.
    const SIGN: u32;
    /// 1.
    const ONE: Self;
}

impl WalkInt for i32 {
    const SIGN: u32 = 31;
    const ONE: Self = 1;
}

impl WalkInt for i64 {
    const SIGN: u32 = 63;
    const ONE: Self = 1;
}

impl Step<i64> {
    /// A bound that never binds: `q` stays at `at`.
    const fn neutral(at: i64) -> Self {
        Self {
            q: at,
            r: -1,
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
            r: n - q * d - d,
            d,
            dq,
            dr: dn - dq * d,
        }
    }

    /// The same walk in `T`, if every value it takes over `rows` rows fits: `r` stays in
    /// `[−d, d)` and `q` moves by at most `|dq| + 1` a row.
    fn narrow<T: WalkInt>(&self, rows: i64) -> Option<Step<T>> {
        let fits = |v: i64| T::try_from(v).is_ok() && T::try_from(-v).is_ok();
        let reach = self
            .q
            .abs()
            .saturating_add(rows.saturating_mul(self.dq.abs() + 1));
        if !fits(2 * self.d) || !fits(reach) {
            return None;
        }
        let t = |v: i64| T::try_from(v).ok();
        Some(Step {
            q: t(self.q)?,
            r: t(self.r)?,
            d: t(self.d)?,
            dq: t(self.dq)?,
            dr: t(self.dr)?,
        })
    }
}

impl<T: WalkInt> Step<T> {
    #[inline(always)]
    fn advance(&mut self) {
        self.r = self.r + self.dr;
        // All ones when the remainder reached d.
        let carry = !(self.r >> T::SIGN);
        self.q = self.q + self.dq + (carry & T::ONE);
        self.r = self.r - (self.d & carry);
    }
}

/// Each slanted edge's bound on one row, in absolute pixel columns: `[lo0, lo1, hi0,
/// hi1]`, where an edge with `a > 0` admits the columns `x ≥ lo` and one with `a < 0` the
/// columns `x < hi`. Unclamped, so that they describe the edge and not the bounding box.
type Bounds = [i64; 4];

/// Scanline spans without per-row divisions. A triangle has at most two edges with
/// `a > 0` (they bound the span from the left) and two with `a < 0` (from the right),
/// because the three `a` sum to zero; missing ones are padded with neutral bounds. A
/// horizontal edge (`a = 0`) does not depend on the column: it only trims the row range,
/// which is decided here once. The bounds are stepped over every row of the bounding
/// box, trimmed or not, because the block accounting needs them at block corners.
struct EdgeWalk<T = i64> {
    x0: i64,
    x1: i64,
    lo: [Step<T>; 2],
    hi: [Step<T>; 2],
    /// Rows `[y0, y1)` left after the horizontal edge, if any.
    rows: (u32, u32),
}

impl EdgeWalk {
    fn new(s: &TriSetup) -> Self {
        let [x0, y0, x1, y1] = s.bbox;
        let (mut ya, mut yb) = (y0, y1);
        for e in &s.edges {
            if e.a != 0 {
                continue;
            }
            // Inside iff v + b·k ≥ 0 at row y0 + k, monotone in k.
            let v = e.at(x0 as i64, y0 as i64);
            let span = (y1 - y0) as i64;
            if e.b > 0 {
                let k = (-v).div_euclid(e.b) + ((-v).rem_euclid(e.b) > 0) as i64;
                ya = y0 + k.clamp(0, span) as u32;
            } else if e.b < 0 {
                let k = v.div_euclid(-e.b) + 1;
                yb = y0 + k.clamp(0, span) as u32;
            } else if v < 0 {
                yb = y0;
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
            rows: (ya, yb.max(ya)),
        }
    }

    /// The same walk in `T`, if it fits over `rows` rows.
    fn narrow<T: WalkInt>(&self, rows: u32) -> Option<EdgeWalk<T>> {
        let n = i64::from(rows);
        Some(EdgeWalk {
            x0: self.x0,
            x1: self.x1,
            lo: [self.lo[0].narrow(n)?, self.lo[1].narrow(n)?],
            hi: [self.hi[0].narrow(n)?, self.hi[1].narrow(n)?],
            rows: self.rows,
        })
    }
}

impl<T: WalkInt> EdgeWalk<T> {
    /// The current row's bounds, then steps to the next row.
    #[inline(always)]
    fn next_row(&mut self) -> Bounds {
        let b = [
            self.lo[0].q.into(),
            self.lo[1].q.into(),
            self.hi[0].q.into(),
            self.hi[1].q.into(),
        ];
        self.lo[0].advance();
        self.lo[1].advance();
        self.hi[0].advance();
        self.hi[1].advance();
        b
    }

    /// The covered span of a row with bounds `b` (empty when `lo ≥ hi`).
    #[inline(always)]
    fn span(&self, b: &Bounds) -> (i64, i64) {
        (b[0].max(b[1]).max(self.x0), b[2].min(b[3]).min(self.x1))
    }
}

/// Rows of bounds the walk computes before handing out spans: one coarse tile row, so
/// that a band is also the unit of the tile accounting.
const SPAN_BAND: usize = TILE_SIZES[0] as usize;
/// log2 of the zigzag block side, which is also the fine tile side.
const BLOCK_SHIFT: u32 = ZIGZAG_BLOCK.trailing_zeros();
/// log2 of the coarse tile side.
const TILE_SHIFT: u32 = TILE_SIZES[0].trailing_zeros();
const _: () = assert!(
    TILE_SIZES.len() == 2
        && TILE_SIZES[1] == ZIGZAG_BLOCK
        && ZIGZAG_BLOCK.is_power_of_two()
        && TILE_SIZES[0].is_power_of_two()
        && TILE_SIZES[0] > ZIGZAG_BLOCK,
    "the block accounting assumes a two-level tile hierarchy whose fine level is the zigzag grid"
);

/// One row of blocks (or coarse tiles) as pixel columns: `live` spans the blocks that
/// are not rejected, `acc` those trivially accepted (`acc ⊆ live`), each clipped to the
/// bounding box and empty when `start ≥ end`. Both are runs of whole blocks: per edge,
/// rejection and acceptance are monotone along a row.
#[derive(Debug, Clone, Copy)]
struct RowClass {
    live: (i64, i64),
    acc: (i64, i64),
}

/// Pixels of a run of columns (0 when empty).
#[inline(always)]
fn width((a, b): (i64, i64)) -> i64 {
    (b - a).max(0)
}

/// A grid of `2^shift`-pixel blocks anchored at the bounding box's top-left corner, as
/// the tile and zigzag traversals lay theirs.
#[derive(Debug, Clone, Copy)]
struct Grid {
    x0: i64,
    x1: i64,
    /// Rows inside the horizontal edge, if any (all rows otherwise).
    rows: (u32, u32),
    shift: u32,
}

impl Grid {
    /// Blocks per row.
    fn cols(&self) -> i64 {
        ((self.x1 - 1 - self.x0) >> self.shift) + 1
    }

    /// Pixel run `r` as block columns `[l, h)` (`r` must start on a block and end on one
    /// or at the box's edge).
    fn blocks(&self, r: (i64, i64)) -> (i64, i64) {
        if r.0 >= r.1 {
            return (0, 0);
        }
        let m = (1 << self.shift) - 1;
        (
            (r.0 - self.x0) >> self.shift,
            (r.1 - self.x0 + m) >> self.shift,
        )
    }

    /// What [`classify`] says of every block of the pixel rows `[by, bye)`, from the
    /// edge bounds at the first (`top`) and last (`bot`) of those rows. For an edge with
    /// `a > 0`, all four corners are outside iff the block's right column is left of the
    /// bound on every row, i.e. of its least value, and all are inside iff the left column
    /// reaches its greatest; each bound is monotone in the row, so its extremes over the
    /// block are at its first and last rows. Edges with `a < 0` mirror that, and the
    /// horizontal edge rejects a block with no row in `rows` and accepts one with all.
    #[inline(always)]
    fn class(&self, top: &Bounds, bot: &Bounds, by: u32, bye: u32) -> RowClass {
        let (x0, x1) = (self.x0, self.x1);
        let m = (1 << self.shift) - 1;
        let (ya, yb) = self.rows;
        let live_lo = top[0].min(bot[0]).max(top[1].min(bot[1])).max(x0);
        let acc_lo = top[0].max(bot[0]).max(top[1].max(bot[1])).max(x0);
        let live_hi = top[2].max(bot[2]).min(top[3].max(bot[3])).min(x1);
        let acc_hi = top[2].min(bot[2]).min(top[3].min(bot[3])).min(x1);
        // Live: from the block holding live_lo to the one holding live_hi − 1.
        let live = if by < yb && ya < bye && live_lo < x1 && live_hi > x0 {
            (
                x0 + ((live_lo - x0) & !m),
                (x0 + ((live_hi - x0 + m) & !m)).min(x1),
            )
        } else {
            (0, 0)
        };
        // Accepted: the whole blocks within [acc_lo, acc_hi) (the box's last, narrower
        // block counts as whole when acc_hi reaches the box's edge).
        let acc = if ya <= by && bye <= yb {
            let h = if acc_hi >= x1 {
                x1
            } else {
                x0 + ((acc_hi - x0).max(0) & !m)
            };
            (x0 + ((acc_lo - x0 + m) & !m), h)
        } else {
            (0, 0)
        };
        RowClass { live, acc }
    }
}

/// Seed 004's zigzag over one block row whose live blocks are `[lo, hi)` of `bw`: the
/// classifications it makes (including the rejected blocks it probes), with its column
/// and direction carried to the next row. The same decisions as the pixel walk, taken on
/// the interval instead of block by block.
fn zigzag_row((lo, hi): (i64, i64), bw: i64, col: &mut i64, dir: &mut i64) -> u64 {
    let live = |k: i64| lo <= k && k < hi;
    let in_range = |k: i64| (0..bw).contains(&k);
    // Blocks visited from `k` towards `d` up to and including the first live one.
    let probe = |k: i64, d: i64| -> (u64, Option<i64>) {
        if !in_range(k) {
            return (0, None);
        }
        if live(k) {
            return (1, Some(k));
        }
        if lo < hi && d > 0 && k < lo {
            return ((lo - k + 1) as u64, Some(lo));
        }
        if lo < hi && d < 0 && k >= hi {
            return ((k - hi + 2) as u64, Some(hi - 1));
        }
        // Nothing live ahead: every block up to the edge of the box is visited.
        ((if d > 0 { bw - k } else { k + 1 }) as u64, None)
    };
    // Blocks visited from `m` towards `d` while live, plus the first one that is not (if
    // in range); also where that walk stopped.
    let extend = |m: i64, d: i64| -> (u64, i64) {
        let end = match (live(m), d > 0) {
            (false, _) => m,
            (true, true) => hi,
            (true, false) => lo - 1,
        };
        ((end - m).unsigned_abs() + in_range(end) as u64, end)
    };
    let (mut tests, found) = probe(*col, *dir);
    match found {
        None => {
            let (t, back) = probe(*col - *dir, -*dir);
            tests += t;
            match back {
                Some(k) => {
                    // The run lies behind: walk it to its far end and keep the direction.
                    let (t, end) = extend(k - *dir, -*dir);
                    tests += t;
                    *col = end + *dir;
                }
                None => *dir = -*dir,
            }
        }
        Some(f) => {
            let (t, end) = extend(f + *dir, *dir);
            tests += t;
            if f == *col {
                tests += extend(f - *dir, -*dir).0;
            }
            *col = end - *dir;
            *dir = -*dir;
        }
    }
    tests
}

/// The counters of the block traversals, accumulated band by band from the edge walk's
/// bounds. Tiles and zigzag test the same fine blocks per pixel and accept the same
/// ones: a coarse tile is rejected only if all its fine tiles are and accepted exactly
/// when all are, and the zigzag visits every live block of a row. Only their block
/// classifications differ.
struct BlockCost {
    fine: Grid,
    coarse: Grid,
    /// Zigzag state (column, direction) when accounting that traversal, else tiles.
    zigzag: Option<(i64, i64)>,
    c: TravCounters,
}

impl BlockCost {
    fn new<T>(walk: &EdgeWalk<T>, zigzag: bool) -> Self {
        let fine = Grid {
            x0: walk.x0,
            x1: walk.x1,
            rows: walk.rows,
            shift: BLOCK_SHIFT,
        };
        Self {
            fine,
            coarse: Grid {
                shift: TILE_SHIFT,
                ..fine
            },
            zigzag: zigzag.then_some((0, 1)),
            c: TravCounters::default(),
        }
    }

    /// Accounts the block rows of one band: `rows` are the bounds of the pixel rows from
    /// `y` on, at most one coarse tile high.
    fn band(&mut self, y: u32, rows: &[Bounds]) {
        let (Some(first), Some(last)) = (rows.first(), rows.last()) else {
            return;
        };
        let bw = self.fine.cols();
        for (k, blk) in rows.chunks(ZIGZAG_BLOCK as usize).enumerate() {
            let by = y + k as u32 * ZIGZAG_BLOCK;
            let bye = by + blk.len() as u32;
            let (Some(top), Some(bot)) = (blk.first(), blk.last()) else {
                continue;
            };
            let rc = self.fine.class(top, bot, by, bye);
            let (live, acc) = (width(rc.live), width(rc.acc));
            let h = (bye - by) as u64;
            self.c.accepted += acc as u64 * h;
            self.c.pixel_tests += (live - acc) as u64 * h;
            if let Some((col, dir)) = &mut self.zigzag {
                self.c.block_tests += zigzag_row(self.fine.blocks(rc.live), bw, col, dir);
            }
        }
        if self.zigzag.is_none() {
            // Every coarse tile is classified; partial ones classify their fine tiles.
            let g = &self.coarse;
            let rc = g.class(first, last, y, y + rows.len() as u32);
            let fine_cols = |w: i64| (w as u64).div_ceil(ZIGZAG_BLOCK as u64);
            let fine_rows = (rows.len() as u64).div_ceil(ZIGZAG_BLOCK as u64);
            self.c.block_tests += g.cols() as u64
                + fine_rows * (fine_cols(width(rc.live)) - fine_cols(width(rc.acc)));
        }
    }
}

/// Emits the covered pixels of the triangle as runs `emit(y, x0, x1)`, top to bottom,
/// and adds to `c` the work that traversal `t` does to find them: [`traverse_bands`]
/// one row at a time, for callers that draw span by span.
pub fn traverse<F: FnMut(u32, u32, u32)>(
    s: &TriSetup,
    t: Traversal,
    c: &mut TravCounters,
    emit: &mut F,
) {
    traverse_bands(s, t, c, &mut |y, spans| {
        for (j, &(a, b)) in (y..).zip(spans) {
            if a < b {
                emit(j, a, b);
            }
        }
    });
}

/// A band's spans: `(x0, x1)` per row, `(0, 0)` for a row with no covered pixel.
pub type Spans<'a> = &'a [(u32, u32)];

/// The triangle's covered pixels as bands of consecutive rows, `emit(y, spans)` with
/// `spans[k]` the covered columns of row `y + k`, top to bottom, at most a coarse tile
/// (32 rows) per call; adds to `c` the work that traversal `t` does to find them.
/// Coverage does not depend on the traversal, so every traversal is filled by the
/// fastest exact walk (the scanline's edge bounds) and only the counters are the
/// modelled traversal's: derived from the bounding box, the spans, or the block classes
/// that the bounds determine, never by testing pixels. They equal what walking that
/// traversal counts, which the tests check against the pixel walks kept as an oracle.
///
/// A band at a time, not a span at a time, because a call per span made the caller's
/// span fill an out-of-line call in the walk's loop: the walk's bounds, stepped in vector
/// registers, were reloaded from the stack after every span, and the fill's own set-up
/// (colour pattern, bookkeeping) ran per row instead of per band.
pub fn traverse_bands<F: FnMut(u32, Spans<'_>)>(
    s: &TriSetup,
    t: Traversal,
    c: &mut TravCounters,
    emit: &mut F,
) {
    let walk = EdgeWalk::new(s);
    match walk.narrow::<i32>(s.bbox[3] - s.bbox[1]) {
        Some(narrow) => walk_bands(s, t, c, emit, narrow),
        None => walk_bands(s, t, c, emit, walk),
    }
}

/// [`traverse_bands`] with the walk's integer chosen.
#[inline(always)]
fn walk_bands<T: WalkInt, F: FnMut(u32, Spans<'_>)>(
    s: &TriSetup,
    t: Traversal,
    c: &mut TravCounters,
    emit: &mut F,
    mut walk: EdgeWalk<T>,
) {
    let [x0, y0, x1, y1] = s.bbox;
    let (w, h) = ((x1 - x0) as u64, (y1 - y0) as u64);
    let mut blocks = match t {
        Traversal::Tiles => Some(BlockCost::new(&walk, false)),
        Traversal::Zigzag => Some(BlockCost::new(&walk, true)),
        _ => None,
    };
    let (ya, yb) = walk.rows;
    let mut covered = 0;
    // Bounds are computed a band of rows at a time with no call in the loop, so the
    // walk's state stays in registers.
    let mut band = [[0i64; 4]; SPAN_BAND];
    let mut spans = [(0u32, 0u32); SPAN_BAND];
    let mut y = y0;
    while y < y1 {
        let n = ((y1 - y) as usize).min(SPAN_BAND);
        for b in &mut band[..n] {
            *b = walk.next_row();
        }
        // Rows trimmed by a horizontal edge are walked only for the accounting.
        let (ra, rb) = (ya.clamp(y, y + n as u32), yb.clamp(y, y + n as u32));
        if ra < rb {
            let rows = (ra - y) as usize..(rb - y) as usize;
            for (out, b) in spans[rows.clone()].iter_mut().zip(&band[rows.clone()]) {
                let (a, b) = walk.span(b);
                // Inside the box, so both fit u32 when the span is not empty.
                *out = if a < b { (a as u32, b as u32) } else { (0, 0) };
                covered += (b - a).max(0) as u64;
            }
            emit(ra, &spans[rows]);
        }
        if let Some(bc) = &mut blocks {
            bc.band(y, &band[..n]);
        }
        y += n as u32;
    }
    match t {
        Traversal::BoundingBox => c.pixel_tests += w * h,
        Traversal::Scanline => {
            // One span set-up per bounding-box row, as the hardware walks them all; the
            // spans' pixels need no test.
            c.wide_steps += h;
            c.accepted += covered;
        }
        // One 8-lane step per 8 columns of every row, testing in the lanes.
        Traversal::Simd8 => c.wide_steps += h * w.div_ceil(8),
        Traversal::Tiles | Traversal::Zigzag => {
            if let Some(bc) = blocks {
                c.pixel_tests += bc.c.pixel_tests;
                c.block_tests += bc.c.block_tests;
                c.accepted += bc.c.accepted;
            }
        }
    }
}

#[cfg(test)]
mod walk_oracle;

#[cfg(test)]
mod tests;
