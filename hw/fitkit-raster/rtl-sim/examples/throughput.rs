//! How fast the Verilated block runs here: clock cycles, fragments and SPI bits per
//! second of wall time, over a fixed seeded mix of set-ups, lines and triangles.
//!
//! `cargo run -p fitkit-rtl-sim --release --example throughput` (the C++ is -O3 in any
//! profile; `--release` only speeds up the Rust side).

use std::time::Instant;

use anyhow::{bail, Context, Result};
use embedded_hal::spi::SpiDevice;
use fitkit_rtl_sim::{Rtl, RtlSpi, SpiConfig};
use protocol::bus::{self, FITKIT};
use protocol::fitkit_spi::{self as wire, Status};
use protocol::raster::{Cull, Line, LineAlgo, Point, RasterCmd, Shade, Triangle};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// Cycle bound of every wait: far above the longest command here.
const BOUND: u64 = 50_000_000;

fn main() -> Result<()> {
    let rtl = Rtl::shared()?;
    let mut spi = RtlSpi::new(rtl.clone(), SpiConfig::default())?;
    let mut rng = SmallRng::seed_from_u64(0xF17);
    let started = Instant::now();
    let mut fragments = 0u64;
    let mut spi_time = 0f64;
    for _frame in 0..8 {
        let setup = wire::Setup {
            width: 256,
            height: 256,
            background: rng.gen(),
            cull: Cull::None,
        };
        send(
            &rtl,
            &mut spi,
            wire::ADDR_SETUP,
            &[setup.record()?],
            &mut spi_time,
        )?;
        for k in 0..200 {
            let p = |rng: &mut SmallRng| Point {
                x: rng.gen_range(0..256),
                y: rng.gen_range(0..256),
            };
            let color = bus::rgb332_decode(rng.gen());
            let cmd = if k % 2 == 0 {
                RasterCmd::Line(Line {
                    from: p(&mut rng),
                    to: p(&mut rng),
                    color,
                    color_to: None,
                    width: 1,
                    aa: false,
                    algo: LineAlgo::Bresenham,
                })
            } else {
                RasterCmd::Triangle(Triangle {
                    v: [p(&mut rng), p(&mut rng), p(&mut rng)],
                    shade: Shade::Flat(color),
                    z: None,
                    w: None,
                    tex: None,
                })
            };
            let records = bus::pack(&FITKIT, &cmd, Default::default())?;
            let channel = bus::channel(&FITKIT, bus::Kind::of(&cmd))?;
            send(&rtl, &mut spi, channel, &records, &mut spi_time)?;
        }
        rtl.borrow_mut().wait_idle(BOUND)?;
        let mut b = [0u8; wire::STATUS_BYTES];
        spi.transaction(&mut [
            embedded_hal::spi::Operation::Write(&[wire::ADDR_STATUS]),
            embedded_hal::spi::Operation::Read(&mut b),
        ])?;
        let s = Status::decode(&b)?;
        if let Some(e) = s.error {
            bail!("{e}");
        }
        fragments += u64::from(s.fragments);
    }
    let secs = started.elapsed().as_secs_f64();
    let cycles = rtl.borrow().cycle();
    println!(
        "{cycles} cycles, {fragments} fragments, {} SPI bits in {secs:.2} s",
        spi.bits()
    );
    println!(
        "{:.2} M cycles/s, {:.2} M fragments/s, {:.1} k SPI bits/s ({:.2} s of the run clocking SPI)",
        cycles as f64 / secs / 1e6,
        fragments as f64 / secs / 1e6,
        spi.bits() as f64 / spi_time / 1e3,
        spi_time
    );
    Ok(())
}

/// Waits for FIFO_FREE, then writes one packet; adds the SPI part's wall time.
fn send(
    rtl: &fitkit_rtl_sim::SharedRtl,
    spi: &mut RtlSpi,
    address: u8,
    records: &[u64],
    spi_time: &mut f64,
) -> Result<()> {
    rtl.borrow_mut()
        .wait_until("fifo_free", BOUND, |r| r.fifo_free())
        .context("FIFO never drained")?;
    let mut buf = [0u8; 1 + wire::MAX_PACKET_BYTES];
    let n = wire::packet(address, records, &mut buf)?;
    let t = Instant::now();
    spi.write(&buf[..n])?;
    *spi_time += t.elapsed().as_secs_f64();
    Ok(())
}
