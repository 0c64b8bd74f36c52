struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    fn sign(&mut self) -> f64 {
        if self.next() < 0.5 {
            -1.0
        } else {
            1.0
        }
    }
}
use sim_target::num::{Scalar, Q16_16};
use sim_target::rt::{shapes, vec::V3, Math};

fn culled(o: [f64; 3], d: [f64; 3], r2: f64) -> bool {
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let od = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
    let t = (-od / dd).max(0.0);
    let p = [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
    p[0] * p[0] + p[1] * p[1] + p[2] * p[2] > r2
}

fn probe<S: Scalar>(cone: bool, n: usize) -> usize {
    let m = Math::default();
    let mut rng = Rng(1);
    let mut bad = 0;
    let mut ncull = 0;
    for _ in 0..n {
        let o = if cone {
            [
                rng.range(-1.6, 1.6),
                rng.range(-1.5, 1.5),
                rng.range(-1.6, 1.6),
            ]
        } else {
            let (th, r) = (rng.range(0.0, 6.3), rng.range(1.03, 1.3));
            [
                r * th.cos(),
                rng.sign() * rng.range(0.85, 1.0),
                r * th.sin(),
            ]
        };
        let eps: f64 = 10f64.powf(rng.range(-6.0, -1.0));
        let mut d = if cone {
            let th: f64 = rng.range(0.0, std::f64::consts::TAU);
            [th.cos() + eps * rng.range(-1.0, 1.0), rng.sign(), th.sin()]
        } else {
            [
                eps * rng.range(-1.0, 1.0),
                o[1].signum(),
                eps * rng.range(-1.0, 1.0),
            ]
        };
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        d = d.map(|v| v / l);
        let (os, ds) = (V3::<S>::from_f64(o), V3::<S>::from_f64(d));
        let (oe, de) = (os.to_f64(), ds.to_f64());
        let r2 = if cone { 1.0404 } else { 2.0808 };
        if !culled(oe, de, r2) {
            continue;
        }
        ncull += 1;
        let hit = if cone {
            shapes::cone(os, ds, S::from_f64(0.001), S::from_f64(1e6), &m)
        } else {
            shapes::cylinder(os, ds, S::from_f64(0.001), S::from_f64(1e6), &m)
        };
        if let Some(t) = hit {
            bad += 1;
            if bad < 5 {
                println!("{} cone={cone} o={oe:?} d={de:?} t={}", S::NAME, t.to_f64());
            }
        }
    }
    println!("{} cone={cone} culled {ncull}", S::NAME);
    bad
}

#[test]
fn probe_near_axis() {
    for cone in [false, true] {
        println!(
            "q16 {} f32 {}",
            probe::<Q16_16>(cone, 2_000_000),
            probe::<f32>(cone, 2_000_000)
        );
    }
}

#[test]
fn print_candidates() {
    use sim_target::num::{Q32_32, Q8_24};
    use sim_target::rt::{primary_candidates, scene_file};
    let scene = scene_file::parse(include_str!("../../examples/reference.toml"), "r").unwrap();
    let m = Math::default();
    println!(
        "f64 {:.3} f32 {:.3} q16 {:.3} q8.24 {:.3} q32 {:.3}",
        primary_candidates::<f64>(&scene, 1920, 1080, &m),
        primary_candidates::<f32>(&scene, 1920, 1080, &m),
        primary_candidates::<Q16_16>(&scene, 1920, 1080, &m),
        primary_candidates::<Q8_24>(&scene, 1920, 1080, &m),
        primary_candidates::<Q32_32>(&scene, 1920, 1080, &m),
    );
}

#[test]
fn print_bounds() {
    use sim_target::num::{Q32_32, Q8_24};
    use sim_target::rt::{cull, scene_file};
    let scene = scene_file::parse(include_str!("../../examples/reference.toml"), "r").unwrap();
    let m = Math::default();
    let show = |name: &str, b: Vec<Option<cull::Bound>>| {
        for (o, b) in scene.objects.iter().zip(b) {
            println!(
                "{name} {:?}: {:?}",
                o.shape,
                b.map(|b| (b.safe_distance, b.primary.map(|p| p.a_min)))
            );
        }
    };
    show("f32", cull::bounds::<f32>(&scene, &m));
    show("q16", cull::bounds::<Q16_16>(&scene, &m));
    show("q8.24", cull::bounds::<Q8_24>(&scene, &m));
    show("q32", cull::bounds::<Q32_32>(&scene, &m));
}
