//! The traversals walked pixel by pixel, as the model did before it separated coverage
//! from cost: the oracle that the counters of [`super::traverse`] are checked against.
//! Test-only, so that the model has one production path.

use protocol::raster::Traversal;

use super::{classify, Class, TravCounters, TriSetup, TILE_SIZES, ZIGZAG_BLOCK};

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

/// The traversal `t` walked pixel by pixel as the block does, calling `emit(y, x0, x1)`
/// for runs of covered pixels in the order it finds them, and counting its work.
pub(super) fn walk<F: FnMut(u32, u32, u32)>(
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
            // One span set-up per bounding-box row; every covered pixel is emitted in an
            // exact span without a test.
            c.wide_steps += (y1 - y0) as u64;
            for j in y0..y1 {
                test_row(s, j, x0, x1, &mut |y, a, b| {
                    c.accepted += (b - a) as u64;
                    emit(y, a, b)
                });
            }
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
