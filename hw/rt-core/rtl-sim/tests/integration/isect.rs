//! The core's intersection unit against the golden model's `shapes::intersect` (Q16.16,
//! the default math), one (ray, object) pair per clock: every hit and every distance bit
//! for bit, for rays that hit, graze and miss each shape.
//!
//! Rays: an origin inside, near or far from the unit shape (up to ±1000), aimed at a point
//! of [−1.25, 1.25]³ so that most rays pass near the surface (silhouettes included), with
//! the direction scaled from 1/64 to 16 (object space is not normalised); mixed in: axis-
//! parallel directions (a zero component: the flat shapes' and the cube's special cases),
//! the zero direction, words at the format's limits, tmin from 0 to 2⁻⁸ and tmax from
//! small to the format's maximum.

use std::collections::VecDeque;

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rt_core_rtl_sim::{Intersect, Pair};
use sim_target::num::{Scalar, Q16_16};
use sim_target::rt::{shapes, Math, Shape};

use super::waves::{Mismatches, Waves};

fn q(x: f64) -> i32 {
    Q16_16::from_f64(x).0.to_bits()
}

fn word(bits: i32) -> Q16_16 {
    Q16_16(fixed::types::I16F16::from_bits(bits))
}

/// The model's verdict for a pair: Some(t bits) on a hit.
fn model(p: &Pair) -> Option<i32> {
    let shape = Shape::from_code(u32::from(p.shape))?;
    let v = |a: [i32; 3]| sim_target::rt::V3::new(word(a[0]), word(a[1]), word(a[2]));
    shapes::intersect(
        shape,
        v(p.o),
        v(p.d),
        word(p.tmin),
        word(p.tmax),
        &Math::default(),
    )
    .map(|t| t.0.to_bits())
}

fn pair(rng: &mut SmallRng, tag: u16) -> Pair {
    let shape = if rng.gen_range(0..50) == 0 {
        7
    } else {
        rng.gen_range(0..7)
    };
    let r = |rng: &mut SmallRng, s: f64| rng.gen_range(-s..=s);
    let far = match rng.gen_range(0..8) {
        0 => 1.0,
        1 => 1.5,
        2..=5 => 4.0,
        6 => 50.0,
        _ => 1000.0,
    };
    let o = [r(rng, far), r(rng, far), r(rng, far)];
    let aim = [r(rng, 1.25), r(rng, 1.25), r(rng, 1.25)];
    let scale = 2f64.powi(rng.gen_range(-6..=4)) / (far * 1.7);
    let mut d = [0, 1, 2].map(|k| (aim[k] - o[k]) * scale);
    match rng.gen_range(0..12) {
        0 => d[rng.gen_range(0..3)] = 0.0,
        1 => {
            let k = rng.gen_range(0..3);
            d = [0.0; 3];
            d[k] = if rng.gen() { 1.0 } else { -1.0 };
        }
        2 => d = [0.0; 3],
        _ => {}
    }
    let mut p = Pair {
        shape,
        o: o.map(q),
        d: d.map(q),
        tmin: *[0, 1, 66, 256].get(rng.gen_range(0..4)).unwrap_or(&66),
        tmax: if rng.gen_range(0..4) == 0 {
            q(rng.gen_range(0.0..20.0))
        } else {
            i32::MAX
        },
        tag,
    };
    if rng.gen_range(0..64) == 0 {
        // a word at the format's limits somewhere
        let v = *[i32::MAX, i32::MIN, i32::MIN + 1, 1, -1]
            .get(rng.gen_range(0..5))
            .unwrap_or(&1);
        match rng.gen_range(0..6) {
            k @ 0..=2 => p.o[k] = v,
            k => p.d[k - 3] = v,
        }
    }
    p
}

/// Streams `n` pairs through the unit (with `gaps`: idle cycles and held cycles mixed in)
/// and checks each result as it comes out; returns the results checked and the hits per
/// shape code. A failure's case is the clock its pair went in (`cycle N`): its waveform
/// runs from there to the pair's result.
fn run(waves: &Waves, n: usize, seed: u64, gaps: bool) -> (usize, [usize; 8]) {
    let mut rtl =
        Intersect::new().expect("the Verilated core (cargo xtask setup installs verilator)");
    let replay: Option<u64> = waves
        .replaying()
        .and_then(|c| c.strip_prefix("cycle ")?.parse().ok());
    let mut rng = SmallRng::seed_from_u64(seed);
    let mut pending: VecDeque<(u64, Pair, Option<i32>)> = VecDeque::new();
    let (mut sent, mut checked, mut hits) = (0usize, 0usize, [0usize; 8]);
    let mut failures = Mismatches::default();
    let mut last = None;
    while sent < n || !pending.is_empty() {
        let input =
            (sent < n && !(gaps && rng.gen_range(0..4) == 0)).then(|| pair(&mut rng, sent as u16));
        let now = rtl.cycles() + 1;
        if let Some(at) = replay {
            waves.before(&format!("cycle {now}"), &mut rtl);
            if now > at + Intersect::LATENCY {
                waves.passed(&format!("cycle {at}"));
            }
        }
        if let Some(p) = input {
            sent += 1;
            pending.push_back((now, p, model(&p)));
        }
        if let (true, Some(before)) = (gaps && rng.gen_range(0..4) == 0, last) {
            let held = rtl.hold(pair(&mut rng, 0));
            if held != before {
                failures.push(now, format!("cycle {now}: a held cycle changed the output"));
            }
        }
        let out = rtl.cycle(input);
        last = Some(out);
        assert!(
            now < 1000 + 2 * n as u64,
            "the unit stopped producing results"
        );
        if !out.valid {
            continue;
        }
        let Some((at, p, want)) = pending.pop_front() else {
            failures.push(now, format!("a result nobody asked for at cycle {now}"));
            continue;
        };
        checked += 1;
        hits[usize::from(p.shape & 7)] += usize::from(want.is_some());
        let got = out.hit.then_some(out.t);
        let latency = now - at + 1;
        let unsupported = Shape::from_code(u32::from(p.shape)).is_none();
        if got != want
            || out.unsupported != unsupported
            || out.tag != p.tag
            || latency != Intersect::LATENCY
        {
            failures.push(
                at,
                format!(
                    "{p:?}: RTL {got:?} (unsupported {}, tag {}, {latency} cycles), model {want:?}",
                    out.unsupported, out.tag
                ),
            );
        }
        if failures.enough(waves, replay) {
            break;
        }
    }
    failures.finish(waves);
    (checked, hits)
}

#[test]
fn every_shape_matches_the_model_one_pair_per_clock() {
    let waves = Waves::new("isect::every_shape_matches_the_model_one_pair_per_clock");
    let (checked, hits) = run(&waves, 300_000, 11, false);
    assert_eq!(checked, 300_000);
    // the generator aims at the shapes: a good share of each shape's pairs hit (about
    // 43 000 pairs each)
    for (code, &h) in hits.iter().take(7).enumerate() {
        assert!(h > 5_000, "shape {code}: only {h} hits");
    }
}

#[test]
fn idle_and_held_cycles_change_nothing() {
    let waves = Waves::new("isect::idle_and_held_cycles_change_nothing");
    let (checked, _) = run(&waves, 20_000, 12, true);
    assert_eq!(checked, 20_000);
}
