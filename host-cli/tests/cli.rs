//! The `fpgfx` binary on bad input: a one-line error that says what and where, exit
//! status 1, no panic, no backtrace (the common runner checks those two on every run);
//! and on good input, a PNG.

mod common;

use common::{example, fails, ok, tmp};

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

    let err = fails(&["render", "x.toml", "--numeric", "q9.9"]);
    assert!(err.contains("cannot read") || err.contains("q9.9"), "{err}");
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
