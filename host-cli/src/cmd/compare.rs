//! `fpgfx compare`: a frame against a reference, by the `compare` kernel (docs/compare.md).
//! Exit 0 within tolerance, 1 beyond it, 2 when the input is unusable: a script tells "the
//! frames differ" from "the comparison could not be made" by the status alone.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, ensure, Context, Result};
use compare::{Coverage, Errors, Frame, Mismatch, Options, Pixels, Report};
use host_cli::frames;
use serde_json::{json, Value};

/// Arguments of `fpgfx compare`.
#[derive(clap::Args)]
pub struct Args {
    /// The reference frame: .png, .pfm, or a $readmemh framebuffer (.hex, .memh, .mem).
    expected: PathBuf,
    /// The frame under test, in any of the same formats.
    actual: PathBuf,
    /// Largest per-channel absolute difference still counted as equal: whole 8-bit
    /// levels (0..=255) for colour frames (one RGB332 red or green step is 36 or 37
    /// levels, a blue step 85), the samples' own unit for PFM.
    #[arg(long, default_value_t = 0.0, value_name = "LEVELS")]
    tolerance: f64,
    /// Allow a pixel to differ when its centre lies within 2^-BITS px of an edge of the
    /// raster job (triangle and polygon sides, line outlines). The job comes from
    /// --raster, or from job.toml beside EXPECTED (an `fpgfx vectors` directory).
    #[arg(long, value_name = "BITS", value_parser = clap::value_parser!(u8).range(0..=32))]
    coverage_precision: Option<u8>,
    /// The raster job (the file `fpgfx raster` reads) whose edges the allowance is
    /// measured from; alone, it turns the allowance on at the job's subpixel_bits.
    #[arg(long, value_name = "JOB.toml")]
    raster: Option<PathBuf>,
    /// Write an error mask PNG: EXPECTED at 30 % brightness, red where a pixel fails,
    /// yellow where it differs but is allowed.
    #[arg(long, value_name = "mask.png")]
    mask: Option<PathBuf>,
    /// Print one JSON object with every figure and the listed mismatches.
    #[arg(long)]
    json: bool,
}

/// Compares, prints and turns the outcome into the exit status (0, 1 or 2).
pub fn run(a: &Args) -> ExitCode {
    match compare_files(a) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// The allowance as used, for the report.
struct Allowance {
    job: PathBuf,
    coverage: Coverage,
}

/// Whether ACTUAL passed; an error is unusable input.
fn compare_files(a: &Args) -> Result<bool> {
    if let Some(path) = &a.mask {
        super::check_output_file(
            &super::flag_path("--mask", path),
            path,
            "the error mask",
            &["png"],
        )?;
    }
    let expected = frames::read(&a.expected)?;
    let actual = frames::read(&a.actual)?;
    let t = a.tolerance;
    ensure!(
        t.is_finite() && t >= 0.0,
        "--tolerance {t}: must be a finite number ≥ 0"
    );
    let colour = |f: &Frame| matches!(f.pixels, Pixels::Rgb8(_));
    if colour(&expected) || colour(&actual) {
        ensure!(
            t.fract() == 0.0 && t <= 255.0,
            "--tolerance {t}: colour frames take whole 8-bit levels, 0..=255"
        );
    }
    let allowance = allowance(a, &expected)?;
    let opts = Options {
        tolerance: t,
        coverage: allowance.as_ref().map(|al| al.coverage.clone()),
        ..Options::default()
    };
    let report = compare::compare(&expected, &actual, &opts).with_context(|| {
        format!(
            "cannot compare {} with {}",
            a.expected.display(),
            a.actual.display()
        )
    })?;
    if let Some(path) = &a.mask {
        image::RgbImage::from_raw(report.width, report.height, report.mask.clone())
            .context("the mask does not match the frame size")?
            .save(path)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    if a.json {
        println!("{}", to_json(a, &report, allowance.as_ref()));
    } else {
        print_text(a, &report, allowance.as_ref());
    }
    Ok(report.passed())
}

/// The edge allowance the flags ask for, with the job it was measured from.
fn allowance(a: &Args, expected: &Frame) -> Result<Option<Allowance>> {
    let beside = || {
        let p = a
            .expected
            .parent()
            .unwrap_or(Path::new("."))
            .join("job.toml");
        p.is_file().then_some(p)
    };
    let job = match (&a.raster, a.coverage_precision) {
        (Some(p), _) => p.clone(),
        (None, None) => return Ok(None),
        (None, Some(bits)) => match beside() {
            Some(p) => p,
            None => bail!(
                "--coverage-precision {bits}: the allowance needs the frame's geometry: give \
                 --raster JOB.toml (or compare an `fpgfx vectors` directory's frame, beside \
                 its job.toml)"
            ),
        },
    };
    let name = job.display().to_string();
    let text = std::fs::read_to_string(&job).with_context(|| format!("cannot read {name}"))?;
    let parsed = jobs::raster::parse(&text, &name)?;
    let size = (
        u32::from(parsed.setup.width),
        u32::from(parsed.setup.height),
    );
    ensure!(
        size == (expected.width, expected.height),
        "{name} draws {}×{}, but {} is {}×{}",
        size.0,
        size.1,
        a.expected.display(),
        expected.width,
        expected.height
    );
    Ok(Some(Allowance {
        coverage: Coverage {
            bits: a.coverage_precision.unwrap_or(parsed.setup.subpixel_bits),
            edges: compare::raster_edges(&parsed.setup, &parsed.cmds),
        },
        job,
    }))
}

/// A mismatch's samples as the text report shows them: `#rrggbb` for colour.
fn samples(r: &Report, v: &[f32; compare::MAX_CHANNELS]) -> String {
    let v = &v[..r.channels];
    if matches!(r.errors, Errors::Levels(_)) {
        let mut s = String::from("#");
        for c in v {
            s.push_str(&format!("{:02x}", *c as u8));
        }
        s
    } else if v.len() == 1 {
        v[0].to_string()
    } else {
        format!("{v:?}")
    }
}

fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

fn print_text(a: &Args, r: &Report, allowance: Option<&Allowance>) {
    let kind = match r.errors {
        Errors::Levels(_) => "8-bit RGB".to_string(),
        Errors::Float(_) => format!("{}-channel float", r.channels),
    };
    println!("expected    {}", a.expected.display());
    println!("actual      {}", a.actual.display());
    println!(
        "frame       {}×{} {kind}, {} pixels",
        r.width,
        r.height,
        r.pixels()
    );
    println!(
        "equal       {} identical, {} within tolerance {}",
        r.equal, r.within_tolerance, a.tolerance
    );
    if let Some(al) = allowance {
        println!(
            "allowed     {} within 2^-{} px of an edge ({} edges from {})",
            r.near_edge,
            al.coverage.bits,
            al.coverage.edges.len(),
            al.job.display()
        );
    }
    println!(
        "failing     {}: missing {}, unexpected {}, differing {}",
        r.failures(),
        r.missing,
        r.unexpected,
        r.differing
    );
    match r.errors {
        Errors::Levels(l) => {
            let psnr = if l.psnr_db.is_finite() {
                format!("{:.2} dB", l.psnr_db)
            } else {
                "∞ (identical)".into()
            };
            println!(
                "error       max {} levels, mean {:.4} levels, PSNR {psnr}",
                l.max, l.mean
            );
        }
        Errors::Float(f) => println!(
            "error       absolute max {:e} mean {:e}, relative max {:e} mean {:e}",
            f.max_abs, f.mean_abs, f.max_rel, f.mean_rel
        ),
    }
    if let Some(bg) = r.background {
        println!(
            "background  {} (the most common colour of expected)",
            hex(bg)
        );
    }
    if !r.mismatches.is_empty() {
        println!(
            "first {} of {} failing (x, y, expected, got):",
            r.mismatches.len(),
            r.failures()
        );
        for m in &r.mismatches {
            println!(
                "  ({}, {}) {} {} {}",
                m.x,
                m.y,
                samples(r, &m.expected),
                samples(r, &m.actual),
                m.class.name()
            );
        }
    }
    if r.passed() {
        println!("PASS");
    } else {
        println!("FAIL: {} of {} pixels", r.failures(), r.pixels());
    }
}

/// A sample for JSON: a number, or `"inf"`, `"-inf"`, `"nan"` (JSON has no such numbers,
/// and a depth plane's "no hit" must not read as 0).
fn sample_json(v: f32) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        json!(v.to_string().to_ascii_lowercase())
    }
}

fn mismatch_json(r: &Report, m: &Mismatch) -> Value {
    let levels = matches!(r.errors, Errors::Levels(_));
    let vals = |v: &[f32; compare::MAX_CHANNELS]| -> Vec<Value> {
        v[..r.channels]
            .iter()
            .map(|&s| {
                if levels {
                    json!(s as u8)
                } else {
                    sample_json(s)
                }
            })
            .collect()
    };
    json!({
        "x": m.x,
        "y": m.y,
        "class": m.class.name(),
        "expected": vals(&m.expected),
        "actual": vals(&m.actual),
    })
}

fn to_json(a: &Args, r: &Report, allowance: Option<&Allowance>) -> Value {
    let mut v = json!({
        "expected": a.expected.display().to_string(),
        "actual": a.actual.display().to_string(),
        "width": r.width,
        "height": r.height,
        "channels": r.channels,
        "tolerance": a.tolerance,
        "coverage": allowance.map(|al| json!({
            "bits": al.coverage.bits,
            "radius_px": al.coverage.radius(),
            "edges": al.coverage.edges.len(),
            "job": al.job.display().to_string(),
        })),
        "background": r.background.map(hex),
        "pixels": r.pixels(),
        "equal": r.equal,
        "within_tolerance": r.within_tolerance,
        "near_edge": r.near_edge,
        "missing": r.missing,
        "unexpected": r.unexpected,
        "differing": r.differing,
        "failures": r.failures(),
        "passed": r.passed(),
        "mask": a.mask.as_ref().map(|p| p.display().to_string()),
        "mismatches": r.mismatches.iter().map(|m| mismatch_json(r, m)).collect::<Vec<_>>(),
    });
    let figures = match r.errors {
        Errors::Levels(l) => json!({
            "kind": "rgb8",
            "max_error": l.max,
            "mean_error": l.mean,
            // null when identical: PSNR is +∞ there, which JSON cannot hold.
            "psnr_db": l.psnr_db.is_finite().then_some(l.psnr_db),
        }),
        Errors::Float(f) => json!({
            "kind": "float",
            "max_abs_error": f.max_abs,
            "mean_abs_error": f.mean_abs,
            "max_rel_error": f.max_rel,
            "mean_rel_error": f.mean_rel,
        }),
    };
    if let (Some(obj), Value::Object(extra)) = (v.as_object_mut(), figures) {
        obj.extend(extra);
    }
    v
}
