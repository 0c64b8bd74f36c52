//! The raster command file parser against hostile input: any text (TOML or JSON) gives a
//! job or an error, never a panic; every non-finite number is refused; whatever parses
//! draws on the raster block without a panic.

use std::sync::OnceLock;

use proptest::prelude::*;
use sim_target::raster::Raster;

use crate::hostile_text::{damage, edits, float_literals};

/// The raster gallery's texts, read once: the property tests damage them thousands of
/// times.
fn examples() -> &'static [String] {
    static TEXTS: OnceLock<Vec<String>> = OnceLock::new();
    TEXTS.get_or_init(|| {
        crate::raster_gallery()
            .iter()
            .map(|p| std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display())))
            .collect()
    })
}

fn to_json(text: &str) -> String {
    let v: toml::Value = toml::from_str(text).expect("example is TOML");
    serde_json::to_string(&v).expect("JSON")
}

/// Draws a parsed job on the block (clipped to 64 × 64 to keep it quick).
fn draw(job: &jobs::raster::RasterJob) {
    let w = u32::from(job.setup.width).min(64);
    let h = u32::from(job.setup.height).min(64);
    if let Ok(mut block) = Raster::new(w, h, &job.setup) {
        for c in &job.cmds {
            let _ = block.draw(c);
        }
    }
}

/// Every float of every example, replaced by every non-finite spelling, is refused
/// (exhaustive); in JSON, an overflowing literal is refused too.
#[test]
fn every_non_finite_number_is_refused() {
    let mut tried = 0;
    for (e, text) in examples().iter().enumerate() {
        assert!(jobs::raster::parse(text, "ex.toml").is_ok(), "example {e}");
        let lits = float_literals(text);
        assert!(!lits.is_empty(), "example {e} has floats");
        for &(s, t) in &lits {
            for bad in ["nan", "-nan", "+inf", "-inf", "inf", "1e999"] {
                let mut damaged = text.to_string();
                damaged.replace_range(s..t, bad);
                assert!(
                    jobs::raster::parse(&damaged, "bad.toml").is_err(),
                    "example {e}: {} -> {bad} accepted",
                    &text[s..t]
                );
                tried += 1;
            }
        }
        let json = to_json(text);
        assert!(
            jobs::raster::parse(&json, "ex.json").is_ok(),
            "example {e} as JSON"
        );
        for &(s, t) in &float_literals(&json) {
            let mut damaged = json.clone();
            damaged.replace_range(s..t, "1e999");
            assert!(jobs::raster::parse(&damaged, "bad.json").is_err());
            tried += 1;
        }
    }
    assert!(tried > 100, "{tried}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    /// Any text, read as TOML and as JSON: a job or an error.
    #[test]
    fn any_text_parses_or_fails(text in "\\PC{0,300}") {
        for name in ["any.toml", "any.json"] {
            if let Ok(job) = jobs::raster::parse(&text, name) {
                draw(&job);
            }
        }
    }

    /// Damaged examples (TOML and JSON): a job that draws, or an error.
    #[test]
    fn damaged_examples_parse_or_fail(
        ex in 0usize..examples().len(),
        json in any::<bool>(),
        edits in edits(b"[]{}=\",.:\n0-9e#a "),
    ) {
        let base = if json { to_json(&examples()[ex]) } else { examples()[ex].clone() };
        let text = damage(&base, &edits);
        if let Ok(job) = jobs::raster::parse(&text, if json { "d.json" } else { "d.toml" }) {
            draw(&job);
        }
    }
}
