//! `fpgfx bench --quick` as CI runs it: every output is written, every point has a
//! finite cost and error, the reference-identical points are where they must be, and the
//! default configurations sit on their Pareto fronts. The binary carries its workloads
//! (it runs outside the repository) and its plots carry text in the font it carries.

use host_cli::sweep::{self, BenchConfig, Point};
use std::path::{Path, PathBuf};

use crate::common;

#[test]
fn quick_bench_writes_outputs_and_default_is_on_the_front() {
    let out = PathBuf::from(common::tmp("out"));
    let cfg = BenchConfig {
        scenes: Vec::new(),
        raster_files: Vec::new(),
        quick: true,
        repeats: 1,
    };
    let report = sweep::run(&cfg).expect("bench runs");
    sweep::write(&report, &out).expect("outputs written");
    eprintln!("{}", sweep::to_markdown(&report));
    for f in [
        "bench.csv",
        "bench.md",
        "pareto-rt.png",
        "pareto-raster.png",
    ] {
        let meta = std::fs::metadata(out.join(f)).expect(f);
        assert!(meta.len() > 100, "{f} is {} bytes", meta.len());
    }
    // 7 formats × 4 approximation sets
    assert_eq!(report.rt.len(), 28);
    let csv = std::fs::read_to_string(out.join("bench.csv")).expect("csv");
    assert_eq!(
        csv.lines().count(),
        1 + report.rt.len() + report.raster.len()
    );
    for p in report.rt.iter().chain(&report.raster) {
        assert!(p.cost.is_finite() && p.cost > 0.0, "{p:?}");
        assert!(p.psnr.is_finite(), "{p:?}");
    }
    // the scalar kernel's time beside the packets', for f32's configurations only
    let col = csv
        .lines()
        .next()
        .and_then(|h| h.split(',').position(|c| c == "scalar_host_ms"))
        .expect("scalar_host_ms column");
    for line in csv.lines().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        let packets = cells[0] == "rt" && cells[1].starts_with("f32/");
        let scalar = cells[col];
        assert_eq!(
            !scalar.is_empty(),
            packets,
            "{line}: scalar time only for f32's ray tracing"
        );
        if packets {
            assert!(scalar.parse::<f64>().is_ok_and(|ms| ms > 0.0), "{line}");
        }
    }
    // the reference configuration reproduces itself exactly
    let f64_exact = report
        .rt
        .iter()
        .find(|p| p.config == "f64/exact")
        .expect("f64/exact measured");
    assert_eq!(f64_exact.mismatched, 0);
    assert_eq!(f64_exact.psnr, sweep::PSNR_CAP);
    // Q16.16 with the seed's approximations is measurably worse than f32
    let psnr = |c: &str| {
        let p = report.rt.iter().find(|p| p.config == c);
        p.map(|p| p.psnr)
            .unwrap_or_else(|| panic!("{c} not measured"))
    };
    assert!(psnr("q16.16/seed") < psnr("f32/exact"));
    // cost ranks formats by datapath width
    let cost = |c: &str| {
        let p = report.rt.iter().find(|p| p.config == c);
        p.map(|p| p.cost)
            .unwrap_or_else(|| panic!("{c} not measured"))
    };
    assert!(cost("f16/exact") < cost("f32/exact"));
    assert!(cost("f32/exact") < cost("f64/exact"));
    let d = report.rt.iter().find(|p| p.is_default).expect("rt default");
    assert!(d.front, "rt default off the front: {d:?}");
    // The raster default (8 bits, no AA) is NOT asserted: the quick run's two files put
    // every vertex on a ¼-pixel grid, so 4 bits draw them identically for less
    // (docs/bench.md, "Reading").
    let d = report
        .raster
        .iter()
        .find(|p| p.is_default)
        .expect("raster default");
    let four = report
        .raster
        .iter()
        .find(|p| p.config == "4bit/nonex1")
        .expect("4 bits");
    assert_eq!(d.mismatched, four.mismatched);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn pareto_front_by_hand() {
    // (cost, quality): b dominates c (cheaper and better); a, b, d, e are on the front;
    // f is 0.5 % cheaper than d at equal quality: within the model's resolution, so it
    // does not push d off; g is 2 % cheaper than h at equal quality and does.
    let pts = [
        (1.0, 10.0),
        (2.0, 30.0),
        (3.0, 20.0),
        (4.0, 40.0),
        (4.0, 40.0),
        (3.98, 40.0),
        (4.9, 45.0),
        (5.0, 45.0),
    ];
    assert_eq!(
        sweep::pareto_front(&pts),
        vec![true, true, false, true, true, true, true, false]
    );
}

/// The workloads built into the binary are the example files, byte for byte, and every
/// raster example and ray-trace example is among them (a new example must join the list).
#[test]
fn builtin_workloads_are_the_example_files() {
    let root = common::workspace();
    for (name, text) in sweep::BUILTIN_SCENES.iter().chain(&sweep::BUILTIN_RASTER) {
        let on_disk =
            std::fs::read_to_string(root.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(*text, on_disk, "{name} differs from its built-in copy");
    }
    let names = |dir: &str| -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(root.join(dir))
            .unwrap_or_else(|e| panic!("{dir}: {e}"))
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .map(|p| format!("{dir}/{}", p.file_name().unwrap().to_string_lossy()))
            .collect();
        v.sort();
        v
    };
    let raster: Vec<&str> = sweep::BUILTIN_RASTER.iter().map(|(n, _)| *n).collect();
    assert_eq!(raster, names("examples/raster"));
    let scenes: Vec<&str> = sweep::BUILTIN_SCENES.iter().map(|(n, _)| *n).collect();
    assert_eq!(scenes[0], "examples/reference.toml");
    for rt in names("examples/rt") {
        assert!(scenes.contains(&rt.as_str()), "{rt} is not built in");
    }
}

/// `fpgfx bench --quick` from a directory outside the repository: the built-in workloads
/// travel inside the binary, and the report names them by their repository paths.
#[test]
fn bench_runs_outside_the_repository() {
    let dir = PathBuf::from(common::tmp("elsewhere"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let dir = dir.canonicalize().expect("scratch dir");
    let root = common::workspace().canonicalize().expect("workspace");
    assert!(
        !dir.starts_with(&root),
        "{} is inside the repository",
        dir.display()
    );
    let args = ["bench", "--quick", "--repeats", "1", "-o", "out"];
    let run = common::assert_ok(
        common::run(common::fpgfx_command(&args).current_dir(&dir)),
        &args,
    );
    for f in [
        "bench.csv",
        "bench.md",
        "pareto-rt.png",
        "pareto-raster.png",
    ] {
        assert!(
            dir.join("out").join(f).is_file(),
            "{f} missing:\n{}",
            run.stderr
        );
    }
    let md = std::fs::read_to_string(dir.join("out/bench.md")).expect("bench.md");
    assert!(md.contains("examples/reference.toml at 48×27"), "{md}");
    assert!(md.contains("examples/raster/aa.toml"), "{md}");
}

/// A scene file that cannot be read is named once, with the operating system's reason
/// once (not "cannot read X: reason: reason").
#[test]
fn unreadable_scene_is_reported_once() {
    let out = common::tmp("unreadable-out");
    let missing = common::tmp("no-such-scene.toml");
    let args = ["bench", "--quick", "--scene", &missing, "-o", &out];
    let err = common::fails(&args);
    assert!(err.contains(&format!("cannot read {missing}")), "{err}");
    let reason = std::fs::read(&missing).unwrap_err().to_string();
    assert_eq!(err.matches(&reason).count(), 1, "{err}");
}

/// Pixels darker than mid-grey in `rows` × `cols` of an RGB image.
fn ink(img: &image::RgbImage, cols: std::ops::Range<u32>, rows: std::ops::Range<u32>) -> usize {
    rows.flat_map(|y| cols.clone().map(move |x| (x, y)))
        .filter(|&(x, y)| img.get_pixel(x, y).0.iter().all(|&c| c < 100))
        .count()
}

fn point(config: &str, cost: f64, psnr: f64, front: bool, is_default: bool) -> Point {
    Point {
        block: "rt",
        config: config.into(),
        cost,
        host_ms: 1.0,
        scalar_ms: None,
        psnr,
        max_err: 0,
        depth_rmse: 0.0,
        mismatched: 0,
        coverage_mismatch: 0,
        aa_area_err: 0.0,
        is_default,
        front,
    }
}

/// The plots carry text: the title above the plot, the y axis's description along its
/// left edge and the x axis's along the bottom are drawn in the built-in font (these
/// strips hold nothing but text), and the point names beside the front.
#[test]
fn pareto_plot_has_title_axes_and_names() {
    let pts = [
        point("f16/exact", 6.0e4, 27.0, true, false),
        point("q16.16/exact", 1.2e5, 56.0, true, false),
        point("f32/exact", 1.5e5, 101.0, true, true),
        point("f64/exact", 4.3e5, 120.0, true, false),
        point("q8.24/seed", 1.25e5, 16.0, false, false),
        point("f64/seed", 4.4e5, 25.5, false, false),
    ];
    let path = common::tmp("pareto-text.png");
    sweep::plot(&pts, Path::new(&path)).expect("plot written");
    let img = common::rgb(&path);
    let (w, h) = img.dimensions();
    let title = ink(&img, w / 4..3 * w / 4, 0..36);
    let y_desc = ink(&img, 0..36, h / 4..3 * h / 4);
    let x_desc = ink(&img, w / 4..3 * w / 4, h - 30..h);
    assert!(title > 100, "no title: {title} dark pixels");
    assert!(y_desc > 100, "no y axis description: {y_desc} dark pixels");
    assert!(x_desc > 100, "no x axis description: {x_desc} dark pixels");
    // The legend and the points' names are near-black text; the markers and grid lines
    // are lighter (grey, blue, red), so the plot's interior holds dark pixels only where
    // text is.
    let inside = ink(&img, 120..w - 40, 60..h - 90);
    assert!(
        inside > 400,
        "no legend or names: {inside} dark pixels in the plot"
    );
}
