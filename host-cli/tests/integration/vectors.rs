//! `fpgfx vectors raster` over the real binary: the FITkit gallery jobs and a seeded
//! random corpus pass the generated Verilog testbench against `hw/fitkit-raster/rtl/` under Icarus (and
//! one job under Verilator); one wrong bit in the expected frame or write stream fails
//! it, naming the pixel; the expected frame is what `fpgfx raster --port builtin` draws;
//! what the layout cannot carry and an unwritable output are refused, naming them.
//!
//! A missing simulator fails these tests with the scripts' "run cargo xtask setup".

use std::path::Path;
use std::process::Command;

use compare::memh::{self, PixelFormat};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

use crate::common::{example, fails, ok, raster_gallery, rgb, tmp, workspace};

/// What a run script printed and how it ended.
struct Sim {
    code: Option<i32>,
    output: String,
}

/// `sh DIR/SCRIPT hw/fitkit-raster/rtl/ ARGS…`.
fn simulate(dir: &str, script: &str, args: &[&str]) -> Sim {
    let out = Command::new("sh")
        .arg(Path::new(dir).join(script))
        .arg(workspace().join("hw/fitkit-raster/rtl"))
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("sh {dir}/{script}: {e}"));
    Sim {
        code: out.status.code(),
        output: format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    }
}

fn assert_passes(dir: &str, script: &str) -> Sim {
    let sim = simulate(dir, script, &[]);
    assert!(
        sim.code == Some(0) && sim.output.contains("TB_FPGFX PASS"),
        "{dir}/{script} failed ({:?}):\n{}",
        sim.code,
        sim.output
    );
    sim
}

fn vectors(job: &str, dir: &str) {
    ok(&["vectors", "raster", job, "-o", dir]);
}

/// An RGB332 colour as the job file spells it (`#rrggbb` of its expansion).
fn rgb332(q: u8) -> String {
    let c = protocol::bus::rgb332_decode(q);
    format!("#{:02x}{:02x}{:02x}", c.r, c.g, c.b)
}

/// A random FITkit job: small frames (the simulator clears every pixel at least once),
/// coordinates across the whole 9-bit range so lines and triangles are clipped too,
/// lines, triangles of both windings and now and then a clear.
fn random_job(seed: u64, commands: usize) -> String {
    let mut rng = SmallRng::seed_from_u64(seed);
    let (w, h) = [(64, 48), (96, 80), (40, 100), (128, 32)][seed as usize % 4];
    let cull = ["none", "cw", "ccw"][rng.gen_range(0..3)];
    let mut job = format!(
        "# fpgfx vectors test corpus, seed {seed}\nsize = [{w}, {h}]\nbackground = \"{}\"\n\
         subpixel_bits = 0\ncull = \"{cull}\"\n",
        rgb332(rng.gen())
    );
    let point = |rng: &mut SmallRng| -> String {
        // Mostly in and around the frame, sometimes anywhere in 0..512.
        let (x, y) = if rng.gen_bool(0.8) {
            (rng.gen_range(0..w + 16), rng.gen_range(0..h + 16))
        } else {
            (rng.gen_range(0..512), rng.gen_range(0..512))
        };
        format!("[{x}.0, {y}.0]")
    };
    for _ in 0..commands {
        let color = rgb332(rng.gen());
        let op = rng.gen_range(0..10);
        job.push_str("\n[[cmd]]\n");
        if op < 4 {
            let (a, b) = (point(&mut rng), point(&mut rng));
            job.push_str(&format!(
                "op = \"line\"\nfrom = {a}\nto = {b}\ncolor = \"{color}\"\n"
            ));
        } else if op < 9 {
            let v = [point(&mut rng), point(&mut rng), point(&mut rng)];
            job.push_str(&format!(
                "op = \"triangle\"\nv = [{}, {}, {}]\ncolor = \"{color}\"\n",
                v[0], v[1], v[2]
            ));
        } else {
            job.push_str(&format!("op = \"clear\"\ncolor = \"{color}\"\n"));
        }
    }
    job
}

/// Writes random job `seed` and its vectors; returns the vectors' directory.
fn random_vectors(seed: u64, commands: usize) -> String {
    let job = tmp(&format!("random-{seed}.toml"));
    std::fs::write(&job, random_job(seed, commands)).expect("write the job");
    let dir = tmp(&format!("random-{seed}"));
    vectors(&job, &dir);
    dir
}

/// The gallery jobs the FITkit layout carries, with their vectors' directories (named
/// `PREFIX-STEM`: tests run in parallel and must not rewrite each other's files); the
/// others must be refused by name, not fail in some other way.
fn fitkit_gallery(prefix: &str) -> Vec<(String, String)> {
    let mut carried = Vec::new();
    for job in raster_gallery() {
        let job = job.display().to_string();
        let stem = Path::new(&job)
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("a gallery file has a name")
            .to_string();
        let dir = tmp(&format!("{prefix}-{stem}"));
        let run = crate::common::fpgfx(&["vectors", "raster", &job, "-o", &dir]);
        if run.code == Some(0) {
            carried.push((job, dir));
        } else {
            assert!(
                run.stderr.contains("cmd[") || run.stderr.contains("FITkit controller refuses"),
                "{job}: refused for another reason than its content:\n{}",
                run.stderr
            );
        }
    }
    assert!(
        carried.iter().any(|(j, _)| j.ends_with("fitkit.toml")),
        "fitkit.toml must be among the FITkit gallery: {carried:?}"
    );
    carried
}

#[test]
fn fitkit_gallery_passes_the_testbench_under_icarus() {
    for (job, dir) in fitkit_gallery("icarus") {
        let sim = assert_passes(&dir, "run-iverilog.sh");
        assert!(sim.output.contains(", 0 failed"), "{job}: {}", sim.output);
    }
}

#[test]
fn random_corpus_passes_the_testbench_under_icarus() {
    // 4 jobs, 48 commands in all, one of them under random mem_wait stalls.
    for seed in 1..=4 {
        let dir = random_vectors(seed, 12);
        assert_passes(&dir, "run-iverilog.sh");
        if seed == 4 {
            let sim = simulate(&dir, "run-iverilog.sh", &["+mem_wait=96"]);
            assert!(
                sim.code == Some(0) && sim.output.contains("mem_wait 96/256"),
                "seed {seed} under mem_wait ({:?}):\n{}",
                sim.code,
                sim.output
            );
        }
    }
}

#[test]
fn fitkit_job_passes_the_testbench_under_verilator() {
    let dir = tmp("verilator-fitkit");
    vectors(&example("raster/fitkit.toml"), &dir);
    assert_passes(&dir, "run-verilator.sh");
}

/// Flips bit 0 of data word `index` (0-based, comments skipped) of `file` in `dir`.
fn flip_word_bit(dir: &str, file: &str, index: usize) -> u64 {
    let path = Path::new(dir).join(file);
    let text = std::fs::read_to_string(&path).expect("vector file");
    let mut seen = 0;
    let mut flipped = 0;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            if l.starts_with("//") {
                return l.to_string();
            }
            seen += 1;
            if seen - 1 != index {
                return l.to_string();
            }
            let w = u64::from_str_radix(l, 16).expect("a hex word") ^ 1;
            flipped = w;
            format!("{w:0width$x}", width = l.len())
        })
        .collect();
    std::fs::write(&path, lines.join("\n") + "\n").expect("write back");
    flipped
}

#[test]
fn one_wrong_bit_fails_the_testbench_naming_the_pixel() {
    let job = tmp("flip.toml");
    std::fs::write(&job, random_job(7, 6)).expect("write the job");

    // The frame: pixel (5, 3) of the expected frame one bit off.
    let dir = tmp("flip-frame");
    vectors(&job, &dir);
    let (w, _) = {
        let text = std::fs::read_to_string(Path::new(&dir).join("expected_framebuffer.hex"))
            .expect("frame");
        let (h, _) = memh::parse_frame(&text).expect("a frame file");
        (h.width as usize, h.height)
    };
    let (x, y) = (5, 3);
    flip_word_bit(&dir, "expected_framebuffer.hex", y * w + x);
    let sim = simulate(&dir, "run-iverilog.sh", &[]);
    assert_ne!(sim.code, Some(0), "a wrong frame passed:\n{}", sim.output);
    assert!(
        sim.output.contains(&format!("FAIL frame pixel ({x}, {y})"))
            && sim.output.contains("TB_FPGFX FAIL"),
        "{}",
        sim.output
    );

    // The write stream: the first drawing fragment's colour one bit off.
    let dir = tmp("flip-fragments");
    vectors(&job, &dir);
    let text =
        std::fs::read_to_string(Path::new(&dir).join("expected_fragments.hex")).expect("fragments");
    let words = memh::parse(&text).expect("memh").words;
    let k = words
        .iter()
        .position(|w| w >> 32 == 1)
        .expect("the job draws a fragment");
    let flipped = flip_word_bit(&dir, "expected_fragments.hex", k);
    let (fx, fy) = ((flipped >> 8) & 0xfff, (flipped >> 20) & 0xfff);
    let sim = simulate(&dir, "run-iverilog.sh", &[]);
    assert_ne!(
        sim.code,
        Some(0),
        "a wrong write stream passed:\n{}",
        sim.output
    );
    assert!(
        sim.output.contains(&format!(
            "FAIL fragment {k}: expected pixel ({fx}, {fy}) = 0x{:02x}",
            flipped & 0xff
        )),
        "{}",
        sim.output
    );
}

/// The expected frame of `dir`, pixel by pixel, against the PNG `fpgfx raster --port
/// builtin` draws for `job`.
fn assert_frame_is_builtins(job: &str, dir: &str, png: &str) {
    ok(&["--port", "builtin", "raster", job, "-o", png]);
    let image = rgb(png);
    let text =
        std::fs::read_to_string(Path::new(dir).join("expected_framebuffer.hex")).expect("frame");
    let (header, pixels) = memh::parse_frame(&text).expect("a frame file");
    assert_eq!((header.width, header.height), image.dimensions(), "{job}");
    let mut differ = 0;
    for (i, &p) in pixels.iter().enumerate() {
        let (x, y) = (i as u32 % header.width, i as u32 / header.width);
        if header.format.to_rgb8(p) != image.get_pixel(x, y).0 {
            differ += 1;
        }
    }
    assert_eq!(
        differ, 0,
        "{job}: {differ} pixels differ from the built-in target's"
    );
}

#[test]
fn expected_frame_is_what_the_builtin_target_draws() {
    for (job, dir) in fitkit_gallery("builtin") {
        let text = std::fs::read_to_string(Path::new(&dir).join("expected_framebuffer.hex"))
            .expect("frame");
        let (header, _) = memh::parse_frame(&text).expect("a frame file");
        assert_eq!(header.format, PixelFormat::Rgb332);
        assert_frame_is_builtins(&job, &dir, &tmp("builtin-fitkit.png"));
    }
    let dir = random_vectors(11, 16);
    assert_frame_is_builtins(&tmp("random-11.toml"), &dir, &tmp("builtin-random-11.png"));
    // The built-in target packs the wide layout: every gallery job, RGB888.
    for job in raster_gallery() {
        let job = job.display().to_string();
        let stem = Path::new(&job)
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("name")
            .to_string();
        let dir = tmp(&format!("wide-{stem}"));
        ok(&["vectors", "raster", &job, "-o", &dir, "--layout", "wide"]);
        assert!(
            !Path::new(&dir).join("tb_fpgfx.v").exists(),
            "a testbench for a layout without RTL"
        );
        assert_frame_is_builtins(&job, &dir, &tmp(&format!("builtin-{stem}.png")));
    }
}

#[test]
fn what_the_layout_cannot_carry_and_unwritable_output_are_refused() {
    let job = tmp("circle.toml");
    std::fs::write(
        &job,
        "size = [64, 48]\nsubpixel_bits = 0\n\n[[cmd]]\nop = \"line\"\nfrom = [0.0, 0.0]\n\
         to = [10.0, 10.0]\ncolor = \"#ffffff\"\n\n[[cmd]]\nop = \"circle\"\n\
         center = [20.0, 20.0]\nradius = 5.0\ncolor = \"#ffffff\"\n",
    )
    .expect("write the job");
    let err = fails(&["vectors", "raster", &job, "-o", &tmp("never")]);
    assert!(
        err.contains(&format!("{job}: cmd[1] (circle)")),
        "the circle is not named: {err}"
    );
    assert!(!Path::new(&tmp("never")).join("manifest.toml").exists());

    let file = tmp("plain-file");
    std::fs::write(&file, "not a directory").expect("write");
    let out = format!("{file}/vectors");
    let err = fails(&[
        "vectors",
        "raster",
        &example("raster/fitkit.toml"),
        "-o",
        &out,
    ]);
    // refused before the vectors are made, naming the flag
    assert!(err.contains(&format!("-o/--output {out}")), "{err}");
    assert!(err.contains("is a file, not a directory"), "{err}");
}
