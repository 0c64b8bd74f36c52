//! The `fpgfx` binary on bad input: a one-line error that says what and where, exit
//! status 1, no panic, no backtrace; and on good input, a PNG.

use std::process::Command;

fn fpgfx(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_fpgfx"))
        .args(args)
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("fpgfx runs");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!stderr.contains("Stack backtrace"), "{stderr}");
    (out.status.code().unwrap_or(-1), stderr)
}

fn temp(name: &str, text: &str) -> String {
    let dir = std::env::temp_dir().join(format!("fpgfx-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write temp file");
    path.display().to_string()
}

#[test]
fn bad_inputs_are_reported_with_place_and_status_1() {
    let (code, err) = fpgfx(&["render", "does-not-exist.toml"]);
    assert_eq!(code, 1);
    assert!(err.contains("cannot read does-not-exist.toml"), "{err}");

    let scene = temp("bad.toml", "[render]\nsize = [10, 10]\nfoo = 1\n");
    let (code, err) = fpgfx(&["render", &scene]);
    assert_eq!(code, 1);
    assert!(err.contains("bad.toml:3") && err.contains("foo"), "{err}");

    let cmds = temp(
        "bad2.toml",
        "size = [10, 10]\n[[cmd]]\nop = \"triangle\"\nv = [[1, 2], [3, 4]]\ncolor = \"#ffffff\"\n",
    );
    let (code, err) = fpgfx(&["raster", &cmds]);
    assert_eq!(code, 1);
    assert!(err.contains("bad2.toml:2: cmd[0] (triangle)"), "{err}");

    let (code, err) = fpgfx(&["render", "x.toml", "--numeric", "q9.9"]);
    assert_eq!(code, 1);
    assert!(err.contains("cannot read") || err.contains("q9.9"), "{err}");
}

#[test]
fn raster_writes_the_gallery_png() {
    let out = std::env::temp_dir().join(format!("fpgfx-gallery-{}.png", std::process::id()));
    let gallery = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/raster/gallery.toml"
    );
    let (code, err) = fpgfx(&[
        "raster",
        gallery,
        "-o",
        &out.display().to_string(),
        "--stats",
    ]);
    assert_eq!(code, 0, "{err}");
    let png = image::open(&out).expect("a PNG was written").to_rgb8();
    assert_eq!(png.dimensions(), (320, 240));
}
