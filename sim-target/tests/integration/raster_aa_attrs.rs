//! The anti-aliased triangle path honours the z-buffer and textures (docs/requirements.md §3): depth is
//! tested once per pixel at its centre, the texture is sampled at the centre, and the
//! result is blended by the sample coverage.

use protocol::raster::*;
use sim_target::raster::{aa, Raster, Z_FAR};

const BITS: u8 = 4;
const N: u32 = 32;

fn setup(pattern: AaPattern, samples: u8) -> RasterSetup {
    RasterSetup {
        width: N as u16,
        height: N as u16,
        subpixel_bits: BITS,
        background: Rgb::new(0, 0, 0),
        aa: Aa { pattern, samples },
        cull: Cull::None,
        traversal: Traversal::Scanline,
    }
}

/// Sub-pixel point from pixel units.
fn p(x: f64, y: f64) -> Point {
    let s = (1 << BITS) as f64;
    Point {
        x: (x * s).round() as i32,
        y: (y * s).round() as i32,
    }
}

fn tri(v: [Point; 3], color: Rgb, z: Option<[u32; 3]>, tex: Option<TexRef>) -> RasterCmd {
    RasterCmd::Triangle(Triangle {
        v,
        shade: Shade::Flat(color),
        z,
        w: None,
        tex,
    })
}

/// A triangle covering the whole framebuffer.
fn cover_all(color: Rgb, z: u32) -> RasterCmd {
    tri(
        [p(-1.0, -1.0), p(70.0, -1.0), p(-1.0, 70.0)],
        color,
        Some([z; 3]),
        None,
    )
}

const NEAR_V: [(f64, f64); 3] = [(3.3, 2.7), (27.6, 9.1), (8.2, 29.4)];

fn near_v() -> [Point; 3] {
    NEAR_V.map(|(x, y)| p(x, y))
}

/// Coverage (samples inside, of n) of the near triangle at every pixel.
fn coverage(pattern: AaPattern, samples: u8) -> Vec<(u32, u32, u32, u32)> {
    let offs = aa::pattern(pattern, samples);
    let v = near_v();
    let mut out = Vec::new();
    for j in 0..N {
        for i in 0..N {
            let k = aa::covered(&v, BITS, &offs, i as i64, j as i64);
            out.push((i, j, k, offs.len() as u32));
        }
    }
    out
}

#[test]
fn aa_triangles_are_depth_tested() {
    let green = Rgb::new(0, 255, 0);
    let red = Rgb::new(255, 0, 0);
    for (pattern, samples) in [(AaPattern::Regular, 16), (AaPattern::Rotated, 4)] {
        let mut r = Raster::new(N, N, &setup(pattern, samples)).expect("setup");
        // Near first, then a far triangle over everything: where the near one covered
        // a pixel centre (and so wrote depth), the far one must not show through.
        r.draw(&tri(near_v(), green, Some([1000; 3]), None))
            .expect("draw");
        r.draw(&cover_all(red, 5000)).expect("draw");
        let fb = r.framebuffer();
        let mut full = 0;
        for (i, j, k, n) in coverage(pattern, samples) {
            let px = fb.pixel(i, j).expect("inside");
            let d = fb.depth()[(j * N + i) as usize];
            if k == n {
                full += 1;
                assert_eq!(px, green, "{pattern:?}: covered pixel ({i}, {j})");
                assert_eq!(d, 1000, "{pattern:?}: depth at ({i}, {j})");
            } else if k == 0 {
                assert_eq!(px, red, "{pattern:?}: uncovered pixel ({i}, {j})");
                assert_eq!(d, 5000);
            } else {
                // Edge pixels: the near triangle wrote its depth there, so the far one
                // is hidden and the pixel keeps green blended over the background.
                assert_eq!(d, 1000);
                assert_eq!(px.r, 0, "{pattern:?}: far colour leaked at ({i}, {j})");
                assert_eq!(px.g as u32, (255 * k + n / 2) / n);
            }
        }
        assert!(full > 100, "the near triangle covers many whole pixels");

        // Far first, near second: the near one passes everywhere it has coverage.
        let mut r = Raster::new(N, N, &setup(pattern, samples)).expect("setup");
        r.draw(&cover_all(red, 5000)).expect("draw");
        r.draw(&tri(near_v(), green, Some([1000; 3]), None))
            .expect("draw");
        for (i, j, k, n) in coverage(pattern, samples) {
            let px = r.framebuffer().pixel(i, j).expect("inside");
            let (g, rd) = ((255 * k + n / 2) / n, (255 * (n - k) + n / 2) / n);
            assert_eq!((px.r as u32, px.g as u32), (rd, g), "({i}, {j})");
        }
    }
}

#[test]
fn aa_depth_is_a_convex_combination_at_edge_pixels() {
    // Depth varying across the triangle: every written depth lies within the vertices'
    // range, including edge pixels whose centre is outside (clamped weights).
    let z = [100_000, 3_000_000, 9_000_000];
    let mut r = Raster::new(N, N, &setup(AaPattern::Regular, 16)).expect("setup");
    r.draw(&tri(near_v(), Rgb::new(9, 9, 9), Some(z), None))
        .expect("draw");
    let mut written = 0;
    for (i, j, k, _) in coverage(AaPattern::Regular, 16) {
        let d = r.framebuffer().depth()[(j * N + i) as usize];
        if k == 0 {
            assert_eq!(d, Z_FAR);
        } else {
            written += 1;
            assert!((100_000..=9_000_000).contains(&d), "({i}, {j}): {d}");
        }
    }
    assert!(written > 200);
    // Inside pixel centres get the same depth as the aliased path.
    let mut al = Raster::new(N, N, &setup(AaPattern::None, 0)).expect("setup");
    al.draw(&tri(near_v(), Rgb::new(9, 9, 9), Some(z), None))
        .expect("draw");
    let mut same = 0;
    for (k, (&a, &b)) in al
        .framebuffer()
        .depth()
        .iter()
        .zip(r.framebuffer().depth())
        .enumerate()
    {
        if a != Z_FAR {
            assert_eq!(a, b, "pixel {k}");
            same += 1;
        }
    }
    assert!(same > 200);
}

#[test]
fn aa_triangles_are_textured() {
    // 4 × 4 texture of distinct colours, nearest, mapped once over the triangle.
    let texels: Vec<u32> = (0..16u32)
        .map(|k| (k * 16) << 16 | (255 - k * 15) << 8 | (k * 7 + 40))
        .collect();
    let bytes: Vec<u8> = texels.iter().flat_map(|t| t.to_le_bytes()).collect();
    let tx = TexRef {
        base: 64,
        width_log2: 2,
        height_log2: 2,
        uv: [[0, 0], [65536, 0], [0, 65536]],
        wrap: Wrap::Clamp,
        filter: Filter::Nearest,
    };
    // The flat colour must not be what ends up in the framebuffer.
    let flat = Rgb::new(255, 0, 255);
    let cmd = tri(near_v(), flat, None, Some(tx));
    let mut al = Raster::new(N, N, &setup(AaPattern::None, 0)).expect("setup");
    al.write_texture(64, &bytes).expect("fits");
    al.draw(&cmd).expect("draw");
    let mut r = Raster::new(N, N, &setup(AaPattern::Regular, 16)).expect("setup");
    r.write_texture(64, &bytes).expect("fits");
    r.draw(&cmd).expect("draw");
    let mut colours = std::collections::BTreeSet::new();
    let mut full = 0;
    for (i, j, k, n) in coverage(AaPattern::Regular, 16) {
        let got = r.framebuffer().pixel(i, j).expect("inside");
        if k == n {
            // Fully covered pixels have their centre inside: the aliased path's texel.
            let want = al.framebuffer().pixel(i, j).expect("inside");
            assert_eq!(got, want, "({i}, {j})");
            assert_ne!(got, flat);
            colours.insert((got.r, got.g, got.b));
            full += 1;
        } else if k > 0 {
            // Partial pixels blend a texel (never the flat colour) over black: each
            // channel is some texel channel scaled by k/n.
            let scaled = |c: u32| (c * k + n / 2) / n;
            let ok = texels.iter().any(|&t| {
                got == Rgb::new(
                    scaled(t >> 16) as u8,
                    scaled(t >> 8 & 0xff) as u8,
                    scaled(t & 0xff) as u8,
                )
            });
            assert!(ok, "({i}, {j}) = {got:?} at {k}/{n} is no scaled texel");
        }
    }
    assert!(full > 100);
    assert!(colours.len() >= 6, "the texture varies over the triangle");
}

#[test]
fn aa_without_z_or_texture_is_unchanged() {
    // The flat path must not touch depth (the hook returns the colour unchanged).
    let mut r = Raster::new(N, N, &setup(AaPattern::Jitter, 4)).expect("setup");
    r.draw(&tri(near_v(), Rgb::new(200, 100, 50), None, None))
        .expect("draw");
    assert!(r.framebuffer().depth().iter().all(|&d| d == Z_FAR));
    for (i, j, k, n) in coverage(AaPattern::Jitter, 4) {
        let px = r.framebuffer().pixel(i, j).expect("inside");
        let s = |c: u32| ((c * k + n / 2) / n) as u8;
        assert_eq!(px, Rgb::new(s(200), s(100), s(50)), "({i}, {j})");
    }
}
