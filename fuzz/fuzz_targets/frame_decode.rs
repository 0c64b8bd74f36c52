//! Any bytes through the frame decoder (COBS + CRC), the message decoders and the in-place
//! raster-batch walker: a value or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use protocol::frame::{decode, raster_commands, DeviceFrame, HostFrame};
use protocol::link::decode_frame;

fuzz_target!(|data: &[u8]| {
    let mut buf = data.to_vec();
    if let Ok((_, payload)) = decode_frame(&mut buf) {
        let _ = decode::<HostFrame>(payload);
    }
    let _ = decode::<HostFrame>(data);
    let _ = decode::<DeviceFrame>(data);
    if let Ok(it) = raster_commands(data) {
        for c in it.take(64) {
            if c.is_err() {
                break;
            }
        }
    }
});
