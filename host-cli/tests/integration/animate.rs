//! `fpgfx animate`: scripts drive the scene or the raster block frame by frame; only
//! changed registers cross the link; each frame equals a plain render of the scene the
//! script produced; script and scene errors name the script, the frame and the line.

use crate::common::{
    assert_no_panic, collect, example, fails, fpgfx_command, ok, rgb, start_sim, tmp,
};

/// `fpgfx --port builtin ARGS…` must succeed; returns its stdout.
fn builtin_ok(args: &[&str]) -> String {
    ok(&[&["--port", "builtin"], args].concat()).stdout
}

/// `fpgfx --port builtin ARGS…` must fail with status 1; returns its stderr.
fn builtin_fails(args: &[&str]) -> String {
    fails(&[&["--port", "builtin"], args].concat())
}

#[test]
fn viray_demo_sends_only_what_moves_and_matches_plain_renders() {
    let script = example("anim/viray.rhai");
    let (pngs, tomls) = (tmp("v-%02d.png"), tmp("v-%02d.toml"));
    let stdout = builtin_ok(&[
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
    builtin_ok(&["render", &frame2, "--size", "64x36", "-o", &plain]);
    let (a, b) = (rgb(&tmp("v-02.png")), rgb(&plain));
    assert!(a == b, "frame 2 differs from a plain render of its scene");
    let a0 = rgb(&tmp("v-00.png"));
    assert!(a0 != a, "the animation does not move");
}

#[test]
fn raster_script_writes_a_gif() {
    let script = example("anim/spin.rhai");
    let gif = tmp("spin.gif");
    builtin_ok(&[
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
    let reference = example("reference.toml");
    // `animate SCRIPT --scene reference.toml -o OUT EXTRA…`, which must fail.
    let animate = |script: &str, out: &str, extra: &[&str]| {
        let base = ["animate", script, "--scene", &reference, "-o", out];
        builtin_fails(&[&base[..], extra].concat())
    };
    let three_frames = ["--size", "16x9", "--frames", "3"];

    let syntax = write(
        "syntax.rhai",
        "fn scene(s, frame, time) {\n    s.camera.fov_y = ;\n    s\n}\n",
    );
    let err = animate(&syntax, &tmp("x.gif"), &[]);
    assert!(
        err.contains("syntax.rhai") && err.contains("line 2"),
        "{err}"
    );

    let runtime = write(
        "runtime.rhai",
        "fn scene(s, frame, time) {\n    if frame == 2 { s.nothing.here = 1; }\n    s\n}\n",
    );
    let err = animate(&runtime, &tmp("y-%d.png"), &three_frames);
    assert!(
        err.contains("runtime.rhai: frame 2") && err.contains("line 2"),
        "{err}"
    );

    let bad_scene = write(
        "fov.rhai",
        "fn scene(s, frame, time) {\n    s.camera.fov_y = 45.0 + 140.0 * frame;\n    s\n}\n",
    );
    let err = animate(&bad_scene, &tmp("z-%d.png"), &three_frames);
    assert!(
        err.contains("fov.rhai frame 1") && err.contains("fov_y"),
        "{err}"
    );

    let neither = write("neither.rhai", "fn other() { 1 }\n");
    let err = builtin_fails(&["animate", &neither, "-o", &tmp("n.gif")]);
    assert!(err.contains("define exactly one of"), "{err}");

    let err = animate(&bad_scene, &tmp("n.png"), &[]);
    assert!(err.contains("frame-number placeholder"), "{err}");
}

/// `--interactive` on a real terminal (a pty as stdin): three → presses turn the camera
/// 30° about look_at before frame 0, and q stops the run early.
#[test]
fn interactive_keys_orbit_the_camera_and_q_quits() {
    use std::io::{BufRead, BufReader, Write};
    use std::process::Stdio;
    let (mut master, slave) = serialport::TTYPort::pair().expect("pty pair");
    let tty = serialport::SerialPort::name(&slave).expect("pty path");
    let stdin = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(&tty)
        .expect("open the pty as a file");
    drop(slave);
    let script = example("anim/viray.rhai");
    let tomls = tmp("i-%02d.toml");
    master.write_all(b"\x1b[C\x1b[C\x1b[C").expect("keys");
    let mut child = fpgfx_command(&[
        "--port",
        "builtin",
        "animate",
        &script,
        "--interactive",
        "--frames",
        "50",
        "--size",
        "32x18",
        "-o",
        &tmp("i-%02d.png"),
        "--save-frames",
        &tomls,
    ])
    .stdin(Stdio::from(stdin))
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .expect("fpgfx runs");
    let (stderr, stderr_reader) = collect(child.stderr.take().expect("stderr"));
    let mut out = BufReader::new(child.stdout.take().expect("stdout"));
    let mut line = String::new();
    while out.read_line(&mut line).expect("reads") > 0 && !line.contains("frame    1") {
        line.clear();
    }
    master.write_all(b"q").expect("q");
    let status = child.wait().expect("fpgfx ends");
    let _ = stderr_reader.join();
    let stderr = String::from_utf8_lossy(&stderr.lock().expect("stderr lock")).into_owned();
    assert_no_panic(&stderr);
    assert!(status.success(), "{status}: {stderr}");
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut out, &mut rest).expect("reads");
    let frames: u32 = rest
        .lines()
        .find_map(|l| l.strip_prefix("total "))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .expect("a total line");
    assert!(frames < 50, "q did not stop the run ({frames} frames)");

    let position = |path: &str| -> [f64; 3] {
        let v: toml::Value =
            toml::from_str(&std::fs::read_to_string(path).expect("toml")).expect("a scene");
        let p = v["camera"]["position"]
            .as_array()
            .expect("position")
            .clone();
        [0, 1, 2].map(|i| p[i].as_float().expect("float"))
    };
    // The reference camera: eye (0, 2.2, 9) looking at (0, 0.3, 0).
    let p = position(&tmp("i-00.toml"));
    let (dx, dz) = (p[0], p[2]);
    let yaw = dx.atan2(dz).to_degrees();
    assert!((yaw - 30.0).abs() < 1e-6, "camera yaw {yaw}°, expected 30°");
    let r = (dx * dx + (p[1] - 0.3).powi(2) + dz * dz).sqrt();
    let r0 = (1.9f64.powi(2) + 81.0).sqrt();
    assert!(
        (r - r0).abs() < 1e-9,
        "orbit changed the distance: {r} vs {r0}"
    );
}

/// Over a serial line (`fpgfx-sim --pty`) the frames equal built-in mode's.
#[test]
fn animate_over_a_pty_matches_built_in() {
    let sim = start_sim(&[]);
    let script = example("anim/viray.rhai");
    let run = |port: &str, pattern: &str| {
        ok(&[
            "--port", port, "animate", &script, "--frames", "2", "--size", "32x18", "-o", pattern,
        ]);
    };
    run(&sim.pty, &tmp("p-%d.png"));
    run("builtin", &tmp("b-%d.png"));
    drop(sim);
    for f in 0..2 {
        let a = rgb(&tmp(&format!("p-{f}.png")));
        let b = rgb(&tmp(&format!("b-{f}.png")));
        assert!(
            a == b,
            "frame {f} differs between the pty board and built-in"
        );
    }
}
