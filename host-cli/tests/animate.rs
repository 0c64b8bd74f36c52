//! `fpgfx animate`: scripts drive the scene or the raster block frame by frame; only
//! changed registers cross the link; each frame equals a plain render of the scene the
//! script produced; script and scene errors name the script, the frame and the line.

use std::process::Command;

fn root() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/..").to_string()
}

fn tmp(name: &str) -> String {
    std::env::temp_dir()
        .join(format!("fpgfx-anim-{}-{name}", std::process::id()))
        .display()
        .to_string()
}

fn fpgfx(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_fpgfx"))
        .args(["--port", "builtin"])
        .args(args)
        .output()
        .expect("fpgfx runs")
}

fn ok(args: &[&str]) -> String {
    let out = fpgfx(args);
    assert!(
        out.status.success(),
        "fpgfx {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn fails(args: &[&str]) -> String {
    let out = fpgfx(args);
    assert_eq!(out.status.code(), Some(1), "fpgfx {args:?} should fail");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn viray_demo_sends_only_what_moves_and_matches_plain_renders() {
    let script = format!("{}/examples/anim/viray.rhai", root());
    let (pngs, tomls) = (tmp("v-%02d.png"), tmp("v-%02d.toml"));
    let stdout = ok(&[
        "animate",
        &script,
        "--frames",
        "3",
        "--fps",
        "4",
        "--size",
        "64x36",
        "-o",
        &pngs,
        "--save-frames",
        &tomls,
    ]);
    let words: Vec<u32> = stdout
        .lines()
        .filter(|l| l.starts_with("frame"))
        .map(|l| {
            l.split("register words")
                .next()
                .and_then(|p| p.split_whitespace().last())
                .and_then(|w| w.parse().ok())
                .unwrap_or_else(|| panic!("no word count in {l:?}"))
        })
        .collect();
    assert_eq!(words.len(), 3, "{stdout}");
    assert!(words[0] > 200, "frame 0 sends the scene: {words:?}");
    // Light position x/z and direction (5), floor texture offset (1), sphere y (1), and
    // nothing else.
    for w in &words[1..] {
        assert!(
            (1..=8).contains(w),
            "later frames send only what moved: {words:?}"
        );
    }
    let frame2 = tmp("v-02.toml");
    let plain = tmp("plain.png");
    ok(&["render", &frame2, "--size", "64x36", "-o", &plain]);
    let a = image::open(tmp("v-02.png")).expect("frame 2").to_rgb8();
    let b = image::open(&plain).expect("plain render").to_rgb8();
    assert!(a == b, "frame 2 differs from a plain render of its scene");
    let a0 = image::open(tmp("v-00.png")).expect("frame 0").to_rgb8();
    assert!(a0 != a, "the animation does not move");
}

#[test]
fn raster_script_writes_a_gif() {
    let script = format!("{}/examples/anim/spin.rhai", root());
    let gif = tmp("spin.gif");
    ok(&[
        "animate", &script, "--frames", "3", "--fps", "10", "-o", &gif,
    ]);
    use image::AnimationDecoder;
    let file = std::io::BufReader::new(std::fs::File::open(&gif).expect("gif written"));
    let frames = image::codecs::gif::GifDecoder::new(file)
        .expect("a GIF")
        .into_frames()
        .collect_frames()
        .expect("frames decode");
    assert_eq!(frames.len(), 3);
    assert_eq!(frames[0].buffer().dimensions(), (160, 120));
    assert!(
        frames[0].buffer() != frames[1].buffer(),
        "the fan does not turn"
    );
    let (n, d) = frames[0].delay().numer_denom_ms();
    assert_eq!(n / d.max(1), 100, "10 fps is 100 ms a frame");
}

#[test]
fn script_errors_name_the_script_frame_and_line() {
    let dir = tmp("scripts");
    std::fs::create_dir_all(&dir).expect("dir");
    let write = |name: &str, text: &str| {
        let p = format!("{dir}/{name}");
        std::fs::write(&p, text).expect("write");
        p
    };
    let reference = format!("{}/examples/reference.toml", root());
    let syntax = write(
        "syntax.rhai",
        "fn scene(s, frame, time) {\n    s.camera.fov_y = ;\n    s\n}\n",
    );
    let err = fails(&[
        "animate",
        &syntax,
        "--scene",
        &reference,
        "-o",
        &tmp("x.gif"),
    ]);
    assert!(
        err.contains("syntax.rhai") && err.contains("line 2"),
        "{err}"
    );

    let runtime = write(
        "runtime.rhai",
        "fn scene(s, frame, time) {\n    if frame == 2 { s.nothing.here = 1; }\n    s\n}\n",
    );
    let err = fails(&[
        "animate",
        &runtime,
        "--scene",
        &reference,
        "--size",
        "16x9",
        "--frames",
        "3",
        "-o",
        &tmp("y-%d.png"),
    ]);
    assert!(
        err.contains("runtime.rhai: frame 2") && err.contains("line 2"),
        "{err}"
    );

    let bad_scene = write(
        "fov.rhai",
        "fn scene(s, frame, time) {\n    s.camera.fov_y = 45.0 + 140.0 * frame;\n    s\n}\n",
    );
    let err = fails(&[
        "animate",
        &bad_scene,
        "--scene",
        &reference,
        "--size",
        "16x9",
        "--frames",
        "3",
        "-o",
        &tmp("z-%d.png"),
    ]);
    assert!(
        err.contains("fov.rhai frame 1") && err.contains("fov_y"),
        "{err}"
    );

    let neither = write("neither.rhai", "fn other() { 1 }\n");
    let err = fails(&["animate", &neither, "-o", &tmp("n.gif")]);
    assert!(err.contains("define exactly one of"), "{err}");

    let err = fails(&[
        "animate",
        &bad_scene,
        "--scene",
        &reference,
        "-o",
        &tmp("n.png"),
    ]);
    assert!(err.contains("frame-number placeholder"), "{err}");
}
