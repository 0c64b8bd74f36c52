//! The parse category: NaN/∞ and random damage injected into valid scene and raster
//! files; a parser must reject every non-finite number and never panic, and what it
//! accepts must also draw.

use rand::rngs::SmallRng;
use rand::Rng;
use sim_target::raster::Raster;
use sim_target::rt::{self, RenderOptions};

use super::report::CaseResult;

const SCENES: [&str; 5] = [
    include_str!("../../../examples/reference.toml"),
    include_str!("../../../examples/rt/brdf.toml"),
    include_str!("../../../examples/rt/fresnel.toml"),
    include_str!("../../../examples/rt/shapes.toml"),
    include_str!("../../../examples/rt/textures.toml"),
];

const RASTERS: [&str; 3] = [
    include_str!("../../../examples/raster/aa.toml"),
    include_str!("../../../examples/raster/fitkit.toml"),
    include_str!("../../../examples/raster/gallery.toml"),
];

/// Spellings of a non-finite number that TOML (or the float parser behind it) accepts.
const NON_FINITE: [&str; 7] = ["nan", "+nan", "-nan", "inf", "+inf", "-inf", "1e999"];

/// Byte ranges of number literals with a fraction or exponent (float fields) in `text`.
fn float_literals(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let mut in_comment = false;
    while i < b.len() {
        let c = b[i];
        if c == b'#' {
            in_comment = true;
        }
        if c == b'\n' {
            in_comment = false;
        }
        if c == b'"' && !in_comment {
            // skip strings
            i += 1;
            while i < b.len() && b[i] != b'"' && b[i] != b'\n' {
                i += 1;
            }
            i += 1;
            continue;
        }
        let starts = (c.is_ascii_digit() || c == b'-' || c == b'+')
            && (i == 0
                || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.'));
        if !in_comment && starts {
            let s = i;
            i += 1;
            while i < b.len()
                && (b[i].is_ascii_digit()
                    || matches!(b[i], b'.' | b'e' | b'E' | b'-' | b'+' | b'_'))
            {
                i += 1;
            }
            let lit = &text[s..i];
            if (lit.contains('.') || lit.contains(['e', 'E']))
                && lit.bytes().any(|d| d.is_ascii_digit())
            {
                out.push((s, i));
            }
            continue;
        }
        i += 1;
    }
    out
}

pub(super) fn parse_case(rng: &mut SmallRng) -> CaseResult {
    let mut r = CaseResult::default();
    let scene_file = rng.gen();
    let base = if scene_file {
        SCENES[rng.gen_range(0..SCENES.len())]
    } else {
        RASTERS[rng.gen_range(0..RASTERS.len())]
    };
    let mut text = base.to_string();
    let mut injected = None;
    match rng.gen_range(0..4) {
        0 | 1 => {
            let lits = float_literals(&text);
            if !lits.is_empty() {
                let (s, e) = lits[rng.gen_range(0..lits.len())];
                let v = NON_FINITE[rng.gen_range(0..NON_FINITE.len())];
                injected = Some(format!("{} -> {v} at byte {s}", &text[s..e]));
                text.replace_range(s..e, v);
            }
        }
        2 => {
            // finite extremes: must not panic, may be refused
            let lits = float_literals(&text);
            for _ in 0..rng.gen_range(1..4) {
                if let Some(&(s, e)) = lits.get(rng.gen_range(0..lits.len().max(1))) {
                    let v = [
                        "1e308", "-1e308", "5e-324", "0.0", "-0.0", "1e38", "65505.0", "32768.0",
                    ][rng.gen_range(0..8)];
                    if e <= text.len() && text.is_char_boundary(s) && text.is_char_boundary(e) {
                        text.replace_range(s..e, v);
                    }
                    break;
                }
            }
        }
        _ => {
            // random byte damage
            let mut bytes = text.into_bytes();
            for _ in 0..rng.gen_range(1..6) {
                let k = rng.gen_range(0..bytes.len().max(1));
                match rng.gen_range(0..3) {
                    0 if k < bytes.len() => bytes[k] = rng.gen_range(0x20..0x7f),
                    1 if k < bytes.len() => {
                        bytes.remove(k);
                    }
                    _ => bytes.insert(k.min(bytes.len()), b"[]{}=\".,\n0e-#"[rng.gen_range(0..13)]),
                }
            }
            text = String::from_utf8_lossy(&bytes).into_owned();
        }
    }
    let ok = if scene_file {
        match jobs::scene::parse(&text, "stress.toml") {
            Ok(scene) => {
                // What parses must also render (tiny, f32) without panicking.
                let opts = RenderOptions {
                    size: Some((4, 4)),
                    spp: Some(1),
                    ..RenderOptions::default()
                };
                if rng.gen_ratio(1, 4) && rt::render(&scene, &opts).is_err() {
                    r.counts.rejected += 1;
                }
                true
            }
            Err(_) => false,
        }
    } else {
        match jobs::raster::parse(&text, "stress.toml") {
            Ok(job) => {
                if rng.gen_ratio(1, 4) {
                    let w = u32::from(job.setup.width).min(64);
                    let h = u32::from(job.setup.height).min(64);
                    if let Ok(mut block) = Raster::new(w, h, &job.setup) {
                        for c in &job.cmds {
                            if block.draw(c).is_err() {
                                r.counts.rejected += 1;
                            }
                        }
                    }
                }
                true
            }
            Err(_) => false,
        }
    };
    if !ok {
        r.counts.rejected += 1;
    } else if let Some(what) = injected {
        r.counts.accepted_nonfinite += 1;
        r.failure = Some(format!(
            "{} accepted a non-finite number ({what})",
            if scene_file {
                "scene file"
            } else {
                "raster file"
            }
        ));
    }
    r
}
