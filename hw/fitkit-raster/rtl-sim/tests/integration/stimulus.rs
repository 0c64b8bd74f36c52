//! Stimulus at and between the contract's limits, each case against the golden model:
//! SPI timing with jitter, a reset at a random cycle (mid-packet, mid-drawing,
//! mid-read-back), transactions abandoned mid-byte and mid-record, `mem_wait` storms with
//! long holds, and registers and memories starting at random values. A failing case is
//! shrunk to the fewest commands that still fail and replayed into a waveform
//! (`replay`).

use fitkit_rtl_sim::{MemWait, SpiConfig, MIN_CS_HIGH, MIN_HALF_PERIOD};
use protocol::fitkit_spi::{self as wire, BlockError, ErrorCode};
use protocol::raster::{Cull, RasterCmd, RasterSetup, Rgb};
use rand::rngs::SmallRng;
use rand::Rng;

use crate::cases;
use crate::harness::{self, Pair, WAIT_BOUND};
use crate::replay;

const W: u16 = 48;
const H: u16 = 32;

/// A line, a clear or (half the time) a triangle inside the `W × H` frame.
fn command(rng: &mut SmallRng, bg: Rgb) -> RasterCmd {
    let (mx, my) = (i32::from(W) - 1, i32::from(H) - 1);
    let c = cases::color_except(rng, bg);
    match rng.gen_range(0..6) {
        0 | 1 => cases::line(cases::point(rng, mx, my), cases::point(rng, mx, my), c),
        2 => RasterCmd::Clear(c),
        _ => cases::triangle([(); 3].map(|_| cases::point(rng, mx, my)), c),
    }
}

/// A set-up and `n` commands.
fn job(rng: &mut SmallRng, n: usize) -> (RasterSetup, Vec<RasterCmd>) {
    let bg = cases::color(rng);
    let setup = harness::setup(W, H, bg, Cull::None);
    (setup, (0..n).map(|_| command(rng, bg)).collect())
}

/// Every command into both sides; equal frames after each and equal per-unit counters.
fn exact(pair: &mut Pair, case: &str, cmds: &[RasterCmd]) {
    for (n, cmd) in cmds.iter().enumerate() {
        let step = pair.step(&format!("{case} cmd {n}"), cmd, false);
        assert_eq!(step.rtl, step.model, "{case} cmd {n}: {cmd:?}: counters");
    }
}

/// The frame read back over SPI (row by row) equals the RAM: the read-back path under
/// the same timing.
fn read_back_matches(pair: &mut Pair, case: &str) {
    for y in 0..u32::from(H) {
        let got = pair.read_pixels(0, y, usize::from(W));
        let want = pair
            .rtl
            .borrow()
            .frame(u32::from(W), u32::from(H))
            .expect("frame")[(y * u32::from(W)) as usize..((y + 1) * u32::from(W)) as usize]
            .to_vec();
        assert_eq!(got, want, "{case}: read-back row {y}");
    }
    let s = pair.status();
    assert_eq!(s.error, None, "{case}: read-back: {s:?}");
}

#[test]
fn spi_timing_at_and_between_the_limits_changes_nothing() {
    let mut rng = cases::rng(0x5717);
    // the contract's floors exactly, the floors with jitter above them, a slow and
    // uneven master, and one whose holds reach ten times the floors
    let timings = [
        (MIN_HALF_PERIOD, MIN_CS_HIGH, 0),
        (MIN_HALF_PERIOD, MIN_CS_HIGH, 3),
        (5, 9, 11),
        (MIN_HALF_PERIOD, MIN_CS_HIGH, 40),
    ];
    for (k, (half_period, cs_high, jitter)) in timings.into_iter().enumerate() {
        let (setup, cmds) = job(&mut rng, 16);
        let config = SpiConfig {
            half_period,
            cs_high,
            jitter,
            jitter_seed: 0x5717 + k as u64,
            ..SpiConfig::default()
        };
        let name = format!("spi-h{half_period}-cs{cs_high}-j{jitter}");
        replay::shrinking(&name, &cmds, |cmds| {
            let mut pair = Pair::with_spi(setup, MemWait::Off, config);
            exact(&mut pair, &name, cmds);
            read_back_matches(&mut pair, &name);
        });
    }
}

/// The status of a block that has just been reset: nothing queued, nothing counted, no
/// error, no set-up.
fn assert_fresh(pair: &mut Pair, case: &str) {
    pair.rtl
        .borrow_mut()
        .wait_idle(WAIT_BOUND)
        .unwrap_or_else(|e| panic!("{case}: {e}"));
    let s = pair.status();
    assert_eq!(s.error, None, "{case}: the tail became a packet? {s:?}");
    assert_eq!(s.flags, wire::FLAG_FIFO_EMPTY, "{case}: {s:?}");
    assert_eq!(s.free, wire::FIFO_RECORDS, "{case}: {s:?}");
    assert_eq!(
        (
            s.packets,
            s.fragments,
            s.line_cycles,
            s.triangle_cycles,
            s.clear_cycles
        ),
        (0, 0, 0, 0, 0),
        "{case}: {s:?}"
    );
}

#[test]
fn a_reset_at_a_random_cycle_leaves_a_fresh_block() {
    let mut rng = cases::rng(0x7257);
    for k in 0..16 {
        let (setup, cmds) = job(&mut rng, 10);
        // anywhere in the job: mid-packet, mid-drawing, mid-read-back or between
        // transactions (the job's length measured on a block left alone)
        let length = {
            let mut pair = Pair::new(setup);
            let start = pair.rtl.borrow().cycle();
            for cmd in &cmds {
                pair.send(cmd, false);
            }
            pair.finish();
            let end = pair.rtl.borrow().cycle();
            end - start
        };
        let at = rng.gen_range(0..length);
        let cycles = rng.gen_range(1..=5u64);
        let name = format!("reset-{k}-at-{at}-for-{cycles}");
        replay::shrinking(&name, &cmds, |cmds| {
            let mut pair = Pair::new(setup);
            let start = pair.rtl.borrow().cycle();
            pair.rtl.borrow_mut().pulse_reset_at(start + at, cycles);
            for cmd in cmds {
                if pair.rtl.borrow().reset_pulsed() {
                    break;
                }
                // the RTL only: the model is restarted below; a transaction the reset
                // cuts is finished by the master, as a controller that did not notice
                let (channel, records) = pair.pack(cmd, false);
                pair.write_packet(channel, &records);
            }
            // the pulse, then CS_n high for the contract's minimum: the block takes a reset
            // as CS_n low, so a transaction needs the CS-high time after one too
            let end = start + at + cycles + u64::from(MIN_CS_HIGH);
            let now = pair.rtl.borrow().cycle();
            pair.rtl.borrow_mut().run(end.saturating_sub(now));
            assert_fresh(&mut pair, &name);
            // then the controller starts over: a fresh block's frame and counters
            pair.restart();
            exact(&mut pair, &format!("{name}, after the restart"), cmds);
        });
    }
}

#[test]
fn a_transaction_abandoned_mid_byte_or_mid_record_is_discarded() {
    let mut rng = cases::rng(0xAB07);
    for k in 0..32 {
        let (setup, cmds) = job(&mut rng, 6);
        let before = rng.gen_range(0..cmds.len());
        let name = format!("abort-{k}");
        replay::with_waveform(&name, || {
            let mut rng = cases::rng(0xAB07_0000 + k);
            let mut pair = Pair::new(setup);
            exact(&mut pair, &name, &cmds[..before]);
            // the next command's packet, cut after `bits` bits
            let (channel, records) = pair.pack(&cmds[before], false);
            let mut buf = [0u8; 2 + wire::MAX_PACKET_BYTES];
            let n = wire::packet(channel, &records, &mut buf).expect("frames");
            // cut inside it, or whole with 1 to 7 bits of a byte more
            let bits = loop {
                let b = rng.gen_range(1..(n + 1) * 8);
                if b != n * 8 {
                    break b;
                }
            };
            buf[n] = rng.gen();
            pair.wait_fifo_free();
            pair.spi.write_bits(&buf[..=n], bits).expect("SPI");
            let s = pair.finish();
            let want = (bits >= 8).then_some(BlockError {
                code: ErrorCode::Length,
                channel,
                // the set-up and the packets before count
                packet: 1 + before as u16,
            });
            assert_eq!(s.error, want, "{name}: {bits} of {} bits: {s:?}", n * 8);
            pair.assert_frames_equal(&format!("{name}: after {bits} bits"));
            // the rest lands as if the abandoned packet had never been sent, the first
            // error kept
            for (n, cmd) in cmds[before + 1..].iter().enumerate() {
                let case = format!("{name} cmd {n} after the abort");
                let last = pair.model_counters();
                let rtl_last = harness::Counters::from(pair.status());
                pair.send(cmd, false);
                let s = pair.finish();
                assert_eq!(s.error, want, "{case}: {s:?}");
                pair.assert_frames_equal(&case);
                let r = harness::Counters::from(s).minus(&rtl_last);
                let m = pair.model_counters().minus(&last);
                assert_eq!(r, m, "{case}: {cmd:?}: counters");
            }
        });
    }
}

#[test]
fn mem_wait_storms_and_long_holds_change_no_pixel() {
    let mut rng = cases::rng(0x5708);
    for (k, (max_high, max_low)) in [(40u32, 40u32), (2_000, 300), (5, 2_000)]
        .into_iter()
        .enumerate()
    {
        let (setup, cmds) = job(&mut rng, 14);
        let wait = MemWait::Bursts {
            seed: 0x5708 + k as u64,
            max_high,
            max_low,
        };
        let name = format!("storm-{max_high}-{max_low}");
        replay::shrinking(&name, &cmds, |cmds| {
            let mut pair = Pair::with(setup, wait);
            pair.rtl.borrow_mut().record_mem_wait();
            for (n, cmd) in cmds.iter().enumerate() {
                // the model told what the memory did counts every stall
                let step = pair.step_stalled(&format!("{name} cmd {n}"), cmd);
                assert_eq!(step.rtl, step.model, "{name} cmd {n}: {cmd:?}: counters");
            }
            // the read-back under the same storms: each byte its pixel, or 0 with the
            // underrun error latched (docs/rtl.md: a late byte reads 0)
            let frame = pair
                .rtl
                .borrow()
                .frame(u32::from(W), u32::from(H))
                .expect("frame");
            let mut zeros = 0;
            for y in 0..u32::from(H) {
                let got = pair.read_pixels(0, y, usize::from(W));
                for (x, &g) in got.iter().enumerate() {
                    let want = frame[y as usize * usize::from(W) + x];
                    assert!(
                        g == want || g == 0,
                        "{name}: read-back ({x}, {y}): {g:#04x}, pixel {want:#04x}"
                    );
                    zeros += usize::from(g != want);
                }
            }
            let s = pair.status();
            if zeros > 0 {
                assert_eq!(
                    s.error.map(|e| e.code),
                    Some(ErrorCode::ReadUnderrun),
                    "{name}: {zeros} late bytes read as 0: {s:?}"
                );
            }
        });
    }
}

#[test]
fn registers_starting_at_random_values_change_nothing() {
    let mut rng = cases::rng(0x8001);
    let (setup, cmds) = job(&mut rng, 12);
    let results = std::cell::RefCell::new(Vec::new());
    for seed in 1..=3u64 {
        let name = format!("x-seed-{seed}");
        replay::with_waveform(&name, || {
            let mut pair = Pair::on(
                harness::rtl_x(seed),
                setup,
                MemWait::Off,
                SpiConfig::default(),
            );
            exact(&mut pair, &name, &cmds);
            let s = pair.status();
            let frame = pair
                .rtl
                .borrow()
                .frame(u32::from(W), u32::from(H))
                .expect("frame");
            let counters = (s.packets, s.fragments, s.line_cycles, s.triangle_cycles);
            results.borrow_mut().push((frame, counters, s.clear_cycles));
        });
    }
    let r = results.into_inner();
    assert!(r.windows(2).all(|w| w[0] == w[1]), "the seeds disagree");
}
