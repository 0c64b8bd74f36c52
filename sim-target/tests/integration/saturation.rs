//! The device's saturation counter (the formats' count of clipped results, reported as
//! `rt::Stats::saturations` and `DeviceCounters::saturations`): what it counts in each
//! format on the reference scene, that rayon's row split does not change it, that it
//! agrees with the exhaustive `Probe`, and that `Device` reports it.

use jobs::scene::to_regs;
use protocol::frame::{Block, StartFrame};
use sim_target::num::instrumented::{self, Probe};
use sim_target::num::{Q16_16, Q8_24};
use sim_target::rt::{self, Numeric, RenderOptions};
use sim_target::scene_regs::from_regs;

fn reference() -> rt::Scene {
    let text = include_str!("../../../examples/reference.toml");
    let mut scene = jobs::scene::parse(text, "reference.toml").expect("reference parses");
    scene.width = 96;
    scene.height = 54;
    scene
}

fn saturations(numeric: Numeric) -> u64 {
    saturations_of(&reference(), numeric)
}

fn saturations_of(scene: &rt::Scene, numeric: Numeric) -> u64 {
    let opts = RenderOptions {
        numeric,
        ..Default::default()
    };
    rt::render(scene, &opts).expect("renders").stats.saturations
}

#[test]
fn only_a_format_too_narrow_for_the_scene_saturates() {
    let q8 = saturations(Numeric::Q8_24);
    println!("reference 96x54: q8.24 {q8} saturations");
    assert!(q8 > 0, "Q8.24 cannot hold the light's 160: {q8}");
    // Q16.16 clips a handful, as measured (`Probe` finds the same three, below); the
    // wider and the float formats nothing.
    assert_eq!(saturations(Numeric::Q16_16), 3);
    for n in [Numeric::Q32_32, Numeric::F32, Numeric::F64] {
        assert_eq!(saturations(n), 0, "{n:?}");
    }
    // Deterministic whatever the threads did.
    assert_eq!(saturations(Numeric::Q8_24), q8);
}

#[test]
fn the_cheap_count_is_the_probes_count() {
    let scene = reference();
    let opts = RenderOptions::default();
    for (numeric, probed) in [
        (
            Numeric::Q8_24,
            instrumented::count(|| rt::render_instrumented::<Probe<Q8_24>>(&scene, &opts)),
        ),
        (
            Numeric::Q16_16,
            instrumented::count(|| rt::render_instrumented::<Probe<Q16_16>>(&scene, &opts)),
        ),
    ] {
        let (frame, seen) = probed;
        let frame = frame.expect("renders");
        // The probed frame counts itself too: it runs the bare format inside the wrapper.
        assert_eq!(
            frame.stats.saturations, seen.seen.saturations,
            "{numeric:?}"
        );
        assert_eq!(
            saturations(numeric),
            seen.seen.saturations,
            "{numeric:?}: rows in parallel, bare format"
        );
    }
}

#[test]
fn the_device_reports_the_last_frames_saturations() {
    let mut device = sim_target::Device::new(&protocol::bus::WIDE);
    let regs = to_regs(&reference()).expect("fits");
    // The device renders the scene the registers hold (Q16.16-quantised values).
    let held = from_regs(&regs).expect("decodes");
    let words: Vec<u32> = regs.words().collect();
    device
        .write_regs(0, &words)
        .expect("fits the register file");
    let mut last = 0;
    for (id, numeric) in [(1, Numeric::Q8_24), (2, Numeric::F32)] {
        device
            .start(&StartFrame {
                frame_id: id,
                block: Block::RayTrace,
                numeric,
                auto_restart: false,
                aovs: false,
            })
            .expect("renders");
        let got = device.counters().saturations;
        assert_eq!(got, saturations_of(&held, numeric), "{numeric:?}");
        last = got;
    }
    assert_eq!(
        last, 0,
        "per frame, not cumulative: the f32 frame clipped nothing"
    );
}
