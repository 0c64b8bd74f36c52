//! Every command checks its outputs before it works: an output it could not write at the
//! end (a format it does not write, a directory that is missing or is a file) is refused
//! at once, naming the flag and the path. "At once" is asserted by what did not happen:
//! the target was not opened (a `--port` that does not exist is not complained about),
//! no frame was rendered (nothing printed per frame, no other output written), no
//! comparison was reported.

use crate::common::{example, fails, fpgfx, tmp};

/// A port that does not exist: opening it fails with "serial port … does not exist", so
/// a refusal that names the output instead came before the target was opened.
const NO_PORT: &str = "/dev/fpgfx-test-no-such-port";

/// A directory that does not exist, in this module's scratch space.
fn missing_dir() -> String {
    let dir = tmp("no-such-dir");
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// An existing regular file (for an output that must be a directory, or sit in one).
fn a_file() -> String {
    let path = tmp("a-file.txt");
    std::fs::write(&path, "not a directory\n").expect("scratch file");
    path
}

#[test]
fn render_refuses_a_jpeg_before_opening_the_target() {
    let out = tmp("frame.jpg");
    let scene = example("reference.toml");
    let err = fails(&["--port", NO_PORT, "render", &scene, "-o", &out, "--stats"]);
    assert!(err.contains(&format!("-o/--output {out}")), "{err}");
    assert!(err.contains("PNG") && err.contains(".png"), "{err}");
    assert!(
        !err.contains("serial port"),
        "the target was opened first: {err}"
    );
    assert!(!std::path::Path::new(&out).exists());
}

#[test]
fn render_refuses_an_aov_it_could_not_write_before_rendering() {
    let out = tmp("aov-frame.png");
    let _ = std::fs::remove_file(&out);
    let scene = example("reference.toml");
    let aov = format!("depth={}/d.pfm", missing_dir());
    // On the built-in target a small frame renders in a moment: had it rendered, the
    // frame would be written (and --stats printed) before the AOV failed.
    let run = fpgfx(&[
        "--port", "builtin", "render", &scene, "--size", "32x18", "-o", &out, "--aov", &aov,
        "--stats",
    ]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr.contains(&format!("--aov {aov}")),
        "{}",
        run.stderr
    );
    assert!(run.stderr.contains("does not exist"), "{}", run.stderr);
    assert!(run.stdout.is_empty(), "rendered first: {}", run.stdout);
    assert!(
        !std::path::Path::new(&out).exists(),
        "the frame was written first"
    );

    let err = fails(&[
        "--port",
        NO_PORT,
        "render",
        &scene,
        "-o",
        &out,
        "--aov",
        "normal=n.exr",
    ]);
    assert!(
        err.contains("--aov normal=n.exr") && err.contains("PFM"),
        "{err}"
    );
}

#[test]
fn raster_refuses_a_bad_output_before_opening_the_target() {
    let file = example("raster/gallery.toml");
    let out = tmp("raster.bmp");
    let err = fails(&["--port", NO_PORT, "raster", &file, "-o", &out]);
    assert!(
        err.contains(&format!("-o/--output {out}")) && err.contains("PNG"),
        "{err}"
    );
    assert!(!err.contains("serial port"), "{err}");

    let out = format!("{}/raster.png", missing_dir());
    let err = fails(&["--port", NO_PORT, "raster", &file, "-o", &out]);
    assert!(err.contains(&format!("-o/--output {out}")), "{err}");
    assert!(err.contains("does not exist"), "{err}");

    // a directory where the file should go
    let dir = tmp("a-directory.png");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let err = fails(&["--port", NO_PORT, "raster", &file, "-o", &dir]);
    assert!(
        err.contains(&format!("-o/--output {dir}: is a directory")),
        "{err}"
    );
}

#[test]
fn animate_refuses_an_output_it_could_not_write_before_the_first_frame() {
    let script = example("anim/spin.rhai");
    let gif = format!("{}/spin.gif", missing_dir());
    let args = [
        "--port", "builtin", "animate", &script, "--frames", "3", "-o", &gif,
    ];
    let run = fpgfx(&args);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr.contains(&format!("-o/--output {gif}")),
        "{}",
        run.stderr
    );
    assert!(run.stderr.contains("does not exist"), "{}", run.stderr);
    // animate prints a line per frame as it renders it
    assert!(
        !run.stdout.contains("frame"),
        "frames rendered first: {}",
        run.stdout
    );

    let pngs = format!("{}/f-%04d.png", missing_dir());
    let err = fails(&["--port", NO_PORT, "animate", &script, "-o", &pngs]);
    assert!(err.contains(&format!("-o/--output {pngs}")), "{err}");
    assert!(!err.contains("serial port"), "{err}");

    let gif = tmp("ok.gif");
    let saved = format!("{}/f-%d.toml", missing_dir());
    let args = [
        "--port",
        "builtin",
        "animate",
        &script,
        "--frames",
        "3",
        "-o",
        &gif,
        "--save-frames",
        &saved,
    ];
    let run = fpgfx(&args);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr.contains(&format!("--save-frames {saved}")),
        "{}",
        run.stderr
    );
    assert!(
        !run.stdout.contains("frame"),
        "frames rendered first: {}",
        run.stdout
    );
}

#[test]
fn compare_refuses_a_mask_it_does_not_write_before_comparing() {
    let golden = example("raster/golden/gallery.png");
    let mask = tmp("mask.jpg");
    let run = fpgfx(&["compare", &golden, &golden, "--mask", &mask]);
    assert_eq!(run.code, Some(2), "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains(&format!("--mask {mask}")),
        "{}",
        run.stderr
    );
    assert!(run.stderr.contains("PNG"), "{}", run.stderr);
    assert!(run.stdout.is_empty(), "compared first: {}", run.stdout);

    let mask = format!("{}/mask.png", missing_dir());
    let run = fpgfx(&["compare", &golden, &golden, "--mask", &mask]);
    assert_eq!(run.code, Some(2), "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains(&format!("--mask {mask}")),
        "{}",
        run.stderr
    );
    assert!(run.stderr.contains("does not exist"), "{}", run.stderr);
}

#[test]
fn vectors_and_bench_refuse_an_output_directory_that_is_a_file() {
    let file = a_file();
    let job = example("raster/gallery.toml");
    let err = fails(&["vectors", "raster", &job, "-o", &file]);
    assert!(err.contains(&format!("-o/--output {file}")), "{err}");
    assert!(err.contains("is a file, not a directory"), "{err}");

    let under = format!("{file}/vectors");
    let scene = example("reference.toml");
    let err = fails(&["vectors", "render", &scene, "-o", &under]);
    assert!(err.contains(&format!("-o/--output {under}")), "{err}");
    assert!(err.contains("is a file, not a directory"), "{err}");

    // With a scene that does not exist either: the output is refused first, before the
    // sweep would read (and then run) anything.
    let missing_scene = tmp("no-such-scene.toml");
    let err = fails(&["bench", "--quick", "--scene", &missing_scene, "-o", &file]);
    assert!(err.contains(&format!("-o/--output {file}")), "{err}");
    assert!(err.contains("is a file, not a directory"), "{err}");
    assert!(!err.contains("cannot read"), "{err}");
}
