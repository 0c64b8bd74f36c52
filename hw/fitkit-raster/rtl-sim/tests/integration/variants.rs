//! The line-only and triangle-only builds (the seed's XC3S50 holds one unit at a time):
//! each says in its status which unit it lacks, refuses that unit's packets whole as an
//! unknown address, clears and reads back as the full block does, and the controller's
//! driver refuses the missing unit's commands by name before a byte is sent. (Each
//! build's own unit is held to the model by `lines` and `triangles`.)

use embedded_hal::spi::SpiDevice;
use firmware::{FitkitSpi, FitkitSpiError, FpgaBus};
use fitkit_rtl_sim::{Build, Rtl, RtlDelay, RtlSpi, SpiConfig};
use protocol::bus::{self, FITKIT};
use protocol::fitkit_spi::{self as wire, BlockError, ErrorCode};
use protocol::raster::{Cull, RasterCmd, Rgb};

use crate::cases;
use crate::harness::{self, Pair};

/// The status flags that name the units a build lacks, and nothing else of the idle
/// block's flags changes.
#[test]
fn each_build_names_the_unit_it_lacks() {
    for (build, lacks) in [
        (Build::DEFAULT, 0),
        (Build::TRI_LANES_8, 0),
        (Build::LINE, wire::FLAG_NO_TRIANGLE),
        (Build::TRI, wire::FLAG_NO_LINE),
    ] {
        let pair = Pair::with_build(harness::setup(8, 8, Rgb::new(0, 0, 0), Cull::None), build);
        let mut spi = pair.spi;
        let mut buf = [0u8; wire::STATUS_BYTES];
        spi.transaction(&mut [
            embedded_hal::spi::Operation::Write(&[wire::ADDR_STATUS]),
            embedded_hal::spi::Operation::Read(&mut buf),
        ])
        .expect("status read");
        let s = wire::Status::decode(&buf).expect("a status the block sends");
        assert_eq!(
            s.flags,
            wire::FLAG_FIFO_EMPTY | wire::FLAG_SETUP_DONE | lacks,
            "{}: {s:?}",
            build.name
        );
        assert_eq!(s.has_line_unit(), build.line_unit, "{}", build.name);
        assert_eq!(s.has_triangle_unit(), build.tri_unit, "{}", build.name);
    }
}

/// A packet for the missing unit: refused whole as an unknown address (its payload never
/// reaches the FIFO), the frame untouched, and the block still draws its own unit's
/// packets and clears after it (the error stays latched, as every error does).
#[test]
fn a_build_refuses_the_missing_units_packets() {
    let red = Rgb::new(255, 0, 0);
    let line = cases::line((1, 1), (14, 9), red);
    let triangle = cases::triangle([(2, 2), (13, 3), (6, 12)], red);
    for (build, missing, own) in [
        (Build::LINE, &triangle, &line),
        (Build::TRI, &line, &triangle),
    ] {
        let mut pair =
            Pair::with_build(harness::setup(16, 16, Rgb::new(0, 0, 0), Cull::None), build);
        let (channel, records) = pair.pack(missing, false);
        pair.write_packet(channel, &records);
        let s = pair.finish();
        assert_eq!(
            s.error,
            Some(BlockError {
                code: ErrorCode::UnknownAddress,
                channel,
                packet: 1,
            }),
            "{}: {s:?}",
            build.name
        );
        assert_eq!(
            s.packets, 0,
            "{}: the refused packet ran: {s:?}",
            build.name
        );
        pair.assert_frames_equal(&format!("{}: after the refused {missing:?}", build.name));
        // its own unit and a clear still run, pixel for pixel the model's
        pair.send(own, false);
        pair.send(&RasterCmd::Clear(Rgb::new(0, 0, 255)), true);
        pair.send(own, false);
        let s = pair.finish();
        assert_eq!(s.packets, 3, "{}: {s:?}", build.name);
        pair.assert_frames_equal(&format!("{}: its own unit after the refusal", build.name));
    }
}

/// The controller's driver learns the build from the status it reads at the set-up and
/// refuses the missing unit by name; nothing reaches the block (no error latched) and
/// the build's own unit draws what the model draws, read back through the driver.
#[test]
fn the_driver_refuses_the_missing_unit_by_name() {
    let white = Rgb::new(255, 255, 255);
    let line = cases::line((0, 0), (19, 13), white);
    let triangle = cases::triangle([(1, 1), (18, 2), (9, 14)], white);
    for (build, missing, own, name) in [
        (Build::LINE, &triangle, &line, "triangle unit"),
        (Build::TRI, &line, &triangle, "line unit"),
    ] {
        let rtl = std::rc::Rc::new(std::cell::RefCell::new(
            Rtl::with_build(build).unwrap_or_else(|e| panic!("{e}")),
        ));
        let config = SpiConfig::default();
        let spi = RtlSpi::new(rtl.clone(), config).expect("SPI");
        let delay = RtlDelay::new(rtl.clone(), config).expect("delay");
        let mut fpga = FitkitSpi::new(spi, delay);
        let mut model = sim_target::Device::new(&FITKIT);
        let setup = harness::setup(20, 15, Rgb::new(0, 0, 0), Cull::None);
        fpga.raster_setup(&setup).expect("set-up");
        model.raster_setup(&setup).expect("model set-up");
        let push = |fpga: &mut FitkitSpi<RtlSpi, RtlDelay>, cmd: &RasterCmd| {
            let records = bus::pack(&FITKIT, cmd, Default::default()).expect("packs");
            let channel = bus::channel(&FITKIT, bus::Kind::of(cmd)).expect("channel");
            fpga.fifo_free().expect("status");
            (fpga.push_packet(channel, &records), channel, records)
        };
        let (refused, _, _) = push(&mut fpga, missing);
        match refused {
            Err(e @ FitkitSpiError::Unsupported(what)) => {
                assert!(what.starts_with(name), "{}: {what}", build.name);
                assert!(e.to_string().contains(name), "{}: {e}", build.name);
            }
            other => panic!("{}: {missing:?} gave {other:?}", build.name),
        }
        let (drawn, channel, records) = push(&mut fpga, own);
        drawn.expect("the build's own unit");
        model.push_packet(channel, &records).expect("model push");
        model.drain().expect("model runs");
        while !fpga.idle().expect("status without an error") {
            fpga.wait().expect("wait");
        }
        let got = crate::firmware_driver::read_frame(&mut fpga, &setup);
        let want = model.raster().expect("set up").framebuffer().rgb();
        assert!(
            got == want,
            "{}: the read-back differs from the model",
            build.name
        );
        assert_eq!(
            fpga.counters().expect("counters").commands,
            1,
            "{}: the drawn packet, not the refused one (the set-up is not counted)",
            build.name
        );
    }
}
