//! The scene-file parser against hostile input: any text gives a scene or a located
//! error, never a panic; every non-finite number (`nan`, `inf`, an overflowing literal)
//! in any field is refused, naming a key and a line (found by `fpgfx stress`: the parser
//! used to accept them everywhere but in `scale`).

use crate::hostile_text::{damage, edits, float_literals};
use proptest::prelude::*;

const EXAMPLES: [&str; 5] = [
    include_str!("../../../examples/reference.toml"),
    include_str!("../../../examples/rt/brdf.toml"),
    include_str!("../../../examples/rt/fresnel.toml"),
    include_str!("../../../examples/rt/shapes.toml"),
    include_str!("../../../examples/rt/textures.toml"),
];

/// Every float of every example, replaced in turn by every non-finite spelling, is
/// refused with a located error: exhaustive, not sampled.
#[test]
fn every_non_finite_number_is_refused() {
    let mut tried = 0;
    for (e, text) in EXAMPLES.iter().enumerate() {
        assert!(
            jobs::scene::parse(text, "ex.toml").is_ok(),
            "example {e} parses"
        );
        let lits = float_literals(text);
        assert!(lits.len() > 5, "example {e} has floats");
        for &(s, t) in &lits {
            for bad in ["nan", "-nan", "+inf", "-inf", "inf", "1e999", "-1.5e400"] {
                let mut damaged = text.to_string();
                damaged.replace_range(s..t, bad);
                let err = jobs::scene::parse(&damaged, "bad.toml")
                    .expect_err(&format!("example {e}: {} -> {bad} accepted", &text[s..t]));
                let line = text[..s].matches('\n').count() + 1;
                // A float in an integer field fails as a type error, which is located
                // by toml itself; a non-finite float in a float field by the new check.
                assert!(err.line == line, "{err} (expected line {line})");
                assert!(!err.key.is_empty());
                tried += 1;
            }
        }
    }
    assert!(tried > 300, "{tried}");
}

#[test]
fn the_error_names_the_key_and_line() {
    let text = "[camera]\nposition = [0.0, 1.0, 6.0]\nlook_at = [0.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\nfov_y = 45.0\n\n[[light]]\nposition = [1.0, 2.0, 3.0]\ncolor = [1.0, nan, 1.0]\n";
    let err = jobs::scene::parse(text, "s.toml").expect_err("nan refused");
    assert_eq!(err.line, 9);
    assert_eq!(err.key, "light[0].color[1]");
    assert_eq!(err.file, "s.toml");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    /// Any text: a scene or an error with a line inside the text.
    #[test]
    fn any_text_parses_or_fails_located(text in "\\PC{0,400}") {
        if let Err(e) = jobs::scene::parse(&text, "any.toml") {
            prop_assert!(e.line >= 1 && e.line <= text.lines().count().max(1) + 1, "{e}");
        }
    }

    /// Damaged examples (bytes overwritten, inserted or deleted): a scene or an error.
    #[test]
    fn damaged_examples_parse_or_fail(
        ex in 0usize..EXAMPLES.len(),
        edits in edits(b"[]{}=\",.\n0-e#aZ "),
    ) {
        let text = damage(EXAMPLES[ex], &edits);
        if let Ok(scene) = jobs::scene::parse(&text, "d.toml") {
            // Whatever parses is finite everywhere the kernel will look.
            prop_assert!(scene.bias.is_finite() && scene.max_distance.is_finite());
            prop_assert!(scene.camera.position.iter().all(|v| v.is_finite()));
            for l in &scene.lights {
                prop_assert!(l.position.iter().chain(&l.color).all(|v| v.is_finite()));
            }
        }
    }
}

/// Found by the `scene_file` fuzz target (session 6): a value with a backtick in it
/// (`mode = "`onstant"`) gives toml's message "unknown variant ``onstant`, expected one
/// of …", and `key_from_message` (src/rt/scene_file.rs) takes the text between the first
/// two backticks as the key: the empty string, so the user read ``file:48: ``: …``.
/// Fixed: the key now comes from the source before the value's `=`. The crash input is
/// `fuzz/corpus/scene_file/seed-backtick-variant.toml`.
#[test]
fn a_backtick_in_a_value_still_names_a_key() {
    let damaged = EXAMPLES[0].replacen(r#"mode = "constant""#, r#"mode = "`onstant""#, 1);
    assert_ne!(
        damaged, EXAMPLES[0],
        "the reference scene has a constant reflection"
    );
    let err = jobs::scene::parse(&damaged, "bad.toml").expect_err("unknown variant refused");
    assert_eq!(err.line, 48, "{err}");
    assert_eq!(err.key, "mode", "{err}");
}
