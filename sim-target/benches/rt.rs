//! Mrays/s per number format on a reduced reference frame (480×270, depth 2), with the
//! PSNR of each format against f64 printed alongside. Criterion's "elem/s" is rays/s
//! counted as docs/requirements.md §4.10 counts them (DEPTH × (1 + lights) per pixel: 4 for the reference
//! scene, traced or not, as the seed's Mrays/s); the traced count is printed beside it.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sim_target::num::{self, AcosKind, AtanKind, SqrtKind};
use sim_target::rt::{self, Kernel, Numeric, RenderOptions, Subset};
use std::time::Duration;

/// Planned against general kernel, side by side, on the feature subsets of the reference
/// scene (f32, 320×180): identical images (asserted here too), the speed-up, and the
/// register words/bytes each scene costs on the wire.
fn plan(c: &mut Criterion) {
    let text = include_str!("../../examples/reference.toml");
    let Ok(scene) = jobs::scene::parse(text, "examples/reference.toml") else {
        return;
    };
    let mut g = c.benchmark_group("plan");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    for sub in Subset::ALL {
        let s = sub.apply(&scene);
        let opts = |kernel| RenderOptions {
            numeric: Numeric::F32,
            size: Some((320, 180)),
            kernel,
            ..Default::default()
        };
        let (Ok(p), Ok(gen)) = (
            rt::render(&s, &opts(Kernel::Planned)),
            rt::render(&s, &opts(Kernel::General)),
        ) else {
            continue;
        };
        assert_eq!(
            p.rgb8,
            gen.rgb8,
            "{}: planned and general differ",
            sub.label()
        );
        if let Ok((full, planned)) = jobs::scene::scene_wire_cost(&s) {
            eprintln!(
                "{}: kernel {}, {} rays; wire today {} words / {} msgs / {} B, planned {} words ({} needed) / {} msgs / {} B",
                sub.label(),
                p.plan.features(),
                p.stats.rays(),
                full.words,
                full.writes,
                full.bytes,
                planned.words,
                planned.changed,
                planned.writes,
                planned.bytes
            );
        }
        g.throughput(Throughput::Elements(p.stats.nominal_rays));
        for kernel in [Kernel::Planned, Kernel::Scalar, Kernel::General] {
            let o = opts(kernel);
            g.bench_with_input(
                BenchmarkId::new(sub.label(), format!("{kernel:?}")),
                &o,
                |b, o| b.iter(|| rt::render(&s, o)),
            );
        }
    }
    g.finish();
}

/// ns per call of every approximation in f32 and Q16.16 (1024 inputs spread over the
/// domain per iteration; criterion's elem/s is calls/s).
fn approx(c: &mut Criterion) {
    fn group<S: num::Scalar>(c: &mut Criterion) {
        let n = 1024;
        let unit: Vec<S> = (0..n)
            .map(|i| S::from_f64(-1.0 + 2.0 * (i as f64 + 0.5) / n as f64))
            .collect();
        let pos: Vec<S> = (0..n)
            .map(|i| S::from_f64(0.01 + 100.0 * (i as f64 + 0.5) / n as f64))
            .collect();
        let mut g = c.benchmark_group(format!("approx/{}", S::NAME));
        g.sample_size(20)
            .warm_up_time(Duration::from_millis(200))
            .measurement_time(Duration::from_millis(800))
            .throughput(Throughput::Elements(n as u64));
        for (name, k) in [
            ("seed", AtanKind::Seed),
            ("lut33", AtanKind::Lut33),
            ("minimax11", AtanKind::Minimax11),
            ("exact", AtanKind::Exact),
        ] {
            g.bench_function(format!("atan2/{name}"), |b| {
                b.iter(|| {
                    let mut acc = S::zero();
                    for (y, x) in unit.iter().zip(unit.iter().rev()) {
                        acc = acc + num::atan2(black_box(*y), black_box(*x), k);
                    }
                    acc
                })
            });
        }
        for (name, k) in [
            ("seed-lut33", AcosKind::SeedLut33),
            ("binade-lut", AcosKind::BinadeLut),
            ("sqrt4", AcosKind::Sqrt4),
            ("sqrt8", AcosKind::Sqrt8),
            ("exact", AcosKind::Exact),
        ] {
            g.bench_function(format!("acos/{name}"), |b| {
                b.iter(|| {
                    let mut acc = S::zero();
                    for x in &unit {
                        acc = acc + num::acos(black_box(*x), k);
                    }
                    acc
                })
            });
        }
        for (name, k) in [
            ("exact", SqrtKind::Exact),
            ("pre_s+2nr", SqrtKind::PreS { iters: 2 }),
            ("seamless+2nr", SqrtKind::Seamless { iters: 2 }),
            ("lut16+1nr", SqrtKind::Lut16 { iters: 1 }),
            ("lut16+2nr", SqrtKind::Lut16 { iters: 2 }),
        ] {
            g.bench_function(format!("rsqrt/{name}"), |b| {
                b.iter(|| {
                    let mut acc = S::zero();
                    for x in &pos {
                        acc = acc + num::rsqrt(black_box(*x), k);
                    }
                    acc
                })
            });
        }
        g.bench_function("recip/divider", |b| {
            b.iter(|| {
                let mut acc = S::zero();
                for x in &pos {
                    acc = acc + S::one() / black_box(*x);
                }
                acc
            })
        });
        for (name, lut, it) in [
            ("pre_d+2nr", false, 2u8),
            ("lut32+1nr", true, 1),
            ("lut32+2nr", true, 2),
        ] {
            g.bench_function(format!("recip/{name}"), |b| {
                b.iter(|| {
                    let mut acc = S::zero();
                    for x in &pos {
                        acc = acc
                            + if lut {
                                num::div_lut_nr(S::one(), black_box(*x), it)
                            } else {
                                num::div_nr(S::one(), black_box(*x), it)
                            };
                    }
                    acc
                })
            });
        }
        g.bench_function("pow/squaring-e64", |b| {
            b.iter(|| {
                let mut acc = S::zero();
                for x in &unit {
                    acc = acc + num::powi(black_box(x.abs()), black_box(64));
                }
                acc
            })
        });
        g.finish();
    }
    group::<f32>(c);
    group::<num::Q16_16>(c);
}

fn bench(c: &mut Criterion) {
    let text = include_str!("../../examples/reference.toml");
    let scene = match jobs::scene::parse(text, "examples/reference.toml") {
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
        .and_then(|n| n.parse::<Numeric>().ok())
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
            "{numeric:?}: {} rays/frame nominal (docs/requirements.md §4.10), {} traced, PSNR vs f64 {:.2} dB",
            frame.stats.nominal_rays,
            frame.stats.rays(),
            rt::psnr(&reference, &frame.rgb8)
        );
        g.throughput(Throughput::Elements(frame.stats.nominal_rays));
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
            "1080p {numeric:?}: {} rays/frame nominal (docs/requirements.md §4.10), {} traced, {:.3} s single shot, board estimate {:.1} ms",
            frame.stats.nominal_rays,
            frame.stats.rays(),
            frame.stats.seconds,
            frame.stats.board_seconds() * 1e3
        );
        g.throughput(Throughput::Elements(frame.stats.nominal_rays));
        g.bench_with_input(
            BenchmarkId::from_parameter(format!("{numeric:?}")),
            &numeric,
            |b, n| b.iter(|| rt::render(&scene, &full(*n))),
        );
    }
    g.finish();
}

criterion_group!(benches, plan, approx, bench);
criterion_main!(benches);
