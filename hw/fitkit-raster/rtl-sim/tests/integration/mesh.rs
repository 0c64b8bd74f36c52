//! Shared-edge meshes: a grid of triangles tiling a rectangle with jittered inner
//! vertices. With the top-left rule every pixel whose centre is inside the rectangle is
//! written exactly once: all of them change from the background (no gap), and the
//! block's fragment counter equals their number (no pixel twice).

use protocol::bus::rgb332_encode;
use protocol::raster::Cull;
use rand::Rng;

use crate::cases;
use crate::harness::{self, Pair};
use crate::tally::Tally;

#[test]
fn meshes_write_every_pixel_once() {
    let mut t = Tally::default();
    let mut rng = cases::rng(0x31);
    for m in 0..16 {
        let bg = cases::color(&mut rng);
        let mut pair = Pair::new(harness::setup(128, 128, bg, Cull::None));
        let (cols, rows, cell) = (
            rng.gen_range(2..=8),
            rng.gen_range(2..=8),
            rng.gen_range(6..=14),
        );
        let (x0, y0) = (rng.gen_range(0..8), rng.gen_range(0..8));
        // Under a fifth of a cell, every triangle keeps its winding: a valid tiling.
        let jitter = cell / 5;
        let grid: Vec<Vec<(i32, i32)>> = (0..=rows)
            .map(|j| {
                (0..=cols)
                    .map(|i| {
                        let (x, y) = (x0 + i * cell, y0 + j * cell);
                        let inner = i > 0 && i < cols && j > 0 && j < rows;
                        if inner {
                            (
                                x + rng.gen_range(-jitter..=jitter),
                                y + rng.gen_range(-jitter..=jitter),
                            )
                        } else {
                            (x, y)
                        }
                    })
                    .collect()
            })
            .collect();
        let first = pair.status().fragments;
        for j in 0..rows as usize {
            for i in 0..cols as usize {
                let (a, b, c, d) = (
                    grid[j][i],
                    grid[j][i + 1],
                    grid[j + 1][i + 1],
                    grid[j + 1][i],
                );
                let halves = if rng.gen() {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                for mut v in halves {
                    if rng.gen() {
                        v.swap(1, 2);
                    }
                    let cmd = cases::triangle(v, cases::color_except(&mut rng, bg));
                    let case = format!("mesh {m} cell ({i}, {j})");
                    let step = pair.step(&case, &cmd, false);
                    t.add("mesh", || format!("{case}: {cmd:?}"), &step);
                }
            }
        }
        let area = (cols * cell * rows * cell) as usize;
        let bg = rgb332_encode(bg).expect("RGB332");
        let frame = pair.rtl.borrow().frame(128, 128).expect("inside");
        let changed = frame.iter().filter(|&&p| p != bg).count();
        assert_eq!(changed, area, "mesh {m}: pixels written (a gap if fewer)");
        let written = u64::from(pair.status().fragments - first);
        assert_eq!(
            written, area as u64,
            "mesh {m}: fragments (a pixel written twice if more)"
        );
    }
    assert!(t.cases() >= 200, "{} mesh triangles", t.cases());
    t.assert_exact();
}
