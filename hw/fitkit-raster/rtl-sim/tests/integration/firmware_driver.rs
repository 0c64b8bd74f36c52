//! The controller's own FITkit driver (`firmware::fitkit_spi::FitkitSpi`, an `FpgaBus`)
//! over `RtlSpi` and `RtlDelay`: set-up, packets behind its FIFO accounting, completion
//! by status polling and the framebuffer read back, against the model.

use firmware::{FitkitSpi, FpgaBus};
use fitkit_rtl_sim::{RtlDelay, RtlSpi, SpiConfig};
use protocol::bus::{self, FITKIT};
use protocol::frame::{Block, Numeric, PixelFormat, Plane, ReadRequest, Rect, StartFrame};
use protocol::raster::{Cull, RasterSetup};
use sim_target::Device;

use crate::cases;
use crate::harness;

/// The whole frame read back through the driver, as RGB888.
pub fn read_frame(fpga: &mut FitkitSpi<RtlSpi, RtlDelay>, setup: &RasterSetup) -> Vec<u8> {
    let req = ReadRequest {
        plane: Plane::Color,
        format: PixelFormat::Rgb888,
        rect: Rect {
            x: 0,
            y: 0,
            w: setup.width,
            h: setup.height,
        },
    };
    let n = fpga.read_len(&req).expect("len").expect("readable") as usize;
    let mut got = vec![0u8; n];
    fpga.read(&req, 0, &mut got).expect("read-back");
    got
}

#[test]
fn the_firmware_driver_draws_what_the_model_draws() {
    let rtl = harness::rtl();
    let config = SpiConfig::default();
    let spi = RtlSpi::new(rtl.clone(), config).expect("SPI");
    let delay = RtlDelay::new(rtl.clone(), config).expect("delay");
    let mut fpga = FitkitSpi::new(spi, delay);
    let mut model = Device::new(&FITKIT);
    let mut rng = cases::rng(0x71);
    let bg = cases::color(&mut rng);
    let setup = harness::setup(80, 60, bg, Cull::None);
    fpga.raster_setup(&setup).expect("set-up");
    model.raster_setup(&setup).expect("model set-up");
    for k in 0..60 {
        let c = cases::color_except(&mut rng, bg);
        let cmd = if k % 2 == 0 {
            cases::line(
                cases::point(&mut rng, 79, 59),
                cases::point(&mut rng, 79, 59),
                c,
            )
        } else {
            cases::triangle([(); 3].map(|_| cases::point(&mut rng, 79, 59)), c)
        };
        let records = bus::pack(&FITKIT, &cmd, Default::default()).expect("packs");
        let channel = bus::channel(&FITKIT, bus::Kind::of(&cmd)).expect("channel");
        let mut polls = 0;
        while fpga.fifo_free().expect("status") < records.len() {
            fpga.wait().expect("wait");
            polls += 1;
            assert!(polls < 100_000, "FIFO never drained");
        }
        fpga.push_packet(channel, &records).expect("push");
        model.push_packet(channel, &records).expect("model push");
    }
    model.drain().expect("model runs");
    fpga.start(&StartFrame {
        frame_id: 7,
        block: Block::Raster,
        numeric: Numeric::F32,
        auto_restart: false,
        aovs: false,
    })
    .expect("start");
    let done = loop {
        if let Some(d) = fpga.poll_done().expect("poll") {
            break d;
        }
        fpga.wait().expect("wait");
    };
    assert_eq!(done.frame_id, 7);
    let got = read_frame(&mut fpga, &setup);
    let want = model.raster().expect("set up").framebuffer().rgb();
    assert!(got == want, "the driver's read-back differs from the model");
    assert_eq!(done.work, model.raster().expect("set up").stats().fragments);
}
