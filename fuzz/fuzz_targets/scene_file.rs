//! Any text through the scene-file parser; what parses renders 4 × 4 in f32 and Q16.16.
#![no_main]
use libfuzzer_sys::fuzz_target;
use sim_target::rt::{render, scene_file, Numeric, RenderOptions};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(scene) = scene_file::parse(text, "fuzz.toml") {
        for numeric in [Numeric::F32, Numeric::Q16_16] {
            let _ = render(
                &scene,
                &RenderOptions {
                    numeric,
                    size: Some((4, 4)),
                    spp: Some(1),
                    ..RenderOptions::default()
                },
            );
        }
    }
});
