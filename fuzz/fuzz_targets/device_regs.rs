//! Any 32-bit words as the ray tracer's register image, through what the device runs on
//! `ap_start`: `SceneRegs::from_words` (magic, version, value format), `from_regs` (the
//! scene the image describes) and, if it accepts, a frame. Beyond "never panics":
//! - an image `from_words` accepts holds exactly the input words (`words`, `to_words`,
//!   `word` agree with it); one it refuses has a wrong magic, version or value-format word;
//! - a scene `from_regs` reads has as many objects and lights as the header's counts
//!   say (the light count includes the ambient light, so 0 and 1 both mean none besides
//!   it), one material per object, and refusals have a message;
//! - the scene written back with `jobs::scene::to_regs_as` in the image's format (when
//!   the host's writer accepts it) reads back as the same scene, and its derived words
//!   pass `check_derived`;
//! - `Device::start` on the image (frame clamped to at most 8 × 8, 1 spp, depth ≤ 4 so
//!   that a run stays short) succeeds exactly when both decoders accept and the renderer
//!   does, then reports the frame and offers width · height · 3 bytes of RGB888.
//!
//! Input: byte 0 picks the frame's number format (bits 0–2) and the mode (bit 7); the
//! rest are little-endian words. Mode 0: the words are the image from word 0, words the
//! input does not give come from a valid base image (one of the example scenes, chosen by
//! bits 3–6). Mode 1: the base image, patched by (u16 offset, u32 word) pairs, as RegWrite
//! frames reach the device.
#![no_main]
use libfuzzer_sys::fuzz_target;
use protocol::frame::{Block, Numeric, PixelFormat, Plane, ReadRequest, Rect, StartFrame};
use protocol::scene::{hdr, ValueFormat, MAGIC};
use sim_target::scene_regs::{check_derived, from_regs, Regs};
use sim_target::{Device, DeviceError};

mod common;
use common::WORDS;

/// Debug text, so that NaN fields compare equal to themselves.
fn same<T: std::fmt::Debug>(a: &T, b: &T) -> bool {
    format!("{a:?}") == format!("{b:?}")
}

fuzz_target!(|data: &[u8]| {
    let Some((&ctl, rest)) = data.split_first() else {
        return;
    };
    let numeric = Numeric::ALL[usize::from(ctl & 7) % Numeric::ALL.len()];
    let mut words = common::image(ctl, rest);
    decode(&words);

    // The frame as the device renders it, kept tiny.
    common::tiny(&mut words);
    let scene = Regs::from_words(&words)
        .ok()
        .and_then(|r| from_regs(&r).ok());
    let mut device = Device::new(&protocol::bus::WIDE);
    device
        .write_regs(0, &words)
        .expect("a whole image fits the register file");
    let started = device.start(&StartFrame {
        frame_id: 7,
        block: Block::RayTrace,
        numeric,
        auto_restart: false,
        aovs: false,
    });
    match started {
        Ok(()) => {
            let scene = scene.expect("the device rendered an image the decoders refuse");
            let done = device.poll_done().expect("a started frame is done");
            assert_eq!(done.frame_id, 7);
            let (w, h) = (scene.width, scene.height);
            let req = ReadRequest {
                plane: Plane::Color,
                rect: Rect {
                    x: 0,
                    y: 0,
                    w: w as u16,
                    h: h as u16,
                },
                format: PixelFormat::Rgb888,
            };
            assert_eq!(device.read_len(&req), Some(w * h * 3), "{w}x{h} frame");
        }
        Err(DeviceError::Scene(e)) => {
            assert!(
                scene.is_none(),
                "the device refused what the decoders accept: {e}"
            );
            assert!(!e.to_string().is_empty());
        }
        Err(DeviceError::Render(e)) => assert!(!e.to_string().is_empty()),
        Err(e) => panic!("ap_start failed otherwise: {e}"),
    }
});

fn decode(words: &[u32; WORDS]) {
    let regs = match Regs::from_words(words) {
        Ok(r) => r,
        Err(e) => {
            assert!(
                words[hdr::MAGIC] != MAGIC
                    || words[hdr::VERSION] != Regs::VERSION_WORD
                    || ValueFormat::from_code(words[hdr::VALUE_FORMAT]).is_none(),
                "refused a well-headed image: {e}"
            );
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    assert!(
        regs.words().eq(words.iter().copied()),
        "the image is not its words"
    );
    let mut back = [0u32; WORDS];
    assert_eq!(regs.to_words(&mut back), Ok(WORDS));
    assert_eq!(&back, words);
    assert_eq!(regs.word(WORDS), None);
    assert_eq!(regs.word(WORDS - 1), Some(words[WORDS - 1]));

    let scene = match from_regs(&regs) {
        Ok(s) => s,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    assert_eq!(scene.objects.len(), regs.object_count() as usize);
    // The count includes the ambient light, which is read from block 0 whatever the
    // count says (a count of 0 renders as 1: ambient only).
    assert_eq!(
        scene.lights.len(),
        (regs.light_count() as usize).saturating_sub(1)
    );
    assert_eq!(scene.materials.len(), scene.objects.len());
    for (i, o) in scene.objects.iter().enumerate() {
        assert_eq!(o.material, i);
    }

    // The host's writer, fed what the device read, writes an image the device reads as
    // the same scene, with the derived words the core checks.
    let fmt = regs.value_format();
    if let Ok(again) = jobs::scene::to_regs_as(&scene, fmt) {
        let reread = from_regs(&again).expect("the host's image decodes");
        assert!(same(&reread, &scene), "{scene:?}\nrewritten as\n{reread:?}");
        if let Err(e) = check_derived(&again) {
            panic!("the host's own image fails check_derived: {e}");
        }
    }
}
