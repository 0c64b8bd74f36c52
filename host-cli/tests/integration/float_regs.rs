//! The register image's value format and the device's saturation counter, through
//! `--port builtin`: an f64 frame of an analytic scene lands on the exact geometry when
//! the target takes binary32 registers (and misses it through Q16.16 ones), and
//! `fpgfx render --stats` reports the clipped results of a fixed-point frame.

use host_cli::run::render::{scene_regs, Aovs, Packing, Renderer};
use host_cli::session::Session;
use protocol::frame::Numeric;
use protocol::scene::ValueFormat;

use crate::common::{self, ok};

/// Two spheres over a plane, every value chosen off the Q16.16 grid (as a user's scene's
/// values are), so that quantising them shows in the depth.
const ANALYTIC: &str = r#"
[render]
size = [64, 48]
depth = 1
bias = 0.001
max_distance = 1e6
background = [0.0, 0.0, 0.0]

[camera]
position = [0.13, 1.37, 6.21]
look_at  = [0.07, 0.31, -0.17]
up       = [0.0, 1.0, 0.0]
fov_y    = 41.3

[ambient]
color = [0.2, 0.2, 0.2]

[material.m]
diffuse = { k = 0.8, color = [0.7, 0.7, 0.7] }

[[object]]
shape = "sphere"
translate = [0.31, 0.23, -0.47]
scale = [1.13, 1.13, 1.13]
material = "m"

[[object]]
shape = "sphere"
translate = [-1.71, -0.39, 0.83]
scale = [0.61, 0.61, 0.61]
material = "m"

[[object]]
shape = "plane"
translate = [0.0, -1.07, 0.0]
material = "m"
"#;

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

/// The exact distance to the first hit of each pixel's centre ray, from the scene file's
/// own values in f64, or `None` where the answer is ill-conditioned: a ray within 1 % of
/// a sphere's silhouette, or meeting the plane at a grazing angle, turns a rounding of
/// the camera into a large depth change, which says nothing about the datapath.
fn exact_depth(scene: &sim_target::rt::Scene) -> Vec<Option<f64>> {
    let c = &scene.camera;
    let w = normalize(sub(c.position, c.look_at));
    let u = normalize(cross(c.up, w));
    let v = cross(w, u);
    let s = (c.fov_y.to_radians() / 2.0).tan();
    let (wf, hf) = (f64::from(scene.width), f64::from(scene.height));
    let mut out = Vec::new();
    for j in 0..scene.height {
        for i in 0..scene.width {
            let x = (2.0 * (f64::from(i) + 0.5) / wf - 1.0) * s * wf / hf;
            let y = (1.0 - 2.0 * (f64::from(j) + 0.5) / hf) * s;
            let d = normalize([
                x * u[0] + y * v[0] - w[0],
                x * u[1] + y * v[1] - w[1],
                x * u[2] + y * v[2] - w[2],
            ]);
            let mut best: Option<(f64, bool)> = None;
            for o in &scene.objects {
                let (t, ok) = match o.shape {
                    protocol::scene::Shape::Sphere => {
                        let r = o.scale[0];
                        let oc = sub(c.position, o.translate);
                        let b = dot(oc, d);
                        let disc = b * b - (dot(oc, oc) - r * r);
                        if disc < 0.0 {
                            continue;
                        }
                        (-b - disc.sqrt(), disc > 0.01 * r * r)
                    }
                    _ => {
                        let t = (o.translate[1] - c.position[1]) / d[1];
                        (t, d[1].abs() > 0.1)
                    }
                };
                if t > scene.bias && best.is_none_or(|(b, _)| t < b) {
                    best = Some((t, ok));
                }
            }
            out.push(best.and_then(|(t, ok)| ok.then_some(t)));
        }
    }
    out
}

/// Largest relative depth error over the well-conditioned hit pixels, and their number.
fn worst_relative_error(depth: &[f32], exact: &[Option<f64>]) -> (f64, usize) {
    assert_eq!(depth.len(), exact.len());
    let mut worst = 0.0f64;
    let mut n = 0;
    for (&got, want) in depth.iter().zip(exact) {
        if let Some(t) = want {
            worst = worst.max((f64::from(got) - t).abs() / t);
            n += 1;
        }
    }
    (worst, n)
}

#[test]
fn binary32_registers_put_an_f64_render_on_the_exact_geometry() {
    let scene = jobs::scene::parse(ANALYTIC, "analytic.toml").expect("parses");
    let exact = exact_depth(&scene);
    let mut session = Session::new(sim_board::in_process::sim_target());
    session.handshake().expect("handshake");
    let aovs = Aovs {
        depth: true,
        normal: false,
    };
    let mut renderer = Renderer::new();
    // What `fpgfx render --numeric f64 --port builtin` sends: the target's caps ask for
    // binary32 registers for its f64 datapath.
    let regs = scene_regs(&session, &scene, Numeric::F64).expect("fits");
    assert_eq!(regs.value_format(), ValueFormat::Binary32);
    let (out, _) = renderer
        .frame(&mut session, &regs, Numeric::F64, Packing::Rgb888, aovs)
        .expect("renders");
    let (float_err, n) = worst_relative_error(out.depth.as_deref().expect("depth"), &exact);
    // The old path: the same frame from Q16.16 registers.
    let q16 = jobs::scene::to_regs_as(&scene, ValueFormat::Q16_16).expect("fits");
    let (out, _) = renderer
        .frame(&mut session, &q16, Numeric::F64, Packing::Rgb888, aovs)
        .expect("renders");
    let (q16_err, _) = worst_relative_error(out.depth.as_deref().expect("depth"), &exact);
    println!(
        "worst relative depth error over {n} pixels: binary32 registers {float_err:.3e}, \
         Q16.16 registers {q16_err:.3e}"
    );
    assert!(n > 1000, "only {n} well-conditioned hit pixels");
    assert!(float_err <= 1e-6, "binary32 registers: {float_err:e}");
    assert!(q16_err > 1e-6, "Q16.16 registers: {q16_err:e}");
}

/// The clipped-result count of `fpgfx --port builtin render` of the reference scene in
/// `numeric`, as `--stats` prints it.
fn saturations(numeric: &str) -> u64 {
    let png = common::tmp(&format!("sat-{numeric}.png"));
    let run = ok(&[
        "--port",
        "builtin",
        "render",
        &common::example("reference.toml"),
        "--numeric",
        numeric,
        "--size",
        "96x54",
        "--stats",
        "-o",
        &png,
    ]);
    let line = run
        .stdout
        .lines()
        .find(|l| l.starts_with("saturations"))
        .unwrap_or_else(|| panic!("no saturations line in:\n{}", run.stdout));
    line.split_whitespace()
        .nth(1)
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("unreadable count: {line}"))
}

/// The count of the same frame rendered directly from the image the built-in target
/// gets (the device renders the scene its registers hold).
fn direct_saturations(numeric: Numeric) -> u64 {
    let text = std::fs::read_to_string(common::example("reference.toml")).expect("reads");
    let mut scene = jobs::scene::parse(&text, "reference.toml").expect("parses");
    (scene.width, scene.height) = (96, 54);
    let caps = sim_target::Device::new(&protocol::bus::WIDE).caps();
    let regs =
        jobs::scene::to_regs_as(&scene, ValueFormat::for_caps(&caps, numeric)).expect("fits");
    let held = sim_target::scene_regs::from_regs(&regs).expect("decodes");
    let opts = sim_target::rt::RenderOptions {
        numeric,
        ..Default::default()
    };
    sim_target::rt::render(&held, &opts)
        .expect("renders")
        .stats
        .saturations
}

#[test]
fn render_stats_count_the_devices_saturations() {
    // Q8.24's ±128 cannot hold the reference scene's light intensity (160): the device
    // clips all over the frame, and says so.
    let q8 = saturations("q8.24");
    println!("reference 96x54 through --port builtin: q8.24 {q8} saturations");
    assert!(q8 > 1000, "q8.24: {q8}");
    assert_eq!(q8, direct_saturations(Numeric::Q8_24));
    // Q16.16 clips three results of the frame (measured; `Probe` agrees, see
    // sim-target's saturation tests); floats do not saturate.
    assert_eq!(saturations("q16.16"), 3);
    assert_eq!(saturations("f32"), 0);
}
