//! The frame core `rt_cast` against the golden model rendering the same register image in
//! Q16.16 with its AOV planes: for every pixel the same colour, the same hit or miss, the
//! same object, the same depth and the same normal, bit for bit, and the frame's cycle
//! count by the model's formula for the core (`sim_target::rt::core`). Materials: Lambert
//! with or without an ambient term and a Blinn-Phong highlight (exponents 0 to 1023), one
//! point light or none, lights bright enough to clip, backgrounds beyond [0, 1], hard
//! shadows on in most scenes.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rt_core_rtl_sim::{Cast, CastFrame};
use sim_target::rt::core::CoreFrame;
use sim_target::rt::{self, DiffuseModel, Reflection, Scene};

use super::scenes::{compare, expected_cycles, model, scene};
use super::waves::Waves;

/// Scene `s` on a fresh core (`trace`: its waveform from the load on), held to the model:
/// the first difference.
fn fresh_frame(s: &Scene, trace: impl FnOnce(&mut Cast)) -> Result<(), String> {
    let (words, m) = model(s);
    let mut core = Cast::new().expect("Verilated rt_cast");
    trace(&mut core);
    core.load(&words).map_err(|e| e.to_string())?;
    let frame = core.render(1 << 22, |_| false).map_err(|e| e.to_string())?;
    if frame.err != 0 {
        return Err(format!("the core refused it: err {:#010b}", frame.err));
    }
    compare(&frame, &m)?;
    if frame.cycles != expected_cycles(s) {
        return Err(format!(
            "{} cycles, the model's formula {}",
            frame.cycles,
            expected_cycles(s)
        ));
    }
    Ok(())
}

/// After scene `k` (`s`) failed in the run: the smallest of a few sizes of it (its
/// objects, camera and lights kept) that fails on a fresh core too, as a case to replay
/// (`scene K at WxH`) with its first difference: a frame of a few pixels instead of
/// hundreds, and no run before it.
fn shrink_scene(k: u32, s: &Scene) -> Option<(String, String)> {
    [
        (2, 2),
        (4, 3),
        (s.width / 2, s.height / 2),
        (s.width, s.height),
    ]
    .into_iter()
    .filter(|&(w, h)| (2..=s.width).contains(&w) && (2..=s.height).contains(&h))
    .find_map(|(w, h)| {
        let sized = Scene {
            width: w,
            height: h,
            ..s.clone()
        };
        let why = fresh_frame(&sized, |_| {}).err()?;
        Some((format!("scene {k} at {w}x{h}"), why))
    })
}

#[test]
fn generated_scenes_give_the_models_aov_planes() {
    let waves = Waves::new("cast::generated_scenes_give_the_models_aov_planes");
    let mut rng = SmallRng::seed_from_u64(0x7274_6361);
    // a shrunk case: that scene at that size on a fresh core
    let shrunk = waves.replaying().and_then(|c| {
        let (k, size) = c.strip_prefix("scene ")?.split_once(" at ")?;
        let (w, h) = size.split_once('x')?;
        Some((k.parse::<u32>().ok()?, w.parse().ok()?, h.parse().ok()?))
    });
    if let (Some(case), Some((k, width, height))) = (waves.replaying(), shrunk) {
        let s = (0..=k).map(|k| scene(&mut rng, k % 8)).last();
        let s = Scene {
            width,
            height,
            ..s.expect("scene k")
        };
        match fresh_frame(&s, |core| waves.before(case, core)) {
            Ok(()) => waves.passed(case),
            Err(e) => waves.fail(case, &e),
        }
        return;
    }
    let mut core = Cast::new().expect("Verilated rt_cast");
    let (mut pixels, mut hits, mut mid, mut shadowed) = (0usize, 0usize, 0usize, 0usize);
    let mut shapes_hit = [0usize; 7];
    let mut slots = std::collections::BTreeSet::new();
    for k in 0..300u32 {
        let s = scene(&mut rng, k % 8);
        let (words, m) = model(&s);
        if s.shadows {
            // pixels a shadow changed: the model's frame without shadows differs there
            let (_, lit) = model(&Scene {
                shadows: false,
                ..s.clone()
            });
            shadowed += m
                .rgb8
                .chunks(3)
                .zip(lit.rgb8.chunks(3))
                .filter(|(a, b)| a != b)
                .count();
            slots.insert(CoreFrame::of(&s).slot());
        }
        let case = format!("scene {k}");
        waves.before(&case, &mut core);
        let frame = waves.case_or(
            &case,
            || {
                core.load(&words).expect("image fits");
                let frame = core.render(1 << 22, |_| false).expect("frame completes");
                assert_eq!(frame.err, 0, "scene {k}: the core refused it");
                if let Err(e) = compare(&frame, &m) {
                    panic!("scene {k} (class {}): {e}\n{s:#?}", k % 8);
                }
                assert_eq!(frame.cycles, expected_cycles(&s), "scene {k}: cycles");
                frame
            },
            || shrink_scene(k, &s),
        );
        pixels += frame.pixels.len();
        for p in frame.pixels.iter().filter(|p| p.hit) {
            hits += 1;
            // a colour neither black nor clipped in some channel: the shading's arithmetic
            // showed, not only its clamps
            mid += usize::from(p.rgb.iter().any(|c| (1..=254).contains(c)));
            shapes_hit[s.objects[usize::from(p.obj)].shape.code() as usize] += 1;
        }
    }
    eprintln!(
        "{pixels} pixels, {hits} hits ({mid} in mid-tones, {shadowed} in shadow), per shape \
         {shapes_hit:?}, shadow slots of {slots:?} clocks"
    );
    assert!(hits * 5 > pixels, "too few hits: {hits} of {pixels}");
    assert!(
        shadowed * 10 > hits,
        "too few shadowed pixels: {shadowed} of {hits}"
    );
    assert!(
        slots.contains(&2),
        "no scene with the shortest slot (one object, one light)"
    );
    assert!(mid * 2 > hits, "too few mid-tone hits: {mid} of {hits}");
    assert!(
        shapes_hit.iter().all(|&n| n > 200),
        "a shape is hit too rarely: {shapes_hit:?}"
    );
}

#[test]
fn holding_the_core_changes_nothing_but_time() {
    let waves = Waves::new("cast::holding_the_core_changes_nothing_but_time");
    let mut rng = SmallRng::seed_from_u64(0x686f_6c64);
    let mut core = Cast::new().expect("Verilated rt_cast");
    for k in 0..6u32 {
        let s = scene(&mut rng, k % 4);
        let (words, m) = model(&s);
        let case = format!("scene {k}");
        waves.before(&case, &mut core);
        waves.case(&case, || {
            core.load(&words).expect("image fits");
            let mut held = 0u64;
            let mut hold_rng = SmallRng::seed_from_u64(u64::from(k));
            let frame = core
                .render(1 << 22, |_| {
                    let h = hold_rng.gen_bool(0.3);
                    held += u64::from(h);
                    h
                })
                .expect("frame completes");
            if let Err(e) = compare(&frame, &m) {
                panic!("scene {k} under holds: {e}");
            }
            assert_eq!(
                frame.cycles,
                expected_cycles(&s) + held,
                "scene {k}: every held edge adds one cycle"
            );
        });
    }
}

/// A change to a scene.
type Edit = Box<dyn Fn(&mut Scene)>;

/// Each scene feature the core does not build raises its own refusal bit.
#[test]
fn what_the_core_does_not_build_is_refused() {
    let waves = Waves::new("cast::what_the_core_does_not_build_is_refused");
    let mut rng = SmallRng::seed_from_u64(0x7265_6675);
    let mut core = Cast::new().expect("Verilated rt_cast");
    let base = loop {
        let s = scene(&mut rng, 0);
        if !s.lights.is_empty() {
            break s;
        }
    };
    let cases: Vec<(&str, u8, Edit)> = vec![
        ("nothing", 0, Box::new(|_| {})),
        ("2 samples per pixel", 1 << 1, Box::new(|s| s.spp = 2)),
        ("shadows (built)", 0, Box::new(|s| s.shadows = true)),
        (
            "a spot light",
            1 << 6,
            Box::new(|s| {
                s.lights[0].spot = Some(rt::Spot {
                    direction: [0.0, -1.0, 0.0],
                    cos_outer: 0.5,
                    cos_inner: 0.7,
                })
            }),
        ),
        (
            "Oren-Nayar",
            1 << 7,
            Box::new(|s| s.materials[0].diffuse_model = DiffuseModel::OrenNayar { sigma2: 0.3 }),
        ),
        (
            "a reflection at depth 2",
            1 << 7,
            Box::new(|s| {
                s.depth = 2;
                s.materials[0].reflection = Reflection::Constant(0.5);
            }),
        ),
    ];
    for (what, bits, edit) in cases {
        let mut s = base.clone();
        edit(&mut s);
        let regs = jobs::scene::to_regs(&s).expect("scene fits the registers");
        let words: Vec<u32> = regs.words().collect();
        waves.before(what, &mut core);
        waves.case(what, || {
            core.load(&words).expect("image fits");
            let frame = core.render(1 << 22, |_| false).expect("frame completes");
            assert_eq!(frame.err, bits, "{what}: err {:#010b}", frame.err);
        });
    }
    // more lights than the core's lanes: the map itself holds only one point light, so
    // the word is written directly
    let regs = jobs::scene::to_regs(&base).expect("scene fits the registers");
    let mut words: Vec<u32> = regs.words().collect();
    words[protocol::scene::hdr::LIGHT_COUNT] = 3;
    waves.before("three lights", &mut core);
    waves.case("three lights", || {
        core.load(&words).expect("image fits");
        let frame = core.render(1 << 22, |_| false).expect("frame completes");
        assert_eq!(frame.err, 1 << 6, "three lights: err {:#010b}", frame.err);
    });
}

/// The reference scene reduced to what the core builds (`jobs::scene::fit_build`, as
/// `fpgfx render --fit` does): textures and reflections off, the spot light a point
/// light, Oren–Nayar as Lambert, Torrance–Sparrow as Blinn–Phong with its exponent; its
/// shadows stay on.
fn reduced_reference(width: u32, height: u32) -> Scene {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../examples/reference.toml"
    ))
    .expect("examples/reference.toml");
    let mut s = jobs::scene::parse(&text, "reference.toml").expect("reference parses");
    s.width = width;
    s.height = height;
    jobs::scene::fit_build(&mut s, &sim_target::rt::core::BUILD);
    s
}

/// The reduced reference scene at `width` × `height` on a fresh core (`trace`: its
/// waveform from the load on): the frame and the seconds its render took, or the first
/// difference from the model.
fn reference_frame(
    width: u32,
    height: u32,
    trace: impl FnOnce(&mut Cast),
) -> Result<(CastFrame, f64), String> {
    let s = reduced_reference(width, height);
    let (words, m) = model(&s);
    let mut core = Cast::new().expect("Verilated rt_cast");
    trace(&mut core);
    core.load(&words).expect("image fits");
    let start = std::time::Instant::now();
    let frame = core.render(1 << 26, |_| false).map_err(|e| e.to_string())?;
    let secs = start.elapsed().as_secs_f64();
    if frame.err != 0 {
        return Err(format!("the core refused it: err {:#010b}", frame.err));
    }
    compare(&frame, &m)?;
    if frame.cycles != expected_cycles(&s) {
        return Err(format!(
            "{} cycles, the model's formula {}",
            frame.cycles,
            expected_cycles(&s)
        ));
    }
    Ok((frame, secs))
}

/// The reduced reference scene at 160 × 90: every plane equal to the model's. Prints the
/// Verilated core's wall time and pairs per second (the figures docs/rt-core.md quotes).
/// A failure is shrunk to the smallest of a few sizes of the same scene that still fails
/// (the whole frame is 230 000 clocks, far too long a waveform), which is replayed.
#[test]
fn the_reduced_reference_scene_matches_the_model() {
    let waves = Waves::new("cast::the_reduced_reference_scene_matches_the_model");
    if let Some(case) = waves.replaying() {
        let (w, h) = case
            .split_once('x')
            .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
            .expect("a replayed size WxH");
        match reference_frame(w, h, |core| waves.before(case, core)) {
            Ok(_) => waves.passed(case),
            Err(e) => waves.fail(case, &e),
        }
        return;
    }
    let s = reduced_reference(160, 90);
    assert!(s.shadows, "the reference scene has shadows");
    let (frame, secs) = match reference_frame(160, 90, |_| {}) {
        Ok(f) => f,
        Err(e) => {
            let (w, h) = [(8, 5), (16, 9), (32, 18), (80, 45)]
                .into_iter()
                .find(|&(w, h)| reference_frame(w, h, |_| {}).is_err())
                .unwrap_or((160, 90));
            waves.fail(
                &format!("{w}x{h}"),
                &format!(
                    "reduced reference 160x90: {e}\n  (the smallest size that fails: {w}x{h})"
                ),
            )
        }
    };
    // pairs the unit tested: every slot's clocks, primary and shadow
    let pairs = u64::from(s.width * s.height) * CoreFrame::of(&s).slot();
    eprintln!(
        "reduced reference 160x90: {} cycles, {:.2} s Verilated, {:.0} pairs/s, {:.0} rays/s",
        frame.cycles,
        secs,
        pairs as f64 / secs,
        f64::from(s.width * s.height) / secs
    );
}

/// Registers and memories starting at random values (Verilator's --x-initial unique,
/// three seeds) give the same frames and clock counts: the reset and the frame's start
/// bring everything that reaches a pixel to a known state.
#[test]
fn uninitialised_state_never_reaches_a_pixel() {
    let waves = Waves::new("cast::uninitialised_state_never_reaches_a_pixel");
    for seed in 1..=3u64 {
        let mut rng = SmallRng::seed_from_u64(0x7873_6565 + seed);
        let mut core = Cast::with_x_seed(seed).expect("Verilated rt_cast");
        for k in 0..10u32 {
            let s = scene(&mut rng, k % 8);
            let (words, m) = model(&s);
            let case = format!("seed {seed} scene {k}");
            waves.before(&case, &mut core);
            waves.case(&case, || {
                core.load(&words).expect("image fits");
                let frame = core.render(1 << 22, |_| false).expect("frame completes");
                if let Err(e) = compare(&frame, &m) {
                    panic!("seed {seed}, scene {k}: {e}");
                }
                assert_eq!(
                    frame.cycles,
                    expected_cycles(&s),
                    "seed {seed}, scene {k}: cycles"
                );
            });
        }
    }
}
