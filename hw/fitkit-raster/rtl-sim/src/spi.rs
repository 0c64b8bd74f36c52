//! `embedded-hal` 1.0 over the Verilated block: an SPI master bit-banging mode 0 on its
//! pins, and a delay that runs its clock.
//!
//! Timing is counted in block clock cycles, the only time the model has. The block
//! samples `spi_sck` through a two-flop synchroniser (docs/rtl.md), hence the floor of
//! [`MIN_HALF_PERIOD`] cycles per SCK half period (f_SCK ≤ f_clk / 8) and the minimum
//! CS-high time [`MIN_CS_HIGH`] between transactions.

use embedded_hal::delay::DelayNs;
use embedded_hal::spi::{ErrorKind, ErrorType, Operation, SpiDevice};

use crate::{Rtl, SharedRtl};

/// Fewest clock cycles per SCK half period: f_SCK ≤ f_clk / 8 (docs/rtl.md).
pub const MIN_HALF_PERIOD: u32 = 4;
/// Fewest clock cycles `spi_cs_n` stays high between transactions (docs/rtl.md), so the
/// block sees the rising edge that commits a packet before the next one starts.
pub const MIN_CS_HIGH: u32 = 8;

/// How [`RtlSpi`] and [`RtlDelay`] turn bits and nanoseconds into clock cycles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SpiConfig {
    /// Clock cycles per SCK half period, at least [`MIN_HALF_PERIOD`].
    pub half_period: u32,
    /// Clock cycles `spi_cs_n` stays high after a transaction, at least [`MIN_CS_HIGH`].
    pub cs_high: u32,
    /// The block's clock, for `DelayNs` (an `Operation::DelayNs` or [`RtlDelay`]).
    pub clk_hz: u32,
    /// Up to this many clock cycles added at random to every SCK half period (high and
    /// low drawn apart, so the duty cycle wanders too), to the CS_n-to-first-edge and
    /// last-edge-to-CS_n holds and to the CS-high time: a real MCU's SPI is never as even
    /// as a fixed divider, and the synchroniser must not care. 0: the fixed timing.
    pub jitter: u32,
    /// Seed of the jitter's generator, so a failing case replays exactly.
    pub jitter_seed: u64,
}

impl Default for SpiConfig {
    /// The fastest SPI the contract allows, at the FITkit's 50 MHz.
    fn default() -> Self {
        Self {
            half_period: MIN_HALF_PERIOD,
            cs_high: MIN_CS_HIGH,
            clk_hz: 50_000_000,
            jitter: 0,
            jitter_seed: 0,
        }
    }
}

impl SpiConfig {
    /// Clock cycles that cover `ns` nanoseconds (rounded up: a delay is a minimum).
    pub fn cycles_for_ns(&self, ns: u32) -> u64 {
        (u64::from(ns) * u64::from(self.clk_hz)).div_ceil(1_000_000_000)
    }
}

/// Why an SPI device could not be made or a transaction not run.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SpiError {
    /// The half period is below what the block's synchroniser can follow.
    #[error("SCK half period of {0} clock cycles is below the minimum {MIN_HALF_PERIOD} (f_SCK <= f_clk/8)")]
    HalfPeriod(u32),
    /// The CS-high time is below the contract's minimum.
    #[error("CS-high time of {0} clock cycles is below the minimum {MIN_CS_HIGH}")]
    CsHigh(u32),
    /// A zero clock frequency cannot turn nanoseconds into cycles.
    #[error("clock frequency of 0 Hz")]
    Clock,
    /// The model was borrowed elsewhere (a re-entrant call through the shared handle).
    #[error("the RTL model is already borrowed")]
    Shared,
}

impl embedded_hal::spi::Error for SpiError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Other
    }
}

impl SpiConfig {
    fn check(&self) -> Result<(), SpiError> {
        if self.half_period < MIN_HALF_PERIOD {
            return Err(SpiError::HalfPeriod(self.half_period));
        }
        if self.cs_high < MIN_CS_HIGH {
            return Err(SpiError::CsHigh(self.cs_high));
        }
        if self.clk_hz == 0 {
            return Err(SpiError::Clock);
        }
        Ok(())
    }
}

/// An SPI master on the block's pins, as the MCU would be: mode 0, MSB first, one
/// transaction per CS-low period.
#[derive(Debug)]
pub struct RtlSpi {
    rtl: SharedRtl,
    config: SpiConfig,
    bits: u64,
    /// The jitter's xorshift state.
    rng: u64,
    /// The cycle CS_n last rose (the end of the last transaction).
    cs_rise: u64,
}

impl RtlSpi {
    /// A master on `rtl` with `config`'s timing.
    pub fn new(rtl: SharedRtl, config: SpiConfig) -> Result<Self, SpiError> {
        config.check()?;
        Ok(Self {
            rtl,
            config,
            bits: 0,
            rng: config.jitter_seed | 1,
            cs_rise: 0,
        })
    }

    /// `base` cycles plus the jitter's next draw in `0..=jitter`.
    fn jittered(&mut self, base: u32) -> u64 {
        let j = u64::from(self.config.jitter);
        if j == 0 {
            return u64::from(base);
        }
        self.rng ^= self.rng << 13;
        self.rng ^= self.rng >> 7;
        self.rng ^= self.rng << 17;
        u64::from(base) + self.rng % (j + 1)
    }

    /// The timing in use.
    pub fn config(&self) -> SpiConfig {
        self.config
    }

    /// The block's cycle at which CS_n last rose: where the block's decoder commits the
    /// last packet, a fixed number of cycles before its unit starts (docs/rtl.md).
    pub fn last_cs_rise(&self) -> u64 {
        self.cs_rise
    }

    /// Bits shifted (each one both out on MOSI and in from MISO) since construction.
    pub fn bits(&self) -> u64 {
        self.bits
    }

    /// One transaction that shifts out only the first `bits` bits of `bytes` (MSB first)
    /// and then raises CS_n: a master that gives up mid-byte or mid-record, which the
    /// block must discard whole. Returns an error only as `transaction` does.
    pub fn write_bits(&mut self, bytes: &[u8], bits: usize) -> Result<(), SpiError> {
        let shared = self.rtl.clone();
        let mut rtl = shared.try_borrow_mut().map_err(|_| SpiError::Shared)?;
        rtl.set_sck(false);
        rtl.set_cs_n(false);
        for k in 0..bits.min(bytes.len() * 8) {
            self.clock_bit(&mut rtl, bytes[k / 8] >> (7 - k % 8) & 1 != 0);
        }
        self.release(&mut rtl);
        Ok(())
    }

    /// One bit: MOSI is set, SCK rises after a half period and MISO is sampled at that
    /// edge, SCK falls after another.
    fn clock_bit(&mut self, rtl: &mut Rtl, mosi: bool) -> bool {
        let half = self.config.half_period;
        rtl.set_mosi(mosi);
        rtl.run(self.jittered(half));
        rtl.set_sck(true);
        let miso = rtl.miso();
        rtl.run(self.jittered(half));
        rtl.set_sck(false);
        self.bits += 1;
        miso
    }

    /// The end of a transaction: the hold after the last falling edge, then CS_n high for
    /// the contract's minimum.
    fn release(&mut self, rtl: &mut Rtl) {
        let hold = self.jittered(self.config.half_period);
        rtl.run(hold);
        rtl.set_mosi(false);
        rtl.set_cs_n(true);
        self.cs_rise = rtl.cycle();
        let high = self.jittered(self.config.cs_high);
        rtl.run(high);
    }

    /// One byte out, one in, MSB first.
    fn byte(&mut self, rtl: &mut Rtl, out: u8) -> u8 {
        (0..8).rev().fold(0u8, |got, bit| {
            got << 1 | u8::from(self.clock_bit(rtl, out >> bit & 1 != 0))
        })
    }
}

impl ErrorType for RtlSpi {
    type Error = SpiError;
}

impl SpiDevice<u8> for RtlSpi {
    fn transaction(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), SpiError> {
        let shared = self.rtl.clone();
        let mut rtl = shared.try_borrow_mut().map_err(|_| SpiError::Shared)?;
        rtl.set_sck(false);
        rtl.set_cs_n(false);
        for op in operations.iter_mut() {
            match op {
                Operation::Read(buf) => {
                    for b in buf.iter_mut() {
                        *b = self.byte(&mut rtl, 0);
                    }
                }
                Operation::Write(buf) => {
                    for &b in buf.iter() {
                        self.byte(&mut rtl, b);
                    }
                }
                Operation::Transfer(read, write) => {
                    for k in 0..read.len().max(write.len()) {
                        let got = self.byte(&mut rtl, write.get(k).copied().unwrap_or(0));
                        if let Some(r) = read.get_mut(k) {
                            *r = got;
                        }
                    }
                }
                Operation::TransferInPlace(buf) => {
                    for b in buf.iter_mut() {
                        *b = self.byte(&mut rtl, *b);
                    }
                }
                Operation::DelayNs(ns) => {
                    let n = self.config.cycles_for_ns(*ns);
                    rtl.run(n);
                }
            }
        }
        self.release(&mut rtl);
        Ok(())
    }
}

/// A delay that runs the block's clock: `delay_ns(n)` is `n` nanoseconds of cycles at
/// [`SpiConfig::clk_hz`], capped at [`RtlDelay::max_cycles`] per call so that no delay can
/// stall a test for minutes (the cap is counted, [`RtlDelay::capped`]).
#[derive(Debug)]
pub struct RtlDelay {
    rtl: SharedRtl,
    config: SpiConfig,
    max_cycles: u64,
    capped: u64,
}

impl RtlDelay {
    /// Default cap per call: 2^22 cycles, 84 ms at 50 MHz, a few seconds of simulation.
    pub const DEFAULT_MAX_CYCLES: u64 = 1 << 22;

    /// A delay on `rtl` at `config.clk_hz`, capped at [`Self::DEFAULT_MAX_CYCLES`].
    pub fn new(rtl: SharedRtl, config: SpiConfig) -> Result<Self, SpiError> {
        config.check()?;
        Ok(Self {
            rtl,
            config,
            max_cycles: Self::DEFAULT_MAX_CYCLES,
            capped: 0,
        })
    }

    /// Changes the cap per call.
    pub fn with_max_cycles(mut self, max_cycles: u64) -> Self {
        self.max_cycles = max_cycles;
        self
    }

    /// The cap per call, in cycles.
    pub fn max_cycles(&self) -> u64 {
        self.max_cycles
    }

    /// Calls that asked for more than the cap and got the cap.
    pub fn capped(&self) -> u64 {
        self.capped
    }
}

impl DelayNs for RtlDelay {
    /// Runs the clock; panics only if called while the shared model is borrowed, which
    /// is a re-entrant call from the same thread, a bug in the caller.
    fn delay_ns(&mut self, ns: u32) {
        let want = self.config.cycles_for_ns(ns);
        let n = want.min(self.max_cycles);
        if n < want {
            self.capped += 1;
        }
        self.rtl.borrow_mut().run(n);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nanoseconds_round_up_to_whole_cycles() {
        let c = SpiConfig::default();
        assert_eq!(c.cycles_for_ns(0), 0);
        assert_eq!(c.cycles_for_ns(1), 1);
        assert_eq!(c.cycles_for_ns(20), 1);
        assert_eq!(c.cycles_for_ns(21), 2);
        assert_eq!(c.cycles_for_ns(10_000), 500);
        assert_eq!(c.cycles_for_ns(u32::MAX), 214_748_365);
    }

    #[test]
    fn configs_below_the_contract_are_refused() {
        let ok = SpiConfig::default();
        assert_eq!(ok.check(), Ok(()));
        let fast = SpiConfig {
            half_period: MIN_HALF_PERIOD - 1,
            ..ok
        };
        assert_eq!(fast.check(), Err(SpiError::HalfPeriod(MIN_HALF_PERIOD - 1)));
        let cs = SpiConfig {
            cs_high: MIN_CS_HIGH - 1,
            ..ok
        };
        assert_eq!(cs.check(), Err(SpiError::CsHigh(MIN_CS_HIGH - 1)));
        let clk = SpiConfig { clk_hz: 0, ..ok };
        assert_eq!(clk.check(), Err(SpiError::Clock));
    }
}
