//! `fpgfx bench --quick` as CI runs it: every output is written, every point has a
//! finite cost and error, the reference-identical points are where they must be, and the
//! default configurations sit on their Pareto fronts.

use host_cli::bench::{self, BenchConfig};
use std::path::PathBuf;

use crate::common;

#[test]
fn quick_bench_writes_outputs_and_default_is_on_the_front() {
    let out = PathBuf::from(common::tmp("out"));
    let cfg = BenchConfig {
        scenes: Vec::new(),
        raster_files: Vec::new(),
        quick: true,
        repeats: 1,
        root: common::workspace(),
    };
    let report = bench::run(&cfg).expect("bench runs");
    bench::write(&report, &out).expect("outputs written");
    eprintln!("{}", bench::to_markdown(&report));
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
    // the reference configuration reproduces itself exactly
    let f64_exact = report
        .rt
        .iter()
        .find(|p| p.config == "f64/exact")
        .expect("f64/exact measured");
    assert_eq!(f64_exact.mismatched, 0);
    assert_eq!(f64_exact.psnr, bench::PSNR_CAP);
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
        bench::pareto_front(&pts),
        vec![true, true, false, true, true, true, true, false]
    );
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
