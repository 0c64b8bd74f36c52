//! Error budget of a format against the f64 reference on a scene (default
//! `examples/reference.toml`): where the squared error of the Q16.16 (or any) render
//! comes from — per primary-hit object, per term (scene variants with one feature
//! removed), per error size — plus a heat-map PNG of the per-pixel error.
//!
//! `cargo run --release -p sim-target --example psnr_budget -- [W H] [format] [scene] [heat.png]`
//! (`PSNR_ONLY=1`: only the PSNR line; `HEAT_CROP=x,y,w,h,zoom`: enlarge a window of the
//! heat map).
//!
//! A measuring tool for docs/rt.md, not a shipped command.

#[path = "../tests/integration/common.rs"]
mod common;

use sim_target::rt::{self, Frame, Numeric, Reflection, Scene};

/// With AOVs, culled: the render the tests compare (`tests/integration/common.rs`, shared by path).
fn render(scene: &Scene, numeric: Numeric, w: u32, h: u32) -> Frame {
    common::render_culled(scene, numeric, true, Some((w, h)))
}

fn sq_err(a: &[u8], b: &[u8]) -> Vec<f64> {
    a.chunks(3)
        .zip(b.chunks(3))
        .map(|(p, q)| {
            p.iter()
                .zip(q)
                .map(|(x, y)| {
                    let d = *x as f64 - *y as f64;
                    d * d
                })
                .sum()
        })
        .collect()
}

fn db(mse: f64) -> f64 {
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0f64 * 255.0 / mse).log10()
    }
}

/// Per pixel: index of the object the primary ray hits (None for background), from an
/// f64 render where each object is lit only by an ambient term of a distinct colour.
fn ids(scene: &Scene, w: u32, h: u32) -> Vec<Option<usize>> {
    let mut s = scene.clone();
    s.lights.clear();
    s.ambient = [1.0, 1.0, 1.0];
    s.background = [0.0, 0.0, 0.0];
    s.depth = 1;
    let n = s.objects.len();
    let mut mats = Vec::new();
    for (i, o) in s.objects.iter_mut().enumerate() {
        let mut m = scene.materials[o.material].clone();
        let level = (i + 1) as f64 * 8.0 / 255.0 + 0.5 / 255.0;
        m.ambient = Some(rt::Term {
            k: 1.0,
            color: [level, 0.0, 0.0],
        });
        m.diffuse.k = 0.0;
        m.specular = None;
        m.reflection = Reflection::None;
        m.texture = None;
        mats.push(m);
        o.material = i;
    }
    s.materials = mats;
    let f = render(&s, Numeric::F64, w, h);
    f.rgb8
        .chunks(3)
        .map(|p| {
            let k = (p[0] as usize + 4) / 8;
            (k >= 1 && k <= n).then(|| k - 1)
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let w: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(384);
    let h: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(216);
    let numeric = args
        .get(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(Numeric::Q16_16);
    let path = args
        .get(3)
        .cloned()
        .unwrap_or_else(|| "examples/reference.toml".into());
    let heat = args.get(4).cloned();
    let text = std::fs::read_to_string(&path).expect("scene file");
    let scene = jobs::scene::parse(&text, &path).expect("scene parses");
    let npx = (w * h) as f64;
    let denom = npx * 3.0;

    let r = render(&scene, Numeric::F64, w, h);
    let q = render(&scene, numeric, w, h);
    let e = sq_err(&r.rgb8, &q.rgb8);
    let total: f64 = e.iter().sum();
    println!(
        "{numeric:?} {w}x{h}: PSNR {:.2} dB (MSE {:.4})",
        db(total / denom),
        total / denom
    );

    // PSNR_ONLY=1: just the figure (for the per-format table)
    if std::env::var_os("PSNR_ONLY").is_some() {
        return;
    }

    // per object of the primary hit
    let id = ids(&scene, w, h);
    let names: Vec<String> = scene
        .objects
        .iter()
        .map(|o| format!("{:?}/{}", o.shape, scene.materials[o.material].name))
        .collect();
    let mut per: Vec<(String, f64, usize, usize)> = names
        .iter()
        .map(|n| (n.clone(), 0.0, 0, 0))
        .chain([("background".to_string(), 0.0, 0, 0)])
        .collect();
    let bg = per.len() - 1;
    for (ei, idi) in e.iter().zip(&id) {
        let k = idi.unwrap_or(bg);
        per[k].1 += ei;
        per[k].2 += 1;
        if *ei > 0.0 {
            per[k].3 += 1;
        }
    }
    per.sort_by(|a, b| b.1.total_cmp(&a.1));
    println!("\nper primary-hit object: share of squared error, pixels, pixels differing");
    for (n, s, c, d) in &per {
        println!(
            "  {n:<24} {:6.2} %  {c:7} px  {d:6} differ",
            100.0 * s / total.max(1e-300)
        );
    }

    // by size of the per-pixel error (largest channel difference)
    let maxd: Vec<u8> = r
        .rgb8
        .chunks(3)
        .zip(q.rgb8.chunks(3))
        .map(|(p, q)| {
            p.iter()
                .zip(q)
                .map(|(a, b)| a.abs_diff(*b))
                .max()
                .unwrap_or(0)
        })
        .collect();
    println!("\nby largest channel difference: share of squared error, pixels");
    for (lo, hi) in [(1u8, 2u8), (3, 8), (9, 32), (33, 255)] {
        let (mut s, mut c) = (0.0, 0);
        for (m, ei) in maxd.iter().zip(&e) {
            if *m >= lo && *m <= hi {
                s += ei;
                c += 1;
            }
        }
        println!(
            "  {lo:3}..{hi:3}: {:6.2} %  {c:7} px",
            100.0 * s / total.max(1e-300)
        );
    }

    // per term: the same scene with one feature removed, both formats re-rendered
    println!("\nvariants (f64 and {numeric:?} both re-rendered): PSNR");
    let mut variants: Vec<(String, Scene)> = Vec::new();
    let mut s = scene.clone();
    s.depth = 1;
    variants.push(("depth 1 (no reflected rays)".into(), s));
    let mut s = scene.clone();
    for m in &mut s.materials {
        m.texture = None;
    }
    variants.push(("no textures".into(), s));
    // one texture made constant (not removed: the texture count sets the texel side)
    for (i, m) in scene.materials.iter().enumerate() {
        if let Some(t) = &m.texture {
            let mut s = scene.clone();
            let mut flat = t.clone();
            flat.kind = rt::TextureKind::Checkerboard { cell: 1 << 20 };
            s.materials[i].texture = Some(flat);
            variants.push((format!("texture of {} constant", m.name), s));
        }
    }
    let mut s = scene.clone();
    s.shadows = false;
    variants.push(("no shadow rays".into(), s));
    let mut s = scene.clone();
    for m in &mut s.materials {
        m.specular = None;
    }
    variants.push(("no specular".into(), s));
    for (name, s) in &variants {
        let a = render(s, Numeric::F64, w, h);
        let b = render(s, numeric, w, h);
        println!("  {name:<36} {:6.2} dB", rt::psnr(&a.rgb8, &b.rgb8));
    }

    // first-hit geometry: depth and normal AOV error
    if let (Some(da), Some(db_), Some(na), Some(nb)) = (&r.depth, &q.depth, &r.normal, &q.normal) {
        let mut worst_t = 0.0f64;
        let mut worst_n = 0.0f64;
        let mut mism = 0;
        for i in 0..da.len() {
            if da[i].is_finite() != db_[i].is_finite() {
                mism += 1;
                continue;
            }
            if da[i].is_finite() {
                worst_t = worst_t.max(((da[i] - db_[i]) as f64).abs());
                for c in 0..3 {
                    worst_n = worst_n.max(((na[3 * i + c] - nb[3 * i + c]) as f64).abs());
                }
            }
        }
        println!("\nAOVs: hit/miss mismatches {mism}, worst |Δt| {worst_t:.3e}, worst |Δn| {worst_n:.3e}");
    }

    if let Some(p) = heat {
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            let i = (y * w + x) as usize;
            let m = maxd[i];
            if m == 0 {
                let g = r.rgb8[3 * i..3 * i + 3]
                    .iter()
                    .map(|v| *v as u32)
                    .sum::<u32>()
                    / 12;
                image::Rgb([g as u8, g as u8, g as u8])
            } else if m <= 2 {
                image::Rgb([0, 90, 255])
            } else if m <= 8 {
                image::Rgb([0, 220, 0])
            } else if m <= 32 {
                image::Rgb([255, 200, 0])
            } else {
                image::Rgb([255, 0, 0])
            }
        });
        // HEAT_CROP=x,y,w,h,zoom: write only that window, enlarged (for looking at flips)
        let img = match std::env::var("HEAT_CROP").ok().map(|c| {
            c.split(',')
                .filter_map(|v| v.parse::<u32>().ok())
                .collect::<Vec<_>>()
        }) {
            Some(c) if c.len() == 5 => {
                let sub = image::imageops::crop_imm(&img, c[0], c[1], c[2], c[3]).to_image();
                image::imageops::resize(
                    &sub,
                    c[2] * c[4],
                    c[3] * c[4],
                    image::imageops::FilterType::Nearest,
                )
            }
            _ => img,
        };
        img.save(&p).expect("writes the heat map");
        println!(
            "\nheat map: {p} (grey = equal, blue ≤ 2, green ≤ 8, yellow ≤ 32, red > 32 levels)"
        );
    }
}
