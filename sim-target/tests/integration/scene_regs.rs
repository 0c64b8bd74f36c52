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

#[test]
fn the_hosts_derived_words_are_the_models_and_a_stale_one_is_named() {
    use protocol::scene::{cam, obj};
    use sim_target::scene_regs::{check_derived, SceneRegsError};
    let mut scene = reference();
    // a rotated object, so that M⁻¹ has off-diagonal words
    scene.objects[1].rotate = [30.0, -45.0, 10.0];
    let regs = to_regs(&scene).expect("fits");
    check_derived(&regs).expect("the host derives what the model derives");
    // the model's own numbers, rounded as the kernel rounds them, are the words
    let held = from_regs(&regs).expect("decodes");
    let m = rt::derive::inverse_linear(held.objects[1].rotate, held.objects[1].scale);
    let at = Regs::object_offset(1) + obj::MINV;
    assert_eq!(
        regs.word(at + 1),
        Some(protocol::scene::ValueFormat::Q16_16.encode_saturating(m[0][1]))
    );
    assert_ne!(regs.word(at + 1), Some(0), "rotated: an off-diagonal word");
    let pitch = rt::derive::pitch(held.camera.fov_y, held.height, held.spp);
    assert_eq!(regs.camera().pitch, pitch);

    // a controller-side ramp of the camera position leaves the basis stale
    let mut moved = regs.clone();
    let x = cam::OFFSET + cam::POSITION;
    let w = moved.word(x).expect("in the map");
    moved
        .write(x, &[w.wrapping_add(3 << 16)])
        .expect("in the map");
    let err = check_derived(&moved).expect_err("stale basis");
    assert!(
        matches!(&err, SceneRegsError::Derived { field, .. } if field.starts_with("camera.")),
        "{err}"
    );
    // one LSB off in an inverse transform word is named with its object
    let mut off = regs.clone();
    let v = off.word(at + 4).expect("in the map");
    off.write(at + 4, &[v ^ 1]).expect("in the map");
    let err = check_derived(&off).expect_err("wrong M⁻¹");
    assert_eq!(
        err.to_string().split(" (word").next(),
        Some("object 1 minv[1][1]"),
        "{err}"
    );
    // the pitch's high word
    let mut wide = regs.clone();
    let p = cam::OFFSET + cam::PITCH + 1;
    wide.write(p, &[1]).expect("in the map");
    let err = check_derived(&wide).expect_err("wrong pitch");
    assert!(
        err.to_string().starts_with("camera.pitch (high word)"),
        "{err}"
    );
}

/// A register image the device did not build is checked word by word before it renders:
/// a corrupt frame size, depth or sample count is an error naming the field, never a
/// frame of 2³² columns (which overflowed the tile grid's arithmetic and panicked, found
/// by setting each word of an image to all ones through the Python package).
#[test]
fn a_corrupt_frame_word_is_refused_by_name_not_rendered() {
    use protocol::scene::hdr;
    let regs = to_regs(&reference()).expect("fits");
    let words: Vec<u32> = regs.words().collect();
    for (field, at, value) in [
        ("width", hdr::WIDTH, u32::MAX),
        ("width", hdr::WIDTH, 0),
        ("height", hdr::HEIGHT, 70_000),
        ("depth", hdr::DEPTH, 17),
        ("spp", hdr::SPP, 0),
    ] {
        let mut bad = words.clone();
        bad[at] = value;
        let image = Regs::from_words(&bad).expect("a whole image");
        let e = from_regs(&image).expect_err(field).to_string();
        assert!(e.contains(&format!("`{field}` = {value}")), "{field}: {e}");
        let mut device = sim_target::Device::new(&protocol::bus::WIDE);
        device.write_regs(0, &bad).expect("in the register file");
        let start = protocol::frame::StartFrame {
            frame_id: 1,
            block: protocol::frame::Block::RayTrace,
            numeric: Numeric::Q16_16,
            auto_restart: false,
            aovs: false,
        };
        let e = device.start(&start).expect_err(field).to_string();
        assert!(e.contains(field), "{field}: {e}");
    }
}

/// In range for the register map but past the protocol's frame side: the model refuses
/// it rather than allocate planes no target reads back.
#[test]
fn a_frame_past_the_protocols_side_is_refused() {
    let mut scene = reference();
    scene.width = protocol::MAX_FRAME_SIDE + 1;
    let e = rt::render(&scene, &RenderOptions::default()).expect_err("too wide");
    assert!(e.to_string().contains("larger than 4096 per side"), "{e}");
}
