//! Scene → registers → scene: what the device renders from the register image must be the
//! scene the file described, up to Q16.16 quantisation.

use jobs::scene::to_regs;
use sim_target::rt::{self, Numeric, RenderOptions};
use sim_target::scene_regs::{from_regs, Regs};

fn reference() -> rt::Scene {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/reference.toml"
    ))
    .expect("examples/reference.toml");
    jobs::scene::parse(&text, "reference.toml").expect("reference parses")
}

#[test]
fn register_round_trip_is_exact_after_one_quantisation() {
    let scene = reference();
    let regs = to_regs(&scene).expect("fits the default map");
    let back = from_regs(&regs).expect("decodes");
    // A second pass changes nothing: the register image is a fixed point.
    let again = to_regs(&back).expect("fits");
    assert_eq!(regs, again);
    assert_eq!(back.objects.len(), scene.objects.len());
    assert_eq!(back.lights.len(), scene.lights.len());
    // Values moved by at most half a Q16.16 step.
    let step = 0.5 / 65536.0 + 1e-12;
    assert!((back.camera.fov_y - scene.camera.fov_y).abs() <= step);
    for (a, b) in back.objects.iter().zip(&scene.objects) {
        for k in 0..3 {
            assert!((a.translate[k] - b.translate[k]).abs() <= step);
            assert!((a.scale[k] - b.scale[k]).abs() <= step);
        }
        assert_eq!(a.shape, b.shape);
        let (ma, mb) = (&back.materials[a.material], &scene.materials[b.material]);
        assert_eq!(ma.specular.is_some(), mb.specular.is_some());
        assert_eq!(ma.texture.is_some(), mb.texture.is_some());
        assert_eq!(
            std::mem::discriminant(&ma.reflection),
            std::mem::discriminant(&mb.reflection)
        );
    }
    // The words survive the trip through the flat image the device holds.
    let words: Vec<u32> = regs.words().collect();
    assert_eq!(Regs::from_words(&words).expect("valid image"), regs);
}

#[test]
fn rendering_from_registers_matches_the_file() {
    let scene = reference();
    let via_regs = from_regs(&to_regs(&scene).expect("fits")).expect("decodes");
    let opts = RenderOptions {
        numeric: Numeric::F64,
        size: Some((192, 108)),
        ..Default::default()
    };
    let a = rt::render(&scene, &opts).expect("renders");
    let b = rt::render(&via_regs, &opts).expect("renders");
    let psnr = rt::psnr(&a.rgb8, &b.rgb8);
    // Q16.16 moves colours by < 1e-5 and positions by < 8e-6: only edge pixels may flip.
    assert!(
        psnr > 40.0,
        "PSNR {psnr:.1} dB between file and register scene"
    );
}

#[test]
fn too_many_objects_is_an_error_naming_the_limit() {
    let mut scene = reference();
    let extra = scene.objects[0].clone();
    scene.objects.push(extra);
    let err = to_regs(&scene)
        .expect_err("9 objects exceed OBJ_NUM = 8")
        .to_string();
    assert!(err.contains('9') && err.contains('8'), "{err}");
}
