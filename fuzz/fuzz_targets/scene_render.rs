//! Any text through the scene-file parser and, when it parses, the ray tracer (the parse
//! alone, checked in full, is `scene_file`). Beyond "never panics":
//! - an accepted scene satisfies every rule the parser promises (positive sizes, depth and
//!   spp, fov in (0, 180), finite numbers, positive finite scales, material indices in
//!   range, the seed's object and light limits, spot and BRDF parameter ranges), and it
//!   renders 4 × 4 at 1 spp in f32 and Q16.16 (depth at most 4) into a frame of 16
//!   RGB8 pixels with depth and normal planes of that size;
//! - a refused text gets a message that names the file, a line inside the text and a key.
#![no_main]
use libfuzzer_sys::fuzz_target;
use sim_target::rt::{render, Numeric, RenderOptions};

mod common;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Some(mut scene) = common::scene::parse_checked(text) else {
        return;
    };
    // Depth is bounded only by u32; a 4 × 4 render at depth 10⁹ between two
    // mirrors is a (legitimate) long run, not what this target looks for.
    scene.depth = scene.depth.min(4);
    for numeric in [Numeric::F32, Numeric::Q16_16] {
        let got = render(
            &scene,
            &RenderOptions {
                numeric,
                size: Some((4, 4)),
                spp: Some(1),
                aovs: true,
                ..RenderOptions::default()
            },
        );
        match got {
            Ok(f) => {
                assert_eq!((f.width, f.height), (4, 4));
                assert_eq!(f.rgb8.len(), 16 * 3);
                assert_eq!(f.depth.as_ref().map(Vec::len), Some(16));
                assert_eq!(f.normal.as_ref().map(Vec::len), Some(16 * 3));
            }
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
});
