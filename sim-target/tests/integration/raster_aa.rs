//! Anti-aliasing error against exact area, and texture sampling.

use protocol::raster::*;
use sim_target::raster::{aa, tex, tri, Raster};

fn lcg(seed: &mut u64) -> u32 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 33) as u32
}

fn triangles(n: usize) -> Vec<[Point; 3]> {
    let mut s = 7u64;
    (0..n)
        .map(|_| {
            core::array::from_fn(|_| Point {
                x: (lcg(&mut s) % (24 * 256)) as i32 + 256,
                y: (lcg(&mut s) % (24 * 256)) as i32 + 256,
            })
        })
        .collect()
}

/// (mean |per-pixel coverage error| over touched pixels, mean relative total-area error).
fn errors(tris: &[[Point; 3]], p: AaPattern, n: u8) -> (f64, f64) {
    let offs = aa::pattern(p, n);
    let levels = if n == 0 { 256 } else { n as u32 };
    let (mut pix_err, mut pix_n, mut area_err) = (0.0, 0u32, 0.0);
    for v in tris {
        let (mut sum, mut exact_sum) = (0.0, 0.0);
        for j in 0..27 {
            for i in 0..27 {
                let exact = aa::exact_coverage(v, 8, i, j);
                let got = if p == AaPattern::Coverage {
                    (exact * levels as f64).round() / levels as f64
                } else {
                    aa::covered(v, 8, &offs, i, j) as f64 / offs.len() as f64
                };
                if exact > 0.0 || got > 0.0 {
                    pix_err += (got - exact).abs();
                    pix_n += 1;
                }
                sum += got;
                exact_sum += exact;
            }
        }
        if exact_sum > 0.5 {
            area_err += (sum - exact_sum).abs() / exact_sum;
        }
    }
    (pix_err / pix_n.max(1) as f64, area_err / tris.len() as f64)
}

#[test]
fn aa_area_error_table() {
    let tris = triangles(60);
    println!("| pattern | samples | mean per-pixel error | mean relative area error |");
    println!("|---|---|---|---|");
    let mut table = Vec::new();
    for p in [
        AaPattern::Regular,
        AaPattern::Jitter,
        AaPattern::Rotated,
        AaPattern::Poisson,
        AaPattern::Coverage,
    ] {
        for n in [1u8, 4, 16, 64] {
            let (e, a) = errors(&tris, p, n);
            println!("| {p:?} | {n} | {e:.4} | {a:.4} |");
            table.push((p, n, e, a));
        }
    }
    for p in [
        AaPattern::Regular,
        AaPattern::Jitter,
        AaPattern::Rotated,
        AaPattern::Poisson,
    ] {
        let row: Vec<_> = table.iter().filter(|r| r.0 == p).collect();
        // More samples, less error: 1 → 4 → 16 strictly, and 16 samples within 6 %.
        assert!(
            row[1].2 < row[0].2 && row[2].2 < row[1].2,
            "{p:?} does not converge: {row:?}"
        );
        assert!(row[2].2 < 0.06, "{p:?} at 16 samples: {}", row[2].2);
        assert!(
            row[3].3 < 0.02,
            "{p:?} at 64 samples: area error {}",
            row[3].3
        );
    }
    for r in table.iter().filter(|r| r.0 == AaPattern::Coverage) {
        // Analytic coverage errs only by quantisation.
        assert!(r.2 <= 0.5 / r.1 as f64 + 1e-9, "{r:?}");
    }
}

#[test]
fn patterns_are_deterministic_and_inside_the_pixel() {
    for p in [
        AaPattern::Regular,
        AaPattern::Jitter,
        AaPattern::Rotated,
        AaPattern::Poisson,
    ] {
        for n in [1u8, 4, 9, 16] {
            let a = aa::pattern(p, n);
            assert_eq!(a, aa::pattern(p, n));
            assert_eq!(a.len(), n as usize, "{p:?} {n}");
            assert!(a.iter().all(|&(x, y)| x < 256 && y < 256));
        }
    }
    // RGSS: no two samples share a row or column.
    let r = aa::pattern(AaPattern::Rotated, 4);
    assert_eq!(r, vec![(32, 96), (96, 224), (160, 32), (224, 160)]);
}

#[test]
fn aa_triangle_through_the_raster() {
    let s = RasterSetup {
        width: 16,
        height: 16,
        subpixel_bits: 8,
        background: Rgb::new(0, 0, 0),
        aa: Aa {
            pattern: AaPattern::Regular,
            samples: 16,
        },
        cull: Cull::None,
        traversal: Traversal::Tiles,
    };
    let mut r = Raster::new(16, 16, &s).expect("setup");
    // Half-plane x < 8.25 over rows 0..16: column 8 is a quarter covered.
    let v = [
        Point { x: 0, y: 0 },
        Point {
            x: 8 * 256 + 64,
            y: 0,
        },
        Point {
            x: 8 * 256 + 64,
            y: 16 * 256,
        },
    ];
    let v2 = [
        Point { x: 0, y: 0 },
        Point {
            x: 8 * 256 + 64,
            y: 16 * 256,
        },
        Point { x: 0, y: 16 * 256 },
    ];
    for v in [v, v2] {
        r.draw(&RasterCmd::Triangle(Triangle {
            v,
            shade: Shade::Flat(Rgb::new(255, 255, 255)),
            z: None,
            w: None,
            tex: None,
        }))
        .expect("draw");
    }
    // Shared diagonal: both halves blend, so the diagonal pixels are not quite full, but
    // pixel (8, 0), touched by the first half only, is exactly a quarter (4 of 16).
    assert_eq!(r.framebuffer().pixel(8, 0), Some(Rgb::new(64, 64, 64)));
    assert_eq!(r.framebuffer().pixel(9, 3), Some(Rgb::new(0, 0, 0)));
}

fn tex_ref(wl: u8, hl: u8, wrap: Wrap, filter: Filter) -> TexRef {
    TexRef {
        base: 0,
        width_log2: wl,
        height_log2: hl,
        uv: [[0, 0]; 3],
        wrap,
        filter,
    }
}

#[test]
fn bilinear_is_exact_on_linear_gradients() {
    let (w, h) = (16u32, 16u32);
    let mem: Vec<u32> = (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            (8 * x + 3) << 16 | (5 * y + 10) << 8 | (2 * x + 3 * y)
        })
        .collect();
    let t = tex_ref(4, 4, Wrap::Clamp, Filter::Bilinear);
    // Positions on the 1/256-texel grid between texel centres 0.5 and 15.5.
    for kx in (128..=15 * 256 + 128).step_by(37) {
        for ky in (128..=15 * 256 + 128).step_by(53) {
            let (u, v) = ((kx << 8) / w as i64, (ky << 8) / h as i64);
            let q = tex::bilinear_q8(&mem, &t, 0, u, v);
            // Exact value × 256 of the linear function at (kx/256 − ½, ky/256 − ½).
            let (px, py) = (kx - 128, ky - 128);
            assert_eq!(q[0] as i64, 8 * px + 3 * 256, "r at {kx},{ky}");
            assert_eq!(q[1] as i64, 5 * py + 10 * 256, "g");
            assert_eq!(q[2] as i64, 2 * px + 3 * py, "b");
            let c = tex::sample(&mem, &t, u, v, 0);
            assert_eq!(c.r as i64, (8 * px + 3 * 256 + 128) >> 8);
        }
    }
}

#[test]
fn nearest_with_repeat_and_clamp() {
    let mem: Vec<u32> = (0..16).collect();
    let q = 65536 / 4;
    for (wrap, want) in [(Wrap::Repeat, 3), (Wrap::Clamp, 0)] {
        let t = tex_ref(2, 2, wrap, Filter::Nearest);
        // u = −¼ texture = −1 texel: repeat wraps to column 3, clamp sticks to 0.
        assert_eq!(tex::sample(&mem, &t, -q, 0, 0).b as u32, want);
        assert_eq!(tex::sample(&mem, &t, q + 1, q * 2 + 5, 0).b, 9);
    }
}

#[test]
fn trilinear_blends_mip_levels() {
    // 4 × 4 base (value 0), 2 × 2 level 1 (value 100), 1 × 1 level 2 (value 200).
    let mut mem = vec![0u32; 16];
    mem.extend([100u32; 4]);
    mem.push(200);
    let t = tex_ref(2, 2, Wrap::Repeat, Filter::Trilinear);
    assert_eq!(tex::footprint(&t), 21);
    assert_eq!(tex::sample(&mem, &t, 30000, 30000, 0).b, 0);
    assert_eq!(tex::sample(&mem, &t, 30000, 30000, 256).b, 100);
    assert_eq!(tex::sample(&mem, &t, 30000, 30000, 384).b, 150);
    assert_eq!(tex::sample(&mem, &t, 30000, 30000, 512).b, 200);
    // LOD from the UV gradient: 256 texels over 64 pixels is 4 texels per pixel → 2.0.
    let mut t = tex_ref(8, 8, Wrap::Repeat, Filter::Trilinear);
    t.uv = [[0, 0], [65536, 0], [0, 65536]];
    let v = [
        Point { x: 0, y: 0 },
        Point { x: 64 * 16, y: 0 },
        Point { x: 0, y: 64 * 16 },
    ];
    let s = tri::setup(&v, 4, 64, 64, Cull::None).expect("visible");
    let mut tt = t;
    let o = s.order;
    tt.uv = [t.uv[o[0]], t.uv[o[1]], t.uv[o[2]]];
    assert_eq!(tex::lod(&tt, &s), 512);
}

#[test]
fn textured_triangle_end_to_end() {
    let s = RasterSetup {
        width: 32,
        height: 32,
        subpixel_bits: 4,
        background: Rgb::new(0, 0, 0),
        aa: Aa::default(),
        cull: Cull::None,
        traversal: Traversal::Simd8,
    };
    let mut r = Raster::new(32, 32, &s).expect("setup");
    // 2 × 2 checker: white, red / green, blue.
    let texels: [u32; 4] = [0xffffff, 0xff0000, 0x00ff00, 0x0000ff];
    let bytes: Vec<u8> = texels.iter().flat_map(|t| t.to_le_bytes()).collect();
    r.write_texture(100, &bytes).expect("fits");
    assert!(r.write_texture(u32::MAX, &bytes).is_err());
    let tx = TexRef {
        base: 100,
        width_log2: 1,
        height_log2: 1,
        uv: [[0, 0], [65536, 0], [0, 65536]],
        wrap: Wrap::Clamp,
        filter: Filter::Nearest,
    };
    let t = Triangle {
        v: [
            Point { x: 0, y: 0 },
            Point { x: 32 * 16, y: 0 },
            Point { x: 0, y: 32 * 16 },
        ],
        shade: Shade::Flat(Rgb::new(0, 0, 0)),
        z: None,
        w: None,
        tex: Some(tx),
    };
    r.draw(&RasterCmd::Triangle(t)).expect("draw");
    assert_eq!(r.framebuffer().pixel(2, 2), Some(Rgb::new(255, 255, 255)));
    assert_eq!(r.framebuffer().pixel(20, 2), Some(Rgb::new(255, 0, 0)));
    assert_eq!(r.framebuffer().pixel(2, 20), Some(Rgb::new(0, 255, 0)));
    let far = Triangle {
        tex: Some(TexRef {
            base: (sim_target::raster::TEXTURE_WORDS - 2) as u32,
            ..tx
        }),
        ..t
    };
    assert!(
        r.draw(&RasterCmd::Triangle(far)).is_err(),
        "texture past memory is refused"
    );
}
