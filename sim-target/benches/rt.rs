//! Mrays/s per number format on a reduced reference frame (480×270, depth 2), with the
//! PSNR of each format against f64 printed alongside. Criterion's "elem/s" is rays/s
//! counted as SPEC-RT counts them (primary + shadow + reflected).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sim_target::rt::{self, scene_file, Numeric, RenderOptions};
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let text = include_str!("../../examples/reference.toml");
    let scene = match scene_file::parse(text, "examples/reference.toml") {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    };
    let size = Some((480, 270));
    let opts = |numeric| RenderOptions {
        numeric,
        size,
        ..Default::default()
    };
    // One render and out, for instruction counts that do not depend on the machine's load:
    // `RT_BENCH_ONCE=q16.16 valgrind --tool=callgrind target/release/deps/rt-… --bench`.
    if let Some(numeric) = std::env::var("RT_BENCH_ONCE")
        .ok()
        .and_then(|n| rt::parse_numeric(&n))
    {
        if let Ok(frame) = rt::render(&scene, &opts(numeric)) {
            eprintln!("{numeric:?}: {} rays", frame.stats.rays());
        }
        return;
    }
    let reference = rt::render(&scene, &opts(Numeric::F64))
        .map(|f| f.rgb8)
        .unwrap_or_default();
    let mut g = c.benchmark_group("rt_reference_480x270");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for numeric in Numeric::ALL {
        let Ok(frame) = rt::render(&scene, &opts(numeric)) else {
            continue;
        };
        eprintln!(
            "{numeric:?}: {} rays/frame, PSNR vs f64 {:.2} dB",
            frame.stats.rays(),
            rt::psnr(&reference, &frame.rgb8)
        );
        g.throughput(Throughput::Elements(frame.stats.rays()));
        g.bench_with_input(
            BenchmarkId::from_parameter(format!("{numeric:?}")),
            &numeric,
            |b, n| b.iter(|| rt::render(&scene, &opts(*n))),
        );
    }
    g.finish();

    // the plan's function-pointer dispatch against an inlined match on the shape
    let mut g = c.benchmark_group("rt_dispatch_480x270_f32");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for dispatch in [rt::Dispatch::FnPointer, rt::Dispatch::Match] {
        let o = RenderOptions {
            dispatch,
            ..opts(Numeric::F32)
        };
        g.bench_with_input(
            BenchmarkId::from_parameter(format!("{dispatch:?}")),
            &o,
            |b, o| b.iter(|| rt::render(&scene, o)),
        );
    }
    g.finish();

    // the full 1080p reference frame, for the s/frame figures (few samples: slow)
    let mut g = c.benchmark_group("rt_reference_1080p");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(100))
        .measurement_time(Duration::from_secs(10));
    for numeric in [Numeric::F32, Numeric::Q16_16] {
        let full = |n| RenderOptions {
            numeric: n,
            ..Default::default()
        };
        let Ok(frame) = rt::render(&scene, &full(numeric)) else {
            continue;
        };
        eprintln!(
            "1080p {numeric:?}: {} rays/frame, {:.3} s single shot, board estimate {:.1} ms",
            frame.stats.rays(),
            frame.stats.seconds,
            frame.stats.board_seconds() * 1e3
        );
        g.throughput(Throughput::Elements(frame.stats.rays()));
        g.bench_with_input(
            BenchmarkId::from_parameter(format!("{numeric:?}")),
            &numeric,
            |b, n| b.iter(|| rt::render(&scene, &full(*n))),
        );
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
