//! Any text through the scene-file parser. Beyond "never panics":
//! - an accepted scene satisfies every rule the parser promises (positive sizes, depth and
//!   spp, fov in (0, 180), finite numbers, positive finite scales, material indices in
//!   range, the seed's object and light limits, spot and BRDF parameter ranges);
//! - a refused text gets a message that names the file, a line inside the text and a key.
//!
//! Rendering is `scene_render`'s: without it this target runs ~10x faster.
#![no_main]
use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        common::scene::parse_checked(text);
    }
});
