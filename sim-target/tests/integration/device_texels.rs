//! The device's texture memory: made on the first write (a device starts without it), and
//! every write either lands or is refused, whether or not the raster block is set up.

use protocol::raster::{Aa, Cull, RasterSetup, Rgb, Traversal};
use sim_target::raster::{RasterError, TEXTURE_WORDS};
use sim_target::{Device, DeviceError};

fn setup() -> RasterSetup {
    RasterSetup {
        width: 8,
        height: 8,
        subpixel_bits: 4,
        background: Rgb::new(0, 0, 0),
        aa: Aa::default(),
        cull: Cull::None,
        traversal: Traversal::default(),
    }
}

fn refused(r: Result<(), DeviceError>, offset: u32, len: usize) {
    match r {
        Err(DeviceError::Setup(RasterError::TextureWrite {
            offset: o,
            len: l,
            words,
        })) => assert_eq!((o, l, words), (offset, len, TEXTURE_WORDS)),
        other => panic!("write of {len} bytes at {offset}: {other:?}"),
    }
}

#[test]
fn texel_writes_land_or_are_refused_before_and_after_set_up() {
    let last = (TEXTURE_WORDS - 1) as u32;
    for set_up in [false, true] {
        let mut d = Device::new(&protocol::bus::WIDE);
        if set_up {
            d.raster_setup(&setup()).expect("a small set-up");
        }
        d.write_texels(0, &[]).expect("an empty write at 0");
        d.write_texels(last, &[1, 2, 3, 4]).expect("the last texel");
        d.write_texels(0, &[0; 8]).expect("the first two texels");
        refused(d.write_texels(last, &[0; 8]), last, 8);
        refused(
            d.write_texels(TEXTURE_WORDS as u32, &[0; 4]),
            TEXTURE_WORDS as u32,
            4,
        );
        refused(d.write_texels(u32::MAX, &[0; 4]), u32::MAX, 4);
        refused(d.write_texels(0, &[0; 3]), 0, 3);
        // A set-up after the writes takes the memory over (and one before any write, an
        // empty memory), and the block goes on accepting writes.
        d.raster_setup(&setup()).expect("set-up after texel writes");
        d.write_texels(5, &[9; 4]).expect("a texel after set-up");
    }
}
