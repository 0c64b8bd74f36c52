//! `fpgfx vectors render` over the real binary: its expected frame, planes and KCU116
//! packing are what `fpgfx render --port builtin` produces for the same scene, size and
//! number format, and its files agree with each other and with the manifest.

use compare::memh;

use crate::common::{example, fails, ok, rgb, tmp};

/// Reads a PFM as `sim_target::rt::write_pfm` writes it (little-endian, bottom row
/// first) into row-major floats.
fn pfm(path: &str) -> (u32, u32, usize, Vec<f32>) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut lines = bytes.splitn(4, |&b| b == b'\n');
    let tag = lines.next().expect("PFM tag");
    let channels = if tag == b"PF" { 3 } else { 1 };
    let size = std::str::from_utf8(lines.next().expect("PFM size")).expect("text");
    let (w, h) = size.split_once(' ').expect("W H");
    let (w, h): (u32, u32) = (w.parse().expect("W"), h.parse().expect("H"));
    let scale = std::str::from_utf8(lines.next().expect("PFM scale")).expect("text");
    assert!(scale.starts_with('-'), "little-endian PFM");
    let data: Vec<f32> = lines
        .next()
        .expect("PFM data")
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let row = w as usize * channels;
    let rows: Vec<&[f32]> = data.chunks(row).rev().collect();
    (w, h, channels, rows.concat())
}

/// A `.hex` file of f32 bit patterns as floats.
fn floats(path: &str) -> Vec<f32> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    memh::parse(&text)
        .unwrap_or_else(|e| panic!("{path}: {e}"))
        .words
        .into_iter()
        .map(|w| f32::from_bits(w as u32))
        .collect()
}

fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[test]
fn vectors_are_what_the_built_in_target_renders() {
    for (scene, size, numeric) in [
        ("rt/textures.toml", "48x27", "q16.16"),
        ("rt/fresnel.toml", "40x30", "f32"),
    ] {
        let name = scene.replace(['/', '.'], "-");
        let dir = tmp(&format!("{name}-{numeric}"));
        let file = example(scene);
        let run = ok(&[
            "vectors",
            "render",
            &file,
            "-o",
            &dir,
            "--size",
            size,
            "--numeric",
            numeric,
        ]);
        assert!(run.stderr.contains("frame's vectors to"), "{}", run.stderr);
        assert_eq!(
            run.stdout.lines().count(),
            13,
            "one line per file: {}",
            run.stdout
        );
        let png = tmp(&format!("{name}-{numeric}.png"));
        let kcu = tmp(&format!("{name}-{numeric}-kcu116.png"));
        let (depth, normal) = (tmp(&format!("{name}-d.pfm")), tmp(&format!("{name}-n.pfm")));
        let aov = format!("depth={depth},normal={normal}");
        let common = [
            "--port",
            "builtin",
            "render",
            &file,
            "--size",
            size,
            "--numeric",
            numeric,
        ];
        ok(&[&common[..], &["-o", &png, "--aov", &aov]].concat());
        ok(&[&common[..], &["-o", &kcu, "--packing", "kcu116"]].concat());

        let text = std::fs::read_to_string(format!("{dir}/expected_rgb888.hex")).expect("rgb hex");
        let (header, pixels) = memh::parse_frame(&text).expect("a framebuffer file");
        let image = rgb(&png);
        assert_eq!((header.width, header.height), image.dimensions(), "{scene}");
        assert_eq!(header.format, memh::PixelFormat::Rgb888);
        let expected: Vec<u8> = pixels
            .iter()
            .flat_map(|&w| memh::PixelFormat::Rgb888.to_rgb8(w))
            .collect();
        assert!(
            expected == image.as_raw().as_slice(),
            "{scene}: expected_rgb888.hex differs from `fpgfx render --port builtin`"
        );
        let bin = std::fs::read(format!("{dir}/expected_rgb888.bin")).expect("rgb bin");
        assert_eq!(bin, expected, "{scene}: .bin and .hex differ");

        // The KCU116 words, reconstructed as the host does, are the kcu116 read-back.
        let kcu_text = std::fs::read_to_string(format!("{dir}/expected_kcu116.hex")).expect("kcu");
        let words: Vec<u16> = memh::parse(&kcu_text)
            .expect("kcu116 hex")
            .words
            .into_iter()
            .map(|w| w as u16)
            .collect();
        let rebuilt = sim_target::rt::unpack_kcu116(&words, header.width);
        assert!(
            rebuilt == rgb(&kcu).as_raw().as_slice(),
            "{scene}: kcu116 packing"
        );

        let (w, h, ch, d) = pfm(&depth);
        assert_eq!((w, h, ch), (header.width, header.height, 1));
        assert!(
            same_bits(&floats(&format!("{dir}/expected_depth.hex")), &d),
            "{scene}: depth"
        );
        let (_, _, ch, n) = pfm(&normal);
        assert_eq!(ch, 3);
        assert!(
            same_bits(&floats(&format!("{dir}/expected_normal.hex")), &n),
            "{scene}: normal"
        );

        let manifest = std::fs::read_to_string(format!("{dir}/manifest.toml")).expect("manifest");
        let m: toml::Value = toml::from_str(&manifest).expect("manifest is TOML");
        assert_eq!(m["width"].as_integer(), Some(i64::from(header.width)));
        assert_eq!(m["numeric"].as_str(), Some(numeric));
        assert_eq!(
            m["counts"]["pixels"].as_integer(),
            Some(pixels.len() as i64)
        );
        assert_eq!(m["fpgfx_version"].as_str(), Some(env!("CARGO_PKG_VERSION")));
    }
}

#[test]
fn bad_input_names_the_file() {
    let err = fails(&[
        "vectors",
        "render",
        "no-such-scene.toml",
        "-o",
        &tmp("none"),
    ]);
    assert!(err.contains("no-such-scene.toml"), "{err}");
    // A directory that cannot be made: its parent is a file.
    let file = tmp("a-file");
    std::fs::write(&file, "").expect("write");
    let out = format!("{file}/vectors");
    let err = fails(&[
        "vectors",
        "render",
        &example("rt/shapes.toml"),
        "-o",
        &out,
        "--size",
        "8x8",
    ]);
    assert!(err.contains(&out), "{err}");
}

/// The ray-casting core's RTL checked by the tools: `fpgfx vectors render` of a scene the
/// core builds drives `hw/rt-core/tb/tb_rt_vectors.v` under Icarus (`axi_writes.hex`
/// replayed as AXI4-Lite writes into the core's device, `AP_CTRL` polled, every pixel of
/// its memory port checked for colour, depth and normal against the vectors), and
/// `fpgfx compare` finds the frame the bench wrote identical to the expected one. A missing Icarus fails with "run cargo xtask
/// setup".
#[test]
fn render_vectors_drive_the_rt_core_under_icarus_and_compare_finds_an_exact_match() {
    use std::process::Command;
    let dir = tmp("vectors-rt-core");
    let ws = crate::common::workspace();
    let scene = ws.join("hw/rt-core/scenes/core.toml").display().to_string();
    ok(&[
        "vectors",
        "render",
        &scene,
        "-o",
        &dir,
        "--numeric",
        "q16.16",
        "--size",
        "24x14",
    ]);
    let core = ws.join("hw/rt-core");
    let vvp = format!("{dir}/tb_rt_vectors.vvp");
    let build = Command::new("iverilog")
        .args(["-g2012", "-I"])
        .arg(core.join("rtl"))
        .arg("-I")
        .arg(ws.join("hw/shared-tb"))
        .args(["-s", "tb_rt_vectors", "-o", &vvp])
        .arg(core.join("tb/tb_rt_vectors.v"))
        .args(
            std::fs::read_dir(core.join("rtl"))
                .expect("hw/rt-core/rtl")
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "v")),
        )
        .output()
        .unwrap_or_else(|e| panic!("iverilog: {e} (run cargo xtask setup)"));
    assert!(
        build.status.success(),
        "iverilog: {}",
        String::from_utf8_lossy(&build.stderr)
    );
    let sim = Command::new("vvp")
        .args(["-n", &vvp, &format!("+vec={dir}")])
        .output()
        .unwrap_or_else(|e| panic!("vvp: {e} (run cargo xtask setup)"));
    let out = String::from_utf8_lossy(&sim.stdout);
    assert!(out.contains("TB_RT_CORE PASS: 2016 checks"), "{out}");
    // RT_CYCLES is the model's count for the core plus the clocks the memory held it
    let numbers: Vec<u64> = out
        .lines()
        .find(|l| l.starts_with("TB_RT_CORE PASS"))
        .map(|l| {
            l.split(|c: char| !c.is_ascii_digit())
                .filter_map(|w| w.parse().ok())
                .collect()
        })
        .unwrap_or_default();
    let text = std::fs::read_to_string(&scene).expect("core.toml");
    let mut s = jobs::scene::parse(&text, &scene).expect("core.toml parses");
    (s.width, s.height) = (24, 14);
    let want = sim_target::rt::core::CoreFrame::of(&s).cycles();
    assert!(
        matches!(numbers[..], [2016, cycles, held] if cycles == want + held),
        "RT_CYCLES against the model's {want}: {out}"
    );
    let cmp = ok(&[
        "compare",
        &format!("{dir}/expected_rgb888.hex"),
        &format!("{dir}/actual_rgb888.hex"),
    ]);
    assert!(
        cmp.stdout.contains("336 identical") && cmp.stdout.contains("failing     0"),
        "{}",
        cmp.stdout
    );
}
