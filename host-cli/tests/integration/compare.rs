//! `fpgfx compare` over the real binary: frames drawn by `fpgfx raster --port builtin`,
//! damaged on purpose, and compared as PNG, `$readmemh` framebuffer and PFM; the exit
//! status (0 pass, 1 fail, 2 unusable input), the listed pixel, the JSON, the mask and
//! the edge allowance against a frame rasterised with its edges moved.

use std::sync::OnceLock;

use compare::memh::{format_frame, FrameHeader, PixelFormat};
use serde_json::Value;

use crate::common::{example, fpgfx, ok, rgb, tmp, Run};

/// Draws a raster job on the built-in target into `out`.
fn raster(job: &str, out: &str) {
    ok(&["--port", "builtin", "raster", job, "-o", out]);
}

/// The gallery drawn once for the tests that damage it.
fn gallery() -> &'static str {
    static PNG: OnceLock<String> = OnceLock::new();
    PNG.get_or_init(|| {
        let out = tmp("gallery.png");
        raster(&example("raster/gallery.toml"), &out);
        out
    })
}

/// Runs `fpgfx compare ARGS…` and requires `code`; returns the run.
#[track_caller]
fn expect(code: i32, args: &[&str]) -> Run {
    let run = fpgfx(&[&["compare"], args].concat());
    assert_eq!(
        run.code,
        Some(code),
        "fpgfx compare {args:?}:\nstdout: {}\nstderr: {}",
        run.stdout,
        run.stderr
    );
    run
}

fn json(args: &[&str], code: i32) -> Value {
    let run = expect(code, &[args, &["--json"]].concat());
    serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("{e}: {}", run.stdout))
}

/// The gallery with pixel `(x, y)` inverted, saved as `name`.
fn flipped(name: &str, x: u32, y: u32) -> String {
    let mut img = rgb(gallery());
    let p = img.get_pixel_mut(x, y);
    p.0 = p.0.map(|v| 255 - v);
    let out = tmp(name);
    img.save(&out).expect("write PNG");
    out
}

/// A PNG rewritten as a `$readmemh` framebuffer in `format`.
fn to_memh(png: &str, format: PixelFormat, out: &str) {
    let img = rgb(png);
    let word = |p: &image::Rgb<u8>| {
        let [r, g, b] = p.0.map(u64::from);
        match format {
            PixelFormat::Rgb332 => (r >> 5) << 5 | (g >> 5) << 2 | b >> 6,
            _ => r << 16 | g << 8 | b,
        }
    };
    let header = FrameHeader {
        width: img.width(),
        height: img.height(),
        format,
    };
    std::fs::write(out, format_frame(&header, img.pixels().map(word))).expect("write memh");
}

#[test]
fn the_gallery_drawn_twice_is_identical() {
    let again = tmp("gallery-again.png");
    raster(&example("raster/gallery.toml"), &again);
    let run = expect(0, &[gallery(), &again]);
    assert!(run.stdout.contains("failing     0:"), "{}", run.stdout);
    assert!(run.stdout.trim_end().ends_with("PASS"), "{}", run.stdout);
    let v = json(&[gallery(), &again], 0);
    assert_eq!(v["equal"], 320 * 240);
    assert_eq!(
        v["psnr_db"],
        Value::Null,
        "identical: PSNR is ∞, written null"
    );
}

#[test]
fn one_flipped_pixel_fails_and_is_listed() {
    let bad = flipped("flipped.png", 123, 45);
    let run = expect(1, &[gallery(), &bad]);
    let want = rgb(gallery()).get_pixel(123, 45).0;
    let got = want.map(|v| 255 - v);
    let hex = |c: [u8; 3]| format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]);
    let line = format!("(123, 45) {} {}", hex(want), hex(got));
    assert!(run.stdout.contains(&line), "{line:?} in\n{}", run.stdout);
    assert!(
        run.stdout.contains("FAIL: 1 of 76800 pixels"),
        "{}",
        run.stdout
    );

    let v = json(&[gallery(), &bad], 1);
    assert_eq!(v["failures"], 1);
    assert_eq!(
        v["missing"].as_u64().unwrap()
            + v["unexpected"].as_u64().unwrap()
            + v["differing"].as_u64().unwrap(),
        1
    );
    assert_eq!(v["equal"], 320 * 240 - 1);
    assert_eq!(v["passed"], false);
    assert_eq!(v["mismatches"][0]["x"], 123);
    assert_eq!(v["mismatches"][0]["y"], 45);
    assert_eq!(v["mismatches"][0]["expected"][0], want[0]);
    assert_eq!(v["mismatches"][0]["actual"][0], got[0]);
    assert!(v["psnr_db"].as_f64().is_some_and(|p| p > 40.0), "{v}");
    assert!(v["max_error"].as_u64().is_some_and(|m| m > 0), "{v}");

    // The same difference within a tolerance of its size passes.
    let max = v["max_error"].as_u64().unwrap().to_string();
    let v = json(&[gallery(), &bad, "--tolerance", &max], 0);
    assert_eq!(v["within_tolerance"], 1);
}

#[test]
fn the_mask_marks_the_flipped_pixel_on_the_dimmed_frame() {
    let bad = flipped("mask-src.png", 200, 100);
    let mask = tmp("mask.png");
    expect(1, &[gallery(), &bad, "--mask", &mask]);
    let m = rgb(&mask);
    assert_eq!(m.dimensions(), (320, 240));
    assert_eq!(m.get_pixel(200, 100).0, ::compare::MASK_FAIL);
    let g = rgb(gallery());
    let dim = |c: [u8; 3]| c.map(|v| (u16::from(v) * 3 / 10) as u8);
    assert_eq!(m.get_pixel(0, 0).0, dim(g.get_pixel(0, 0).0));
    assert_eq!(m.get_pixel(319, 239).0, dim(g.get_pixel(319, 239).0));
}

#[test]
fn unusable_input_is_status_2_naming_the_file() {
    let g = gallery();
    let cropped = tmp("cropped.png");
    image::imageops::crop_imm(&rgb(g), 0, 0, 319, 240)
        .to_image()
        .save(&cropped)
        .expect("write PNG");
    let err = expect(2, &[g, &cropped]).stderr;
    assert!(err.contains(g) && err.contains(&cropped), "{err}");
    assert!(err.contains("320×240") && err.contains("319×240"), "{err}");

    let bmp = tmp("frame.bmp");
    std::fs::copy(g, &bmp).expect("copy");
    let err = expect(2, &[g, &bmp]).stderr;
    assert!(
        err.contains(&bmp) && err.contains("unknown frame format"),
        "{err}"
    );

    let missing = tmp("does-not-exist.png");
    let err = expect(2, &[&missing, g]).stderr;
    assert!(
        err.contains(&missing) && err.contains("cannot read"),
        "{err}"
    );

    let not_png = tmp("not-a.png");
    std::fs::write(&not_png, "hello").expect("write");
    let err = expect(2, &[g, &not_png]).stderr;
    assert!(err.contains(&not_png) && err.contains("PNG"), "{err}");

    let headless = tmp("headless.hex");
    std::fs::write(&headless, "00\n01\n").expect("write");
    let err = expect(2, &[&headless, g]).stderr;
    assert!(err.contains(&headless) && err.contains("header"), "{err}");

    let err = expect(2, &[g, g, "--tolerance", "1.5"]).stderr;
    assert!(err.contains("--tolerance 1.5"), "{err}");
    let err = expect(2, &[g, g, "--coverage-precision", "4"]).stderr;
    assert!(
        err.contains("--coverage-precision 4") && err.contains("--raster"),
        "{err}"
    );
    let nope = tmp("nope.toml");
    let err = expect(2, &[g, g, "--raster", &nope]).stderr;
    assert!(err.contains("nope.toml"), "{err}");
}

#[test]
fn a_memh_framebuffer_equals_the_png_of_the_same_frame() {
    let hex = tmp("gallery.hex");
    to_memh(gallery(), PixelFormat::Rgb888, &hex);
    expect(0, &[&hex, gallery()]);
    expect(0, &[gallery(), &hex]);

    // The FITkit job's colours are RGB332 values: its framebuffer in RGB332, expanded by
    // bit replication, is the PNG exactly.
    let png = tmp("fitkit.png");
    raster(&example("raster/fitkit.toml"), &png);
    let hex = tmp("fitkit.hex");
    to_memh(&png, PixelFormat::Rgb332, &hex);
    assert!(std::fs::read_to_string(&hex)
        .expect("written")
        .starts_with("// fpgfx framebuffer 320x240 rgb332\n"));
    expect(0, &[&hex, &png]);
    // And one RGB332 step of red (36 or 37 levels) is beyond 35 but within 37.
    let mut img = rgb(&png);
    let p = img.get_pixel_mut(0, 0);
    p.0[0] = if p.0[0] >= 36 {
        p.0[0] - 36
    } else {
        p.0[0] + 36
    };
    let stepped = tmp("fitkit-step.png");
    img.save(&stepped).expect("write PNG");
    expect(1, &[&hex, &stepped, "--tolerance", "35"]);
    expect(0, &[&hex, &stepped, "--tolerance", "37"]);
}

/// A flat triangle whose vertical left side lies at `x` px: at 20.5 ± 1/32 the centres of
/// column 20 fall outside or inside, 2^-5 px from the side.
fn triangle_job(name: &str, x: f64) -> String {
    let path = tmp(name);
    let text = format!(
        "size = [48, 32]\nbackground = \"#000000\"\nsubpixel_bits = 8\n\n[[cmd]]\nop = \"triangle\"\n\
         v = [[{x:?}, 2.0], [{x:?}, 30.0], [44.0, 16.0]]\ncolor = \"#ff8000\"\n"
    );
    std::fs::write(&path, text).expect("write job");
    path
}

#[test]
fn the_coverage_allowance_accepts_a_shifted_edge_within_its_precision_only() {
    // The same triangle rasterised with its left side 1/16 px further left: a rasteriser
    // that snaps or biases its edges differently by that much.
    let (job, moved) = (
        triangle_job("tri.toml", 20.5 + 1.0 / 32.0),
        triangle_job("tri-moved.toml", 20.5 - 1.0 / 32.0),
    );
    let (want, got) = (tmp("tri.png"), tmp("tri-moved.png"));
    raster(&job, &want);
    raster(&moved, &got);
    // Exact: column 20 (rows 2..=29) is unexpected.
    let v = json(&[&want, &got], 1);
    assert_eq!(v["unexpected"], 28);
    // Column 20's centres lie 2^-5 px from the expected side: allowed at 5 bits ...
    let v = json(
        &[&want, &got, "--raster", &job, "--coverage-precision", "5"],
        0,
    );
    assert_eq!(
        (v["near_edge"].as_u64(), v["failures"].as_u64()),
        (Some(28), Some(0))
    );
    assert_eq!(v["coverage"]["edges"], 3);
    // ... not at 6, nor at the job's own 8 bits (--raster alone).
    let run = expect(
        1,
        &[&want, &got, "--raster", &job, "--coverage-precision", "6"],
    );
    assert!(
        run.stdout.contains("(20, 2) #000000 #ff8000 unexpected"),
        "{}",
        run.stdout
    );
    let v = json(&[&want, &got, "--raster", &job], 1);
    assert_eq!(
        (v["coverage"]["bits"].as_u64(), v["unexpected"].as_u64()),
        (Some(8), Some(28))
    );

    // In an `fpgfx vectors` directory the job is found beside the expected frame.
    let dir = tmp("vectors");
    std::fs::create_dir_all(&dir).expect("mkdir");
    let expected = format!("{dir}/expected_framebuffer.hex");
    to_memh(&want, PixelFormat::Rgb888, &expected);
    std::fs::copy(&job, format!("{dir}/job.toml")).expect("copy job");
    expect(0, &[&expected, &got, "--coverage-precision", "5"]);
    expect(1, &[&expected, &got, "--coverage-precision", "6"]);
}

#[test]
fn bresenham_and_dda_differ_only_at_ties_which_the_line_outline_allows() {
    let job = |algo: &str| {
        let path = tmp(&format!("line-{algo}.toml"));
        let text = format!(
            "size = [64, 48]\nsubpixel_bits = 4\n[[cmd]]\nop = \"line\"\nfrom = [2.0, 3.0]\n\
             to = [60.0, 20.0]\ncolor = \"#ffffff\"\nalgorithm = \"{algo}\"\n"
        );
        std::fs::write(&path, text).expect("write job");
        path
    };
    let (bres, dda) = (job("bresenham"), job("dda"));
    let (a, b) = (tmp("bresenham.png"), tmp("dda.png"));
    raster(&bres, &a);
    raster(&dda, &b);
    // Column 31 is the tie (3 + 17·29/58 = 11.5): one picks row 12, the other row 11.
    let v = json(&[&a, &b], 1);
    assert_eq!(
        (v["missing"].as_u64(), v["unexpected"].as_u64()),
        (Some(1), Some(1))
    );
    // Both centres lie on the outline's long sides, whatever the precision.
    let v = json(
        &[&a, &b, "--raster", &bres, "--coverage-precision", "16"],
        0,
    );
    assert_eq!(v["near_edge"], 2);
}

#[test]
fn pfm_planes_report_absolute_and_relative_error() {
    let write = |name: &str, channels: usize, data: &[f32]| {
        let path = tmp(name);
        let file = std::fs::File::create(&path).expect("create");
        sim_target::rt::write_pfm(file, 2, 2, channels, data).expect("write PFM");
        path
    };
    let inf = f32::INFINITY;
    let e = write("depth.pfm", 1, &[1.0, 2.0, inf, 4.0]);
    let a = write("depth-bad.pfm", 1, &[1.0, 2.5, inf, inf]);
    expect(0, &[&e, &e]);
    let v = json(&[&e, &a], 1);
    assert_eq!(v["kind"], "float");
    assert_eq!(
        (v["differing"].as_u64(), v["missing"].as_u64()),
        (Some(1), Some(1))
    );
    assert_eq!(v["max_abs_error"], 0.5);
    assert_eq!(v["max_rel_error"], 0.25);
    assert_eq!(v["background"], Value::Null);
    assert_eq!(v["mismatches"][1]["actual"][0], "inf");
    // A tolerance of 0.5 (not whole levels: PFM takes its own unit) lets the 0.5 through;
    // a lost hit stays missing.
    let v = json(&[&e, &a, "--tolerance", "0.5"], 1);
    assert_eq!(
        (v["within_tolerance"].as_u64(), v["failures"].as_u64()),
        (Some(1), Some(1))
    );
    // A depth plane is not a normal plane nor a colour frame.
    let n = write("normal.pfm", 3, &[0.0; 12]);
    let err = expect(2, &[&e, &n]).stderr;
    assert!(
        err.contains("1-channel float") && err.contains("3-channel float"),
        "{err}"
    );
    let err = expect(2, &[&e, gallery()]).stderr;
    assert!(err.contains("kinds differ"), "{err}");
}
