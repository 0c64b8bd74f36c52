//! libfpgfx from C: `tests/c/test_fpgfx.c` is compiled with the system C compiler against
//! `include/fpgfx.h` and linked with the staticlib cargo built next to this test, then run
//! on vectors written the way `fpgfx vectors render` writes them and on raster jobs
//! packed into FIFO records here, whose expected frames come from the built-in target.
//! The C program prints `N passed, M failed`; any failure, a missing compiler or a
//! compile error fails the test.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

use protocol::bus::LayoutId;
use protocol::frame::Numeric;
use vectors::render as render_vectors;

/// The package root (`capi/`).
fn capi() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A scratch directory for this process: concurrent runs never collide, and after a
/// failure the vectors are left for a look.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("fpgfx-capi-{}", std::process::id()))
        .join(name);
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

/// `libfpgfx.a` as cargo built it for this test run. The library's two crate types come
/// from one compilation, but cargo copies the staticlib up to `target/<profile>/` only
/// when the package itself is built (`cargo build -p fpgfx-capi`); for a test it stays in
/// `deps/` under a hashed name. So: the newest `libfpgfx*.a` of the test binary's
/// profile, which must be newer than every source of the crate.
fn staticlib() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary has a path");
    let deps = exe
        .parent()
        .expect("the test binary sits in target/<profile>/deps");
    let profile = deps.parent().expect("deps sits in a profile directory");
    let modified = |p: &Path| p.metadata().and_then(|m| m.modified()).ok();
    let candidates = std::fs::read_dir(deps)
        .expect("the deps directory")
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("libfpgfx-") && n.ends_with(".a"))
        })
        .chain(Some(profile.join("libfpgfx.a")).filter(|p| p.is_file()));
    let lib = candidates
        .filter_map(|p| Some((modified(&p)?, p)))
        .max()
        .map(|(_, p)| p)
        .unwrap_or_else(|| {
            panic!(
                "no libfpgfx*.a in {}: crate-type staticlib is missing from capi/Cargo.toml?",
                deps.display()
            )
        });
    let built = modified(&lib).expect("the staticlib has a time");
    for src in [
        "src/lib.rs",
        "src/render.rs",
        "src/raster.rs",
        "src/compare.rs",
    ] {
        let src = capi().join(src);
        assert!(
            modified(&src).is_some_and(|t| t <= built),
            "{} is older than {}: run the test through cargo, which rebuilds it",
            lib.display(),
            src.display()
        );
    }
    lib
}

/// The C test program, compiled once per run.
fn c_program() -> &'static Path {
    static PROGRAM: OnceLock<PathBuf> = OnceLock::new();
    PROGRAM.get_or_init(|| build("cc", &["-std=c99"], &["tests/c/test_fpgfx.c"], "test_fpgfx"))
}

/// Compiles `sources` (relative to `capi/`) with `compiler` against the header and the
/// staticlib into `scratch(name)`; a missing compiler names the package to install.
fn build(compiler: &str, flags: &[&str], sources: &[&str], name: &str) -> PathBuf {
    let out = scratch("bin").join(name);
    let mut cmd = Command::new(compiler);
    cmd.args(flags)
        // -s: the staticlib's debug info would make each program ~200 MB of scratch.
        .args(["-Wall", "-Wextra", "-Werror", "-O1", "-s", "-I"])
        .arg(capi().join("include"));
    for s in sources {
        cmd.arg(capi().join(s));
    }
    // What a Rust staticlib needs from the C runtime on Linux: threads, dlopen/dladdr for
    // the unwinder and backtraces, libm.
    let result = cmd
        .arg(staticlib())
        .args(["-lpthread", "-ldl", "-lm", "-o"])
        .arg(&out)
        .output();
    let result = match result {
        Ok(r) => r,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => panic!(
            "no `{compiler}` on the PATH: install build-essential (Debian: gcc, g++ and \
             libc6-dev) or run `cargo xtask setup`"
        ),
        Err(e) => panic!("cannot run {compiler}: {e}"),
    };
    assert!(
        result.status.success(),
        "{compiler} failed to build {sources:?}:\n{}",
        String::from_utf8_lossy(&result.stderr)
    );
    out
}

/// Runs the C program on `args`.
fn run_c(args: &[String]) -> Output {
    Command::new(c_program())
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", c_program().display()))
}

/// The C program's closing summary, `N passed, M failed`, as (N, M).
fn summary(out: &Output) -> (u32, u32) {
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .rev()
        .find(|l| l.ends_with(" failed"))
        .unwrap_or_else(|| panic!("no `N passed, M failed` line in:\n{text}"));
    let mut nums = line
        .split(|c: char| !c.is_ascii_digit())
        .filter(|s| !s.is_empty());
    let mut next = || {
        nums.next()
            .and_then(|n| n.parse().ok())
            .expect("two counts")
    };
    (next(), next())
}

/// `fpgfx vectors render SCENE --size WxH --numeric N` into a fresh directory.
fn render_vectors(name: &str, scene: &str, size: (u32, u32), numeric: Numeric) -> PathBuf {
    let file = capi().join("../examples/rt").join(scene);
    let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let scene = jobs::scene::parse(&text, scene).expect("example scenes parse");
    let opts = render_vectors::Options {
        numeric,
        size: Some(size),
    };
    let dir = scratch(name);
    render_vectors::render(&scene, &opts)
        .and_then(|v| v.set(&file.display().to_string()))
        .and_then(|set| set.write_to(&dir))
        .unwrap_or_else(|e| panic!("vectors for {name}: {e}"));
    dir
}

/// `fpgfx vectors raster JOB --layout L` into a fresh directory: the C test reads its
/// set-up, FIFO records and expected framebuffer.
fn raster_vectors(name: &str, job_file: &str, layout: LayoutId) -> PathBuf {
    let file = capi().join("../examples/raster").join(job_file);
    let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let dir = scratch(name);
    vectors::raster::raster(&text, job_file, layout)
        .and_then(|set| set.write_to(&dir))
        .unwrap_or_else(|e| panic!("raster vectors for {name}: {e}"));
    dir
}

/// The vectors every test runs on, written once per run.
fn all_vectors() -> &'static [String] {
    static ARGS: OnceLock<Vec<String>> = OnceLock::new();
    ARGS.get_or_init(|| {
        let dirs = [
            (
                "--render",
                render_vectors("shapes-f32", "shapes.toml", (64, 36), Numeric::F32),
            ),
            (
                "--render",
                render_vectors("textures-q16", "textures.toml", (48, 27), Numeric::Q16_16),
            ),
            (
                "--raster",
                raster_vectors("fitkit", "fitkit.toml", LayoutId::Fitkit),
            ),
            (
                "--raster",
                raster_vectors("gallery", "gallery.toml", LayoutId::Wide),
            ),
        ];
        dirs.into_iter()
            .flat_map(|(flag, dir)| [flag.to_string(), dir.display().to_string()])
            .collect()
    })
}

#[test]
fn the_c_test_passes_on_render_and_raster_vectors() {
    let out = run_c(all_vectors());
    let (passed, failed) = summary(&out);
    assert!(
        out.status.success() && failed == 0 && passed > 40,
        "the C test failed ({passed} passed, {failed} failed):\n{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

/// Copies a vector directory so that it can be damaged without touching the others.
fn copy_dir(from: &Path, name: &str) -> PathBuf {
    let to = scratch(name);
    for entry in std::fs::read_dir(from).expect("vector dir") {
        let path = entry.expect("dir entry").path();
        std::fs::copy(&path, to.join(path.file_name().expect("a file name"))).expect("copy");
    }
    to
}

/// Changes one byte of `file` in `dir` by `f`, at the first offset `pick` accepts.
fn damage(dir: &Path, file: &str, pick: impl Fn(&[u8], usize) -> bool, f: impl Fn(u8) -> u8) {
    let path = dir.join(file);
    let mut bytes = std::fs::read(&path).expect("vector file");
    let at = (0..bytes.len())
        .find(|&i| pick(&bytes, i))
        .unwrap_or_else(|| panic!("nothing to damage in {file}"));
    bytes[at] = f(bytes[at]);
    std::fs::write(&path, bytes).expect("write back");
}

#[test]
fn one_flipped_byte_in_a_vector_file_fails_the_c_test() {
    let args = all_vectors();
    let render_dir = Path::new(&args[1]);
    let raster_dir = Path::new(&args[5]);
    // A hex digit of the first pixel line (after the header comment) of the expected frame:
    // a digit stays a digit, so the file still parses and the pixel is what differs.
    let first_pixel = |b: &[u8], i: usize| i > 0 && b[i - 1] == b'\n' && b[i] != b'/';
    let flip_digit = |c: u8| if c == b'0' { b'1' } else { b'0' };
    let cases: [(&str, &Path, &str, &str); 5] = [
        ("rgb", render_dir, "expected_rgb888.hex", "pixels differ"),
        (
            "depth-bin",
            render_dir,
            "expected_depth.bin",
            "expected_depth.bin",
        ),
        (
            "raster",
            raster_dir,
            "expected_framebuffer.hex",
            "pixels differ",
        ),
        (
            "raster-wide",
            Path::new(&args[7]),
            "expected_framebuffer.hex",
            "pixels differ",
        ),
        // A record's flag digit: the packet it ends is cut short, so the block refuses
        // a packet or draws another frame.
        ("records", raster_dir, "fifo_records.hex", "raster"),
    ];
    for (name, dir, file, complaint) in cases {
        let damaged = copy_dir(dir, &format!("damaged-{name}"));
        if file.ends_with(".bin") {
            damage(&damaged, file, |_, i| i == 5, |b| b ^ 0x10);
        } else {
            damage(&damaged, file, first_pixel, flip_digit);
        }
        let flag = if dir != render_dir {
            "--raster"
        } else {
            "--render"
        };
        let mut run = vec![flag.to_string(), damaged.display().to_string()];
        if flag == "--raster" {
            // The error checks need a register image.
            run.extend(["--render".to_string(), args[1].clone()]);
        }
        let out = run_c(&run);
        let (_, failed) = summary(&out);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            !out.status.success() && failed >= 1 && text.contains(complaint),
            "one flipped byte in {file} went unnoticed ({failed} failed):\n{text}"
        );
    }
}

/// docs/hls-testbench.md's testbench (`hls/tb_viray.cpp`), built with g++ around the
/// stand-in DUT (`hls/viray_model.cpp`): it passes the model, passes a DUT off by one
/// level here and there, and fails one off by more.
#[test]
fn the_hls_testbench_holds_a_dut_to_its_tolerances() {
    let tb = build(
        "c++",
        &[
            "-std=c++11",
            "-I",
            &capi().join("hls").display().to_string(),
        ],
        &["hls/tb_viray.cpp", "hls/viray_model.cpp"],
        "tb_viray",
    );
    let vectors = &all_vectors()[3];
    let run = |error: Option<(&str, &str)>| {
        let mut cmd = Command::new(&tb);
        cmd.arg(vectors)
            .env_remove("VIRAY_MODEL_ERROR")
            .env_remove("VIRAY_MODEL_LEVELS");
        if let Some((every, levels)) = error {
            cmd.env("VIRAY_MODEL_ERROR", every)
                .env("VIRAY_MODEL_LEVELS", levels);
        }
        let out = cmd.output().expect("tb_viray runs");
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
        )
    };
    let (code, text) = run(None);
    assert!(
        code == Some(0) && text.contains("colour: 0 pixels") && text.ends_with("PASS\n"),
        "{text}"
    );
    let (code, text) = run(Some(("7", "1")));
    assert!(
        code == Some(0) && text.contains("largest difference 1") && text.ends_with("PASS\n"),
        "one level off must pass:\n{text}"
    );
    let (code, text) = run(Some(("7", "2")));
    assert!(
        code == Some(1) && text.ends_with("FAIL\n"),
        "two levels off must fail:\n{text}"
    );
    let (code, text) = run(Some(("0", "1")));
    assert!(
        code == Some(0),
        "VIRAY_MODEL_ERROR=0 changes nothing:\n{text}"
    );
    let (code, _) = {
        let out = Command::new(&tb)
            .arg(scratch("empty"))
            .output()
            .expect("tb_viray runs");
        (out.status.code(), ())
    };
    assert_eq!(code, Some(2), "no vectors is exit status 2");
}

/// `tests/c/sanitize_fpgfx.c` compiled with AddressSanitizer and UndefinedBehaviorSanitizer
/// (`-fno-sanitize-recover=all`: the first finding stops it) against the same staticlib:
/// every function with NULL, misaligned, off-by-one and overflowing arguments, then
/// register images read from files. The files are the example scenes' images at 4 × 4
/// (each also damaged word by word by the program) and the committed seeds of the
/// `device_regs` and `capi` fuzz targets, malformed on purpose. The Rust side is not
/// instrumented here (stable has no `-Zsanitizer`), but its heap is the C library's
/// malloc, which ASan replaces, and its copies go through the intercepted `memcpy`; the
/// `capi` fuzz target runs the same calls with the Rust side instrumented.
#[test]
fn the_c_library_holds_under_asan_and_ubsan() {
    let flags = [
        "-std=c99",
        "-g",
        "-fsanitize=address,undefined",
        "-fno-sanitize-recover=all",
        "-fno-omit-frame-pointer",
    ];
    let program = build(
        "cc",
        &flags,
        &["tests/c/sanitize_fpgfx.c"],
        "sanitize_fpgfx",
    );
    let dir = scratch("sanitize-images");
    let mut args = Vec::new();
    for scene in ["shapes.toml", "textures.toml", "brdf.toml"] {
        let file = capi().join("../examples/rt").join(scene);
        let text = std::fs::read_to_string(&file).expect("example scene");
        let parsed = jobs::scene::parse(&text, scene).expect("example scenes parse");
        let opts = render_vectors::Options {
            numeric: Numeric::Q16_16,
            size: Some((4, 4)),
        };
        let v = render_vectors::render(&parsed, &opts).expect("example scenes render");
        let bytes: Vec<u8> = v.regs.iter().flat_map(|w| w.to_le_bytes()).collect();
        let path = dir.join(format!("{scene}.regs"));
        std::fs::write(&path, bytes).expect("scratch file");
        args.push(path);
    }
    for target in ["device_regs", "capi"] {
        let corpus = capi().join("../fuzz/corpus").join(target);
        let mut seeds: Vec<PathBuf> = std::fs::read_dir(&corpus)
            .unwrap_or_else(|e| panic!("{}: {e}", corpus.display()))
            .flatten()
            .map(|e| e.path())
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with("seed-"))
            })
            .collect();
        seeds.sort();
        args.extend(seeds);
    }
    let out = Command::new(&program)
        .args(&args)
        // Leaks count too: every block the program makes it frees.
        .env(
            "ASAN_OPTIONS",
            "detect_leaks=1:abort_on_error=0:exitcode=86",
        )
        .env("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1")
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", program.display()));
    let text = String::from_utf8_lossy(&out.stdout);
    let errors = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "the sanitised C program failed ({}):\n{text}\n{errors}",
        out.status
    );
    let (passed, failed) = summary(&out);
    assert!(
        failed == 0 && passed > 5000,
        "{passed} passed, {failed} failed:\n{text}"
    );
}
