//! The synthesis gate: a committed baseline of every design's figures
//! (`hw/synth-baseline.json`, the records `cargo xtask synth --json` prints) and the
//! margins a run may move them by before it fails.
//!
//! Margins, and why (docs/synthesis.md says the same to a user):
//! - LUTs and flip-flops may grow by [`AREA_MARGIN`] (5 %): Yosys is deterministic for a
//!   given source, so a figure moves only when the RTL does, but mapping moves it by more
//!   than the change itself (a nine-line change to the FITkit read-back moved the Gowin
//!   LUTs by +3.3 % and the ECP5's by −2.6 %); 5 % lets such a fix land without touching
//!   the baseline while a unit that doubles, or a pipeline that adds a few hundred
//!   registers to a small block, fails.
//! - Block RAMs and DSPs may not grow at all: they are few and coarse, and one more is a
//!   design decision, taken by updating the baseline.
//! - A design that fitted its part must still fit.
//! - The Fmax (median of the seeds) may fall by [`FMAX_MARGIN`] (8 %): a change anywhere
//!   in a design moves every placement, and the median of four seeds still moves by a
//!   few per cent with it (docs/synthesis.md has the measurement); a halved Fmax, or a new
//!   long path, fails.
//!
//! A figure better than the baseline beyond its margin passes and is named, so the
//! baseline is updated (`cargo xtask synth --update-baseline`) and the gain kept.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use crate::synth::Record;

/// How much LUTs and flip-flops may grow, as a fraction.
pub const AREA_MARGIN: f64 = 0.05;
/// How much the median Fmax may fall, as a fraction.
pub const FMAX_MARGIN: f64 = 0.08;

/// Where the baseline lives.
pub fn path(root: &Path) -> PathBuf {
    root.join("hw").join("synth-baseline.json")
}

/// What a check found: the regressions (empty when the run passes) and a report with one
/// line per design.
#[derive(Debug, Default)]
pub struct Verdict {
    /// One line per figure beyond its margin.
    pub regressions: Vec<String>,
    /// Each design against its baseline.
    pub report: String,
}

fn key(r: &Record) -> (String, String, String) {
    (r.block.clone(), r.variant.clone(), r.family.clone())
}

fn read(path: &Path) -> Result<Vec<Record>> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| {
        format!(
            "{} is not a list of synthesis records (block, variant, family, lut, ff, bram, dsp, fits, fmax_mhz)",
            path.display()
        )
    })
}

/// Holds `run` to the baseline at `path`.
pub fn check(path: &Path, run: &[Record]) -> Result<Verdict> {
    let base = read(path)?;
    Ok(compare(&base, run))
}

/// Holds each record of `run` to its entry in `base`.
pub fn compare(base: &[Record], run: &[Record]) -> Verdict {
    let mut v = Verdict::default();
    for r in run {
        let name = format!("{} {} on {}", r.block, r.variant, r.family);
        let Some(b) = base.iter().find(|b| key(b) == key(r)) else {
            v.regressions.push(format!(
                "{name}: no baseline (`cargo xtask synth --update-baseline --block {} --variant {} --family {}` records it)",
                r.block, r.variant, r.family
            ));
            continue;
        };
        let mut worse = Vec::new();
        let mut better = Vec::new();
        for (what, now, was) in [("LUT", r.lut, b.lut), ("FF", r.ff, b.ff)] {
            let limit = (was as f64 * (1.0 + AREA_MARGIN)).floor() as u64;
            if now > limit {
                worse.push(format!(
                    "{what} {now} > {was} + {:.0} %",
                    AREA_MARGIN * 100.0
                ));
            } else if (now as f64) < was as f64 * (1.0 - AREA_MARGIN) {
                better.push(format!("{what} {now} < {was}"));
            }
        }
        for (what, now, was) in [("BRAM", r.bram, b.bram), ("DSP", r.dsp, b.dsp)] {
            if now > was {
                worse.push(format!("{what} {now} > {was}"));
            } else if now < was {
                better.push(format!("{what} {now} < {was}"));
            }
        }
        if b.fits && !r.fits {
            worse.push("no longer fits its part".into());
        }
        match (r.fmax_mhz, b.fmax_mhz) {
            (Some(now), Some(was)) if now < was * (1.0 - FMAX_MARGIN) => worse.push(format!(
                "Fmax {now:.1} MHz < {was:.1} MHz − {:.0} %",
                FMAX_MARGIN * 100.0
            )),
            (Some(now), Some(was)) if now > was * (1.0 + FMAX_MARGIN) => {
                better.push(format!("Fmax {now:.1} MHz > {was:.1} MHz"))
            }
            (Some(_), None) if !b.fits => {}
            (Some(now), None) => better.push(format!("Fmax {now:.1} MHz, none before")),
            _ => {}
        }
        let fmax = match (r.fmax_mhz, b.fmax_mhz) {
            (Some(now), Some(was)) => format!(", Fmax {now:.1} MHz (baseline {was:.1})"),
            (None, Some(was)) => format!(", not placed (baseline Fmax {was:.1})"),
            _ => String::new(),
        };
        let verdict = if !worse.is_empty() {
            "REGRESSED"
        } else if !better.is_empty() {
            "better (update the baseline to keep it)"
        } else {
            "within the margins"
        };
        v.report += &format!(
            "synth gate: {name}: LUT {} (baseline {}), FF {} ({}), BRAM {} ({}), DSP {} ({}){fmax}: {verdict}",
            r.lut, b.lut, r.ff, b.ff, r.bram, b.bram, r.dsp, b.dsp
        );
        for x in worse.iter().chain(better.iter()) {
            v.report += &format!("; {x}");
        }
        v.report += "\n";
        if !worse.is_empty() {
            v.regressions.push(format!("{name}: {}", worse.join(", ")));
        }
    }
    v
}

/// Writes `run`'s records into the baseline at `path`, replacing the entries of the same
/// designs and keeping the others; a record not placed keeps the baseline's Fmax (a
/// resources-only run does not erase it). Returns how many designs were written.
pub fn update(path: &Path, run: &[Record]) -> Result<usize> {
    let mut base = read(path)?;
    for r in run {
        let mut new = r.clone();
        if let Some(old) = base.iter().find(|b| key(b) == key(r)) {
            if new.fmax_mhz.is_none() && new.fits {
                new.fmax_mhz = old.fmax_mhz;
                new.fmax_seeds = old.fmax_seeds.clone();
            }
        }
        base.retain(|b| key(b) != key(r));
        base.push(new);
    }
    base.sort_by_key(key);
    let text = serde_json::to_string_pretty(&base)? + "\n";
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(run.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(lut: u64, ff: u64, bram: u64, dsp: u64, fmax: Option<f64>) -> Record {
        Record {
            block: "fitkit-raster".into(),
            variant: "default".into(),
            family: "ice40".into(),
            lut,
            ff,
            bram,
            dsp,
            fits: true,
            fmax_mhz: fmax,
            fmax_seeds: Vec::new(),
        }
    }

    #[test]
    fn figures_within_the_margins_pass_and_beyond_them_fail() {
        let base = [rec(1000, 500, 7, 0, Some(60.0))];
        assert!(compare(&base, &[rec(1050, 525, 7, 0, Some(55.3))])
            .regressions
            .is_empty());
        // doubled LUTs, one more EBR, a halved Fmax: each one a regression
        let v = compare(&base, &[rec(2000, 500, 7, 0, Some(60.0))]);
        assert_eq!(v.regressions.len(), 1, "{:?}", v.regressions);
        assert!(v.regressions[0].contains("LUT 2000 > 1000"));
        assert_eq!(
            compare(&base, &[rec(1051, 500, 7, 0, Some(60.0))])
                .regressions
                .len(),
            1
        );
        assert_eq!(
            compare(&base, &[rec(1000, 500, 8, 0, Some(60.0))])
                .regressions
                .len(),
            1
        );
        assert!(
            compare(&base, &[rec(1000, 500, 7, 0, Some(30.0))]).regressions[0]
                .contains("Fmax 30.0 MHz")
        );
        // an unplaced run is held on its resources only
        assert!(compare(&base, &[rec(1000, 500, 7, 0, None)])
            .regressions
            .is_empty());
        // a design that stops fitting fails
        let mut over = rec(1000, 500, 7, 0, None);
        over.fits = false;
        assert!(compare(&base, &[over]).regressions[0].contains("no longer fits"));
        // a design with no baseline fails and says how to record it
        let mut other = rec(1000, 500, 7, 0, None);
        other.family = "gowin".into();
        assert!(compare(&base, &[other]).regressions[0].contains("--update-baseline"));
        // a better figure passes and is named
        let v = compare(&base, &[rec(900, 500, 7, 0, Some(70.0))]);
        assert!(v.report.contains("LUT 900 < 1000"), "{}", v.report);
        assert!(v.regressions.is_empty());
        assert!(v.report.contains("better"), "{}", v.report);
    }

    #[test]
    fn an_update_keeps_other_designs_and_a_placed_fmax() {
        let dir = std::env::temp_dir().join(format!("fpgfx-baseline-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let p = dir.join("b.json");
        let mut a = rec(1000, 500, 7, 0, Some(60.0));
        let mut b = rec(10, 5, 0, 0, Some(200.0));
        b.variant = "other".into();
        update(&p, &[a.clone(), b.clone()]).expect("write");
        a.lut = 1100;
        a.fmax_mhz = None;
        update(&p, &[a]).expect("rewrite");
        let back = read(&p).expect("read");
        assert_eq!(back.len(), 2);
        let a2 = back.iter().find(|r| r.variant == "default").expect("a");
        assert_eq!((a2.lut, a2.fmax_mhz), (1100, Some(60.0)));
        assert_eq!(back.iter().find(|r| r.variant == "other"), Some(&b));
        std::fs::write(&p, "not json").expect("write");
        assert!(check(&p, &[]).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
