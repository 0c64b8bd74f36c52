//! The SPI master and the status block on a fresh block: what a driver sees first.

use embedded_hal::spi::{Operation, SpiDevice};
use fitkit_rtl_sim::{RtlSpi, SpiConfig, SpiError};
use protocol::fitkit_spi::{self as wire, Status};

use crate::harness;

#[test]
fn a_fresh_block_reports_an_empty_fifo_and_no_set_up() {
    let rtl = harness::rtl();
    let mut spi = RtlSpi::new(rtl.clone(), SpiConfig::default()).expect("SPI");
    // 40 bytes: the status block, then zeros past byte 31.
    let mut b = [0xA5u8; 40];
    spi.transaction(&mut [
        Operation::Write(&[wire::ADDR_STATUS]),
        Operation::Read(&mut b),
    ])
    .expect("read");
    assert_eq!(&b[32..], &[0; 8], "past the status block");
    let s = Status::decode(b[..32].try_into().expect("32 bytes")).expect("decodes");
    assert_eq!(s.free, wire::FIFO_RECORDS);
    assert_eq!(s.flags, wire::FLAG_FIFO_EMPTY, "{s:?}");
    assert_eq!(s.error, None);
    assert!(rtl.borrow().fifo_free() && !rtl.borrow().busy());
    // 41 bytes of SPI, 8 bits each.
    assert_eq!(spi.bits(), 41 * 8);
}

#[test]
fn slower_sck_reads_the_same_status() {
    let rtl = harness::rtl();
    let read = |half_period| {
        let config = SpiConfig {
            half_period,
            ..SpiConfig::default()
        };
        let mut spi = RtlSpi::new(rtl.clone(), config).expect("SPI");
        let mut b = [0u8; wire::STATUS_BYTES];
        spi.transaction(&mut [
            Operation::Write(&[wire::ADDR_STATUS]),
            Operation::DelayNs(1_000),
            Operation::Read(&mut b),
        ])
        .expect("read");
        b
    };
    let fast = read(4);
    assert_eq!(read(5), fast);
    assert_eq!(read(13), fast);
}

#[test]
fn the_contract_floors_are_enforced() {
    let rtl = harness::rtl();
    let too_fast = SpiConfig {
        half_period: 3,
        ..SpiConfig::default()
    };
    assert_eq!(
        RtlSpi::new(rtl.clone(), too_fast).err(),
        Some(SpiError::HalfPeriod(3))
    );
    let short_cs = SpiConfig {
        cs_high: 7,
        ..SpiConfig::default()
    };
    assert_eq!(RtlSpi::new(rtl, short_cs).err(), Some(SpiError::CsHigh(7)));
}

#[test]
fn a_soft_reset_clears_the_set_up() {
    let mut pair = harness::Pair::new(harness::setup(
        8,
        8,
        protocol::raster::Rgb::new(0, 0, 0),
        Default::default(),
    ));
    assert_ne!(pair.status().flags & wire::FLAG_SETUP_DONE, 0);
    pair.write_raw(&[wire::ADDR_RESET]);
    let s = pair.status();
    assert_eq!(s.flags, wire::FLAG_FIFO_EMPTY, "{s:?}");
    assert_eq!((s.packets, s.fragments, s.clear_cycles), (0, 0, 0), "{s:?}");
}

#[test]
fn the_delay_runs_the_clock_within_its_cap() {
    use embedded_hal::delay::DelayNs;
    let rtl = harness::rtl();
    let mut delay = fitkit_rtl_sim::RtlDelay::new(rtl.clone(), SpiConfig::default())
        .expect("delay")
        .with_max_cycles(1_000);
    let start = rtl.borrow().cycle();
    delay.delay_us(10);
    assert_eq!(rtl.borrow().cycle() - start, 500, "10 µs at 50 MHz");
    delay.delay_ms(1);
    assert_eq!(
        rtl.borrow().cycle() - start,
        1_500,
        "1 ms capped at 1 000 cycles"
    );
    assert_eq!(delay.capped(), 1);
}

#[test]
fn every_operation_clocks_the_same_bits() {
    let rtl = harness::rtl();
    let mut spi = RtlSpi::new(rtl, SpiConfig::default()).expect("SPI");
    let mut split = [0u8; wire::STATUS_BYTES];
    spi.transaction(&mut [
        Operation::Write(&[wire::ADDR_STATUS]),
        Operation::Read(&mut split),
    ])
    .expect("write + read");
    // Transfer: the address out while byte 0 comes in (MISO is 0 during the address).
    let mut read = [0xFFu8; 1 + wire::STATUS_BYTES];
    spi.transaction(&mut [Operation::Transfer(&mut read, &[wire::ADDR_STATUS])])
        .expect("transfer");
    assert_eq!(read[0], 0);
    assert_eq!(read[1..], split);
    let mut in_place = [0u8; 1 + wire::STATUS_BYTES];
    in_place[0] = wire::ADDR_STATUS;
    spi.transaction(&mut [Operation::TransferInPlace(&mut in_place)])
        .expect("transfer in place");
    assert_eq!(in_place[1..], split);
}
