//! The read-back slave and window of `rt_device` against the model's register file
//! (`sim_target::mmio::RegisterFile`), access for access: the same scene rendered on both,
//! then the same writes of READ_PLANE, READ_FORMAT, the rectangle and READ_PAGE, and the
//! same reads of READ_LEN and of window words, in sequence (the cursor), backwards and at
//! random (the seek), at and past the end. Every answer must agree: the same word, or an
//! error on both (SLVERR from the RTL, a refusal from the model). The planes go through
//! the whole chain, core included, so a byte that differs is either a read-back fault or
//! a pixel the differential suite would name.

use protocol::axi_lite::{self, ctrl, readback as rb, READ_BASE, READ_WINDOW};
use protocol::bus::WIDE;
use protocol::frame::{Block, Numeric, StartFrame};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rt_core_rtl_sim::{AxiError, Device, Jitter};
use sim_target::mmio::{RegisterError, RegisterFile};

use super::scenes::{model, scene};
use super::waves::Waves;

/// Polls of `AP_CTRL` before a frame counts as stuck.
const POLLS: u32 = 1 << 20;

/// Both sides of the comparison.
struct Pair {
    rtl: Device,
    model: RegisterFile,
    /// Accesses compared so far, and how many of them both refused.
    accesses: u32,
    refused: u32,
}

impl Pair {
    fn write(&mut self, addr: u32, value: u32, what: &str) {
        let r = self.rtl.write(addr, value);
        let m = self.model.write(addr, value);
        self.agree(addr, r.map(|_| 0), m.map(|_| 0), what);
    }

    fn read(&mut self, addr: u32, what: &str) -> Option<u32> {
        let r = self.rtl.read(addr);
        let m = self.model.read(addr);
        self.agree(addr, r, m, what)
    }

    fn agree(
        &mut self,
        addr: u32,
        r: Result<u32, AxiError>,
        m: Result<u32, RegisterError>,
        what: &str,
    ) -> Option<u32> {
        self.accesses += 1;
        match (r, m) {
            (Ok(a), Ok(b)) => {
                assert_eq!(a, b, "{what}: {addr:#07x} RTL {a:#010x}, model {b:#010x}");
                Some(a)
            }
            (Err(AxiError::SlvErr { .. }), Err(_)) => {
                self.refused += 1;
                None
            }
            (r, m) => panic!("{what}: {addr:#07x} RTL {r:?}, model {m:?}"),
        }
    }

    /// Renders scene `k` on both, AOV planes as asked, at another size if given.
    fn render(
        &mut self,
        rng: &mut SmallRng,
        k: u32,
        aovs: bool,
        size: Option<(u32, u32)>,
    ) -> (u32, u32) {
        let mut s = scene(rng, k % 8);
        if let Some((w, h)) = size {
            (s.width, s.height) = (w, h);
        }
        let (words, _) = model(&s);
        for (i, w) in words.iter().enumerate() {
            let addr = axi_lite::scene_word_addr(i).expect("the image fits the window");
            self.write(addr, *w, "scene word");
        }
        let start = StartFrame {
            frame_id: 0,
            block: Block::RayTrace,
            numeric: Numeric::Q16_16,
            auto_restart: false,
            aovs,
        };
        for (a, v) in axi_lite::start_writes(&start) {
            self.write(a, v, "start");
        }
        // each side to its own ap_done (the model's comes after a number of polls)
        let done = |read: &mut dyn FnMut() -> u32| (0..POLLS).any(|_| read() & ctrl::AP_DONE != 0);
        assert!(
            done(&mut || self.rtl.read(axi_lite::AP_CTRL).expect("AP_CTRL")),
            "RTL: no ap_done"
        );
        assert!(
            done(&mut || self.model.read(axi_lite::AP_CTRL).expect("AP_CTRL")),
            "model: no ap_done"
        );
        (s.width, s.height)
    }

    /// Reads `len` bytes from byte `from` in window words, turning pages as a driver does.
    fn read_run(&mut self, from: u32, len: u32, what: &str) {
        let mut page = u32::MAX;
        let mut pos = from;
        while pos < from + len {
            if pos / READ_WINDOW != page {
                page = pos / READ_WINDOW;
                self.write(rb::PAGE, page, what);
            }
            self.read(READ_BASE + pos % READ_WINDOW, what);
            pos += 4;
        }
    }
}

#[test]
fn read_back_is_the_models_byte_for_byte() {
    let waves = Waves::new("readback::read_back_is_the_models_byte_for_byte");
    let mut rng = SmallRng::seed_from_u64(0x7265_6164);
    let mut pair = Pair {
        rtl: Device::new(Jitter {
            seed: 3,
            max_delay: 2,
            mem_busy_percent: 25,
        })
        .expect("Verilated rt_device"),
        model: RegisterFile::new(sim_target::Device::new(&WIDE)),
        accesses: 0,
        refused: 0,
    };
    // the first case: before any frame, and a 64 x 48 frame read whole. A case's
    // waveform starts after its frame: the render is the frame core's and the device's
    // tests' (and a frame's pipeline makes a long waveform), the reads are this test's.
    let mut bytes = waves.case("64x48", || {
        // before any frame: no read-back, whatever is asked
        assert_eq!(pair.read(rb::LEN, "READ_LEN at power-on"), Some(rb::NONE));
        pair.read(READ_BASE, "the window at power-on");
        // a frame whose normal plane spans three pages of the window, read whole
        let (w, h) = pair.render(&mut rng, 1, true, Some((64, 48)));
        waves.before("64x48", &mut pair.rtl);
        for (plane, format) in [(2, 4), (1, 3), (0, 0)] {
            let what = format!("64x48 plane {plane} format {format}");
            pair.write(rb::PLANE, plane, &what);
            pair.write(rb::FORMAT, format, &what);
            pair.write(rb::RECT_XY, 0, &what);
            pair.write(rb::RECT_WH, w | h << 16, &what);
            let len = pair.read(rb::LEN, &what).expect("READ_LEN");
            pair.read_run(0, len, &what);
        }
        u64::from(w * h * (12 + 4 + 3))
    });
    for k in 0..12u32 {
        let case = format!("scene {k}");
        bytes += waves.case(&case, || {
            let mut bytes = 0;
            let aovs = k % 3 != 2;
            let (w, h) = pair.render(&mut rng, k, aovs, None);
            waves.before(&case, &mut pair.rtl);
            // every plane and format whole, in sequence: what a driver reads
            for plane in 0..3 {
                for format in 0..5 {
                    let what =
                        format!("scene {k} ({w}x{h}, aovs {aovs}) plane {plane} format {format}");
                    pair.write(rb::PLANE, plane, &what);
                    pair.write(rb::FORMAT, format, &what);
                    pair.write(rb::RECT_XY, 0, &what);
                    pair.write(rb::RECT_WH, w | h << 16, &what);
                    if let Some(len) = pair.read(rb::LEN, &what).filter(|&l| l != rb::NONE) {
                        pair.read_run(0, len, &what);
                        bytes += u64::from(len);
                    }
                }
            }
            // rectangles inside, on the edge and outside; codes that name nothing; reads in
            // and out of order, at and past the end
            for t in 0..24 {
                let what = format!("scene {k} ({w}x{h}) trial {t}");
                let plane = rng.gen_range(0..4);
                let format = rng.gen_range(0..6);
                pair.write(rb::PLANE, plane, &what);
                pair.write(rb::FORMAT, format, &what);
                let (x, y) = (rng.gen_range(0..=w), rng.gen_range(0..=h));
                let (rw, rh) = if rng.gen_bool(0.85) {
                    (rng.gen_range(0..=w - x), rng.gen_range(0..=h - y))
                } else {
                    (rng.gen_range(0..=w + 2), rng.gen_range(0..=h + 2))
                };
                pair.write(rb::RECT_XY, x | y << 16, &what);
                pair.write(rb::RECT_WH, rw | rh << 16, &what);
                let len = pair.read(rb::LEN, &what).unwrap_or(rb::NONE);
                if len == rb::NONE {
                    pair.write(rb::PAGE, 0, &what);
                    pair.read(READ_BASE, &what);
                    continue;
                }
                // a run from a random word, then words at random (seeks), then the end
                let from = rng.gen_range(0..=len / 4) * 4;
                pair.read_run(from, (len - from).min(96), &what);
                for _ in 0..6 {
                    let at = rng.gen_range(0..=len / 4 + 1) * 4;
                    pair.write(rb::PAGE, at / READ_WINDOW, &what);
                    pair.read(READ_BASE + at % READ_WINDOW, &what);
                }
                let last = len.saturating_sub(1) / 4 * 4;
                pair.read_run(last, len - last, &what);
                pair.write(rb::PAGE, len / READ_WINDOW + 1, &what);
                pair.read(READ_BASE, &what);
                pair.write(rb::PAGE, 1 << 18, &what);
                pair.read(READ_BASE, &what);
                bytes += u64::from(len.min(96));
            }
            bytes
        });
    }
    println!(
        "read-back: {} accesses agreed ({} refused by both), {bytes} bytes compared",
        pair.accesses, pair.refused
    );
    assert!(bytes > 90_000, "too few bytes compared: {bytes}");
}
