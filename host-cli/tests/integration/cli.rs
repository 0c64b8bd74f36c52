//! The `fpgfx` binary on bad input: a one-line error that says what and where, exit
//! status 1, no panic, no backtrace (the common runner checks those two on every run);
//! and on good input, a PNG.

use crate::common::{example, fails, ok, refused, tmp};

/// A scratch file with this text; returns its path.
fn temp(name: &str, text: &str) -> String {
    let path = tmp(name);
    std::fs::write(&path, text).expect("write temp file");
    path
}

#[test]
fn bad_inputs_are_reported_with_place_and_status_1() {
    let err = fails(&["render", "does-not-exist.toml"]);
    assert!(err.contains("cannot read does-not-exist.toml"), "{err}");

    let scene = temp("bad.toml", "[render]\nsize = [10, 10]\nfoo = 1\n");
    let err = fails(&["render", &scene]);
    assert!(err.contains("bad.toml:3") && err.contains("foo"), "{err}");

    let cmds = temp(
        "bad2.toml",
        "size = [10, 10]\n[[cmd]]\nop = \"triangle\"\nv = [[1, 2], [3, 4]]\ncolor = \"#ffffff\"\n",
    );
    let err = fails(&["raster", &cmds]);
    assert!(err.contains("bad2.toml:2: cmd[0] (triangle)"), "{err}");

    // A value no flag takes is refused by the parser, which lists the ones it does.
    let err = refused(&["render", "x.toml", "--numeric", "q9.9"]);
    assert!(err.contains("'q9.9'"), "{err}");
    assert!(
        err.contains("[possible values: f64, f32, f16, q16.16, q8.24, q24.8, q32.32]"),
        "{err}"
    );
}

#[test]
fn raster_writes_the_gallery_png() {
    let out = tmp("gallery.png");
    ok(&[
        "raster",
        &example("raster/gallery.toml"),
        "-o",
        &out,
        "--stats",
    ]);
    let png = image::open(&out).expect("a PNG was written").to_rgb8();
    assert_eq!(png.dimensions(), (320, 240));
}

/// `--numeric`, `--traversal` and `--packing` take the library's own spellings: the
/// parser lists them on a mistake, and a format keeps its old case- and `_`-tolerance.
#[test]
fn enum_flags_take_the_library_spellings() {
    let err = refused(&["raster", "x.toml", "--traversal", "hilbert"]);
    assert!(
        err.contains("[possible values: bbox, scanline, zigzag, tiles, simd8]"),
        "{err}"
    );
    let err = refused(&["render", "x.toml", "--packing", "rgb565"]);
    assert!(err.contains("[possible values: rgb888, kcu116]"), "{err}");
    let out = tmp("q16.png");
    ok(&[
        "render",
        &example("reference.toml"),
        "--size",
        "16x9",
        "--numeric",
        "Q16_16",
        "--packing",
        "kcu116",
        "-o",
        &out,
    ]);
    let png = image::open(&out).expect("a PNG was written").to_rgb8();
    assert_eq!(png.dimensions(), (16, 9));
}

/// A scene beyond a format's range is said out loud before rendering, field by field; a
/// format that holds it says nothing.
#[test]
fn render_warns_of_fields_beyond_the_formats_range() {
    let scene = example("reference.toml");
    let out = tmp("range.png");
    let args = |n| {
        [
            "render",
            &scene,
            "--size",
            "16x9",
            "--numeric",
            n,
            "-o",
            &out,
        ]
    };
    let narrow = ok(&args("q8.24"));
    for field in ["lights[0].color", "objects[6].scale", "camera.position"] {
        assert!(
            narrow
                .stderr
                .contains(&format!("reference.toml: {field}: the ")),
            "{field} not named:\n{}",
            narrow.stderr
        );
    }
    assert!(
        narrow.stderr.contains("beyond q8.24's range of ±128"),
        "{}",
        narrow.stderr
    );
    let wide = ok(&args("q16.16"));
    assert!(!wide.stderr.contains("warning"), "{}", wide.stderr);
}
