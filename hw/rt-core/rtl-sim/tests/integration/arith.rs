//! The core's Q16.16 arithmetic units against the golden model's Q16.16 operations, one
//! operand set per clock: every result bit for bit, every saturation flag against what
//! the model's saturation probe saw, and every latency against the module headers.
//!
//! Operands come from a seeded generator that mixes uniform words with the places where
//! rounding and clipping are decided: 0, ±1 LSB, the word's limits, powers of two and
//! their neighbours, and quotients at the edge of overflow (|a| ≈ 2^15·|b|).

use std::collections::VecDeque;

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rt_core_rtl_sim::{MathUnits, Operands, Unit};
use sim_target::num::{Scalar, Q16_16};

use super::waves::{Mismatches, Waves};

type P = Q16_16;

fn q(bits: i32) -> P {
    Q16_16(fixed::types::I16F16::from_bits(bits))
}

fn bits(p: P) -> i32 {
    p.0.to_bits()
}

/// The model's result, and whether the format clipped it.
///
/// The flag is the format's own saturation counter's rule (the one a frame's
/// `Stats::saturations` sums): the rounded result lay beyond the word, or a division by
/// zero. It is computed here from the exact integers because that counter is private to
/// the model; the model's probe (`instrumented::Probe`) asks another question (is the result further
/// than an LSB from the exact value?) and lets pass a sum that rounds up to 2^31 and clips
/// back by less than an LSB.
fn model(unit: Unit, o: &Operands) -> (i32, bool) {
    let [a0, a1, a2] = o.a.map(q);
    let [b0, b1, b2] = o.b.map(q);
    let y = match unit {
        Unit::Mul => a0 * b0,
        Unit::MulRn => a0.mul_rn(b0),
        Unit::Dot2 => P::dot2(a0, b0, a1, b1),
        Unit::Dot3 => P::dot3(a0, b0, a1, b1, a2, b2),
        Unit::Div => a0 / b0,
        Unit::Sqrt => a0.sqrt(),
        Unit::Rsqrt => a0.rsqrt(),
        Unit::ToF32 => return ((a0.to_f64() as f32).to_bits() as i32, false),
    };
    let [a0, a1, a2] = o.a.map(i128::from);
    let [b0, b1, b2] = o.b.map(i128::from);
    let beyond = |v: i128| v > i32::MAX as i128 || v < i32::MIN as i128;
    let half = 1 << 15;
    let sat = match unit {
        Unit::Mul => beyond((a0 * b0) >> 16),
        Unit::MulRn => beyond((a0 * b0 + half) >> 16),
        Unit::Dot2 => beyond((a0 * b0 + a1 * b1 + half) >> 16),
        Unit::Dot3 => beyond((a0 * b0 + a1 * b1 + a2 * b2 + half) >> 16),
        // i128 division truncates toward zero, as the model's divider
        Unit::Div => b0 == 0 || beyond((a0 << 16) / b0),
        Unit::Sqrt | Unit::ToF32 => false,
        Unit::Rsqrt => a0 <= 0,
    };
    (bits(y), sat)
}

/// A word from the mix described in the module docs.
fn word(rng: &mut SmallRng) -> i32 {
    match rng.gen_range(0..8) {
        0 => *[
            0,
            1,
            -1,
            i32::MAX,
            i32::MIN,
            i32::MIN + 1,
            1 << 16,
            -(1 << 16),
        ]
        .get(rng.gen_range(0..8))
        .unwrap_or(&0),
        1 => {
            let p = 1i32.wrapping_shl(rng.gen_range(0..31));
            p.wrapping_add(rng.gen_range(-2..=2)) * if rng.gen() { 1 } else { -1 }
        }
        2 => rng.gen_range(-(1 << 16)..=(1 << 16)),
        3 => rng.gen_range(-(1 << 24)..=(1 << 24)),
        _ => rng.gen(),
    }
}

fn operands(rng: &mut SmallRng) -> Operands {
    let mut o = Operands {
        a: [word(rng), word(rng), word(rng)],
        b: [word(rng), word(rng), word(rng)],
    };
    if rng.gen_range(0..8) == 0 {
        // the divider's overflow edge: |a0| >> 16 against |b0|
        let b: i32 = rng.gen_range(1..(1 << 15));
        let k = b.wrapping_shl(16).wrapping_add(rng.gen_range(-3..=3));
        o.a[0] = if rng.gen() { k } else { k.wrapping_neg() };
        o.b[0] = if rng.gen() { b } else { -b };
    }
    o
}

/// Streams `n` operand sets (one per clock; with `gaps`, idle cycles and cycles with the
/// clock enable low mixed in) through every unit and checks each result as it comes out:
/// a held cycle must take no operands and move no result. Returns the results checked.
/// A failure's case is the clock its operand set went in (`cycle N`): its waveform runs
/// from there to the slowest unit's result.
fn run(waves: &Waves, n: usize, seed: u64, gaps: bool) -> usize {
    let mut rtl =
        MathUnits::new().expect("the Verilated core (cargo xtask setup installs verilator)");
    let replay: Option<u64> = waves
        .replaying()
        .and_then(|c| c.strip_prefix("cycle ")?.parse().ok());
    let slowest = Unit::ALL.iter().map(|u| u.latency()).max().unwrap_or(0);
    let mut rng = SmallRng::seed_from_u64(seed);
    // per unit: (cycle the operands went in, operands, model result, model saturation)
    let mut pending: Vec<VecDeque<(u64, Operands, i32, bool)>> =
        Unit::ALL.iter().map(|_| VecDeque::new()).collect();
    let mut sent = 0;
    let mut checked = 0;
    let mut failures = Mismatches::default();
    let mut last = None;
    while sent < n || pending.iter().any(|p| !p.is_empty()) {
        let input = (sent < n && !(gaps && rng.gen_range(0..4) == 0)).then(|| operands(&mut rng));
        let now = rtl.cycles() + 1;
        if let Some(at) = replay {
            waves.before(&format!("cycle {now}"), &mut rtl);
            if now > at + slowest {
                waves.passed(&format!("cycle {at}"));
            }
        }
        if let Some(o) = input {
            sent += 1;
            for (k, unit) in Unit::ALL.iter().enumerate() {
                let (y, sat) = model(*unit, &o);
                pending[k].push_back((now, o, y, sat));
            }
        }
        if let (true, Some(before)) = (gaps && rng.gen_range(0..4) == 0, last) {
            let held = rtl.hold(operands(&mut rng));
            if held != before {
                failures.push(now, format!("cycle {now}: a held cycle changed an output"));
            }
        }
        let out = rtl.cycle(input);
        last = Some(out);
        assert!(
            now < 200 + 2 * n as u64,
            "the units stopped producing results"
        );
        for (k, unit) in Unit::ALL.iter().enumerate() {
            let got = out.of(*unit);
            if !got.valid {
                continue;
            }
            let Some((at, o, y, sat)) = pending[k].pop_front() else {
                failures.push(
                    now,
                    format!("{unit:?}: a result nobody asked for at cycle {now}"),
                );
                continue;
            };
            checked += 1;
            let latency = now - at + 1;
            // sqrt and to_f32 have no saturation output: their results always fit
            let sat_ok = matches!(unit, Unit::Sqrt | Unit::ToF32) || got.sat == sat;
            if got.y != y || !sat_ok || latency != unit.latency() {
                failures.push(at, format!(
                    "{unit:?} {o:?}: RTL {:#010x} sat {} after {latency} cycles, model {:#010x} sat {sat} after {}",
                    got.y as u32,
                    got.sat,
                    y as u32,
                    unit.latency()
                ));
            }
        }
        if failures.enough(waves, replay) {
            break;
        }
    }
    failures.finish(waves);
    checked
}

#[test]
fn every_unit_matches_the_model_one_operand_set_per_clock() {
    let waves = Waves::new("arith::every_unit_matches_the_model_one_operand_set_per_clock");
    let checked = run(&waves, 1_000_000, 1, false);
    assert_eq!(checked, 1_000_000 * Unit::ALL.len());
}

#[test]
fn idle_cycles_between_operands_change_nothing() {
    let waves = Waves::new("arith::idle_cycles_between_operands_change_nothing");
    let checked = run(&waves, 20_000, 2, true);
    assert_eq!(checked, 20_000 * Unit::ALL.len());
}

#[test]
fn the_edges_of_every_unit() {
    let edges = [
        0,
        1,
        -1,
        2,
        -2,
        0x7fff,
        0x8000,
        0xffff,
        0x1_0000,
        -0x1_0000,
        0x7fff_ffff,
        -0x8000_0000,
        -0x7fff_ffff,
        0x4000_0000,
        0x3fff_ffff,
    ];
    let waves = Waves::new("arith::the_edges_of_every_unit");
    let mut rtl = MathUnits::new().expect("the Verilated core");
    // one case: 225 sets, 325 clocks
    waves.before("all", &mut rtl);
    let mut expected = Vec::new();
    for &a in &edges {
        for &b in &edges {
            let o = Operands {
                a: [a, b, a],
                b: [b, a, b],
            };
            expected.push(o);
        }
    }
    let mut outs = Vec::new();
    for o in &expected {
        outs.push(rtl.cycle(Some(*o)));
    }
    for _ in 0..100 {
        outs.push(rtl.cycle(None));
    }
    waves.case("all", || {
        for unit in Unit::ALL {
            let lat = unit.latency() as usize;
            for (i, o) in expected.iter().enumerate() {
                let got = outs[i + lat - 1].of(unit);
                let (y, sat) = model(unit, o);
                assert!(got.valid, "{unit:?} {o:?}: no result after {lat} cycles");
                assert_eq!(
                    (
                        got.y,
                        got.sat || matches!(unit, Unit::Sqrt | Unit::ToF32) && sat
                    ),
                    (y, sat),
                    "{unit:?} {o:?}"
                );
            }
        }
    });
}
