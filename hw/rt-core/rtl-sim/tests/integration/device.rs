//! The core on its bus, `rt_device`, driven as a soft core drives it: the scene image and
//! the start through AXI4-Lite writes (`protocol::axi_lite::write_sequence`), `AP_CTRL`
//! polled until `ap_done`, the results from the registers, every pixel from the memory
//! port. The master's VALID and READY come after random delays and the memory stalls at
//! random, so every handshake happens in many timings. Held to: the model's frame and
//! clock count, the HLS control semantics, and SLVERR for everything the map does not
//! allow.

use protocol::axi_lite::{self, ctrl, irq, sys};
use protocol::frame::{Block, Numeric, StartFrame};
use rand::rngs::SmallRng;
use rand::SeedableRng;
use rt_core_rtl_sim::{AxiError, CastFrame, CastPixel, Device, Jitter, MemRecord};
use sim_target::rt::core::CoreFrame;
use sim_target::rt::Scene;

use super::scenes::{compare, model, scene};
use super::waves::Waves;

/// Reads of `AP_CTRL` before a frame counts as stuck.
const POLLS: u32 = 1 << 20;

fn start(aovs: bool, auto_restart: bool) -> StartFrame {
    StartFrame {
        frame_id: 0,
        block: Block::RayTrace,
        numeric: Numeric::Q16_16,
        auto_restart,
        aovs,
    }
}

/// Writes the scene image word by word through the scene window.
fn load(dev: &mut Device, words: &[u32]) {
    for (i, w) in words.iter().enumerate() {
        let addr = axi_lite::scene_word_addr(i).expect("the image fits the window");
        dev.write(addr, *w).expect("scene word written");
    }
}

/// Polls `AP_CTRL` until `ap_done`; the word read then.
fn wait_done(dev: &mut Device) -> u32 {
    for _ in 0..POLLS {
        let c = dev.read(axi_lite::AP_CTRL).expect("AP_CTRL reads");
        if c & ctrl::AP_DONE != 0 {
            return c;
        }
    }
    panic!("AP_CTRL: ap_done not seen after {POLLS} polls");
}

/// A 64-bit register, low word first.
fn read64(dev: &mut Device, addr: u32) -> u64 {
    let lo = dev.read(addr).expect("low word");
    let hi = dev.read(addr + 4).expect("high word after its low word");
    u64::from(hi) << 32 | u64::from(lo)
}

/// The memory port's records as the frame core's pixels.
fn pixels(records: &[MemRecord], width: u32) -> CastFrame {
    let mut frame = CastFrame::default();
    for r in records {
        frame.pixels.push(CastPixel {
            x: (r.index % width) as u16,
            y: (r.index / width) as u16,
            hit: r.obj != 0xFF,
            obj: if r.obj == 0xFF { 0 } else { r.obj },
            t: r.t,
            n: r.n,
            rgb: [(r.rgb >> 16) as u8, (r.rgb >> 8) as u8, r.rgb as u8],
            kcu116: r.kcu116,
        });
    }
    frame
}

/// Clocks the device's frame takes: the model's count for the core, one more per clock
/// the memory held it.
fn expected(s: &Scene) -> u64 {
    CoreFrame::of(s).cycles()
}

#[test]
fn frames_through_the_bus_are_the_models() {
    let waves = Waves::new("device::frames_through_the_bus_are_the_models");
    let mut rng = SmallRng::seed_from_u64(0x6178_6934);
    let mut dev = Device::new(Jitter {
        seed: 7,
        max_delay: 3,
        mem_busy_percent: 20,
    })
    .expect("Verilated rt_device");
    let id = dev.read(sys::ID).expect("ID");
    let version = dev.read(sys::VERSION).expect("VERSION");
    assert_eq!((id, version), (axi_lite::DEVICE_ID, axi_lite::MAP_VERSION));
    let (mut total, mut frames) = (0u64, 0u64);
    for k in 0..24u32 {
        let s = scene(&mut rng, k % 8);
        let (words, m) = model(&s);
        let case = format!("scene {k}");
        waves.before(&case, &mut dev);
        waves.case(&case, || {
            load(&mut dev, &words);
            for (a, v) in axi_lite::start_writes(&start(true, false)) {
                dev.write(a, v).expect("start writes");
            }
            let held = dev.held();
            let c = wait_done(&mut dev);
            assert_eq!(
                c & !ctrl::AUTO_RESTART,
                ctrl::AP_DONE | ctrl::AP_READY | ctrl::AP_IDLE,
                "scene {k}: AP_CTRL at the end {c:#x}"
            );
            let held = dev.held() - held;
            let records = dev.take_records();
            assert!(records.iter().all(|r| r.aovs), "scene {k}: AOVS was set");
            if let Err(e) = compare(&pixels(&records, s.width), &m) {
                panic!("scene {k} (class {}): {e}", k % 8);
            }
            let cycles = read64(&mut dev, sys::RT_CYCLES);
            assert_eq!(cycles, expected(&s) + held, "scene {k}: RT_CYCLES");
            let f = CoreFrame::of(&s);
            let rays = u64::from(s.width * s.height) * (1 + u64::from(f.shadow_lights));
            assert_eq!(read64(&mut dev, sys::RT_WORK), rays, "scene {k}: RT_WORK");
            total += cycles;
            frames += 1;
            assert_eq!(
                read64(&mut dev, axi_lite::counter_addr(1)),
                total,
                "cycles counter"
            );
            assert_eq!(
                read64(&mut dev, axi_lite::counter_addr(2)),
                frames,
                "frames counter"
            );
        });
    }
}

#[test]
fn the_control_word_and_interrupts_follow_hls() {
    let waves = Waves::new("device::the_control_word_and_interrupts_follow_hls");
    let mut rng = SmallRng::seed_from_u64(0x6374_726c);
    let mut dev = Device::new(Jitter {
        seed: 3,
        max_delay: 2,
        mem_busy_percent: 0,
    })
    .expect("Verilated rt_device");
    // one case: three small frames and the accesses around them
    waves.before("all", &mut dev);
    waves.case("all", || {
        let s = loop {
            let s = scene(&mut rng, 0);
            if s.width * s.height < 200 {
                break s;
            }
        };
        let (words, _) = model(&s);
        load(&mut dev, &words);
        dev.write(axi_lite::NUMERIC, axi_lite::numeric_code(Numeric::Q16_16))
            .expect("NUMERIC");
        assert_eq!(
            dev.read(axi_lite::AP_CTRL),
            Ok(ctrl::AP_IDLE),
            "idle at power-on"
        );
        // ap_done's interrupt enabled, the global enable not yet
        dev.write(axi_lite::IER, irq::DONE).expect("IER");
        dev.write(axi_lite::AP_CTRL, ctrl::AP_START).expect("start");
        let running = dev.read(axi_lite::AP_CTRL).expect("AP_CTRL");
        assert_eq!(running, ctrl::AP_START, "running: ap_start held, not idle");
        assert_eq!(
            dev.write(axi_lite::AP_CTRL, ctrl::AP_START),
            Err(AxiError::SlvErr {
                addr: axi_lite::AP_CTRL,
                write: true
            }),
            "a start while running"
        );
        assert_eq!(
            dev.write(axi_lite::scene_word_addr(3).unwrap_or(0), 0),
            Err(AxiError::SlvErr {
                addr: axi_lite::scene_word_addr(3).unwrap_or(0),
                write: true
            }),
            "a scene word while running"
        );
        let c = wait_done(&mut dev);
        assert_eq!(c, ctrl::AP_DONE | ctrl::AP_READY | ctrl::AP_IDLE);
        assert_eq!(
            dev.read(axi_lite::AP_CTRL),
            Ok(ctrl::AP_IDLE),
            "done and ready clear on read"
        );
        assert_eq!(
            dev.read(axi_lite::ISR),
            Ok(irq::DONE),
            "the enabled event is pending"
        );
        assert!(!dev.irq(), "no interrupt without GIE");
        dev.write(axi_lite::GIE, 1).expect("GIE");
        assert!(dev.irq(), "GIE and a pending bit raise the line");
        dev.write(axi_lite::ISR, irq::DONE).expect("ISR toggle");
        assert_eq!(
            dev.read(axi_lite::ISR),
            Ok(0),
            "a written 1 toggles the bit off"
        );
        assert!(!dev.irq(), "acknowledged");

        // auto-restart: frames follow each other without going idle, until it is cleared
        let frames = read64(&mut dev, axi_lite::counter_addr(2));
        dev.write(axi_lite::AP_CTRL, ctrl::AP_START | ctrl::AUTO_RESTART)
            .expect("start with auto-restart");
        let c = wait_done(&mut dev);
        assert_eq!(
            c,
            ctrl::AP_START | ctrl::AP_DONE | ctrl::AP_READY | ctrl::AUTO_RESTART,
            "an auto-restarted block does not go idle"
        );
        wait_done(&mut dev);
        dev.write(axi_lite::AP_CTRL, 0).expect("auto-restart off");
        let c = wait_done(&mut dev);
        assert_eq!(
            c & ctrl::AP_IDLE,
            ctrl::AP_IDLE,
            "idle after the last frame: {c:#x}"
        );
        let ran = read64(&mut dev, axi_lite::counter_addr(2)) - frames;
        assert!(ran >= 3, "three frames at least ran back to back: {ran}");
        dev.take_records();

        // RESET: the power-on state, and a frame still runs after it
        dev.write(axi_lite::GIE, 1).expect("GIE");
        dev.write(sys::RESET, 1).expect("RESET");
        for (reg, what) in [
            (axi_lite::GIE, "GIE"),
            (axi_lite::IER, "IER"),
            (axi_lite::ISR, "ISR"),
            (axi_lite::NUMERIC, "NUMERIC"),
        ] {
            assert_eq!(dev.read(reg), Ok(0), "{what} after RESET");
        }
        assert_eq!(
            read64(&mut dev, axi_lite::counter_addr(2)),
            0,
            "frames after RESET"
        );
        load(&mut dev, &words);
        for (a, v) in axi_lite::start_writes(&start(false, false)) {
            dev.write(a, v).expect("start writes");
        }
        wait_done(&mut dev);
        let records = dev.take_records();
        assert_eq!(
            records.len() as u32,
            s.width * s.height,
            "a whole frame after RESET"
        );
        assert!(records.iter().all(|r| !r.aovs), "AOVS was clear");
    });
}

#[test]
fn what_the_map_does_not_allow_answers_slverr() {
    let waves = Waves::new("device::what_the_map_does_not_allow_answers_slverr");
    let mut dev = Device::new(Jitter {
        seed: 11,
        max_delay: 2,
        mem_busy_percent: 0,
    })
    .expect("Verilated rt_device");
    // one case: accesses only, and two refused starts
    waves.before("all", &mut dev);
    waves.case("all", || {
        let past_image = axi_lite::SCENE_BASE + 4 * axi_lite::SCENE_WORDS as u32;
        let reads = [
            (0x14, "the reserved word after NUMERIC"),
            (0x1C, "the reserved word after AOVS"),
            (past_image, "the scene window past the image"),
            (sys::RESET, "RESET (write only)"),
            (sys::RT_CYCLES + 4, "a high word without its low word"),
            (
                axi_lite::raster::CTRL,
                "the raster slave (not on this device)",
            ),
            (
                axi_lite::readback::PAGE + 4,
                "the read-back slave past its registers",
            ),
            (axi_lite::READ_BASE, "the read-back window before any frame"),
            (
                axi_lite::TEXTURE_BASE,
                "the texture window (write only, not on this device)",
            ),
            (0x802, "an unaligned address"),
            (0x1_F000, "nothing at all"),
        ];
        for (addr, what) in reads {
            assert_eq!(
                dev.read(addr),
                Err(AxiError::SlvErr { addr, write: false }),
                "read of {what}"
            );
        }
        let writes = [
            (sys::ID, 1, "ID (read only)"),
            (sys::VERSION, 1, "VERSION (read only)"),
            (sys::RT_CYCLES, 1, "RT_CYCLES (read only)"),
            (axi_lite::counter_addr(0), 1, "a counter (read only)"),
            (past_image, 1, "the scene window past the image"),
            (axi_lite::NUMERIC, 99, "a NUMERIC code no format has"),
            (axi_lite::raster::PUSH_LO, 1, "the raster slave"),
            (axi_lite::readback::LEN, 1, "READ_LEN (read only)"),
            (
                axi_lite::readback::PLANE,
                3,
                "a READ_PLANE code no plane has",
            ),
            (
                axi_lite::readback::FORMAT,
                5,
                "a READ_FORMAT code no format has",
            ),
            (axi_lite::READ_BASE, 1, "the read-back window (read only)"),
            (axi_lite::TEXTURE_BASE, 1, "the texture window"),
            (0x806, 1, "an unaligned address"),
        ];
        for (addr, value, what) in writes {
            assert_eq!(
                dev.write(addr, value),
                Err(AxiError::SlvErr { addr, write: true }),
                "write to {what}"
            );
        }
        assert_eq!(
            dev.write_strobed(axi_lite::GIE, 1, 0x1),
            Err(AxiError::SlvErr {
                addr: axi_lite::GIE,
                write: true
            }),
            "a write with partial strobes"
        );
        assert_eq!(
            dev.read(axi_lite::GIE),
            Ok(0),
            "the partial write changed nothing"
        );

        // starts the core cannot honour: another number format, a scene it does not build
        let mut rng = SmallRng::seed_from_u64(5);
        let s = scene(&mut rng, 0);
        let (words, _) = model(&s);
        load(&mut dev, &words);
        dev.write(axi_lite::NUMERIC, axi_lite::numeric_code(Numeric::F32))
            .expect("NUMERIC F32 is a format");
        assert_eq!(
            dev.write(axi_lite::AP_CTRL, ctrl::AP_START),
            Err(AxiError::SlvErr {
                addr: axi_lite::AP_CTRL,
                write: true
            }),
            "a start in f32"
        );
        dev.write(axi_lite::NUMERIC, axi_lite::numeric_code(Numeric::Q16_16))
            .expect("NUMERIC");
        let spp = axi_lite::scene_word_addr(protocol::scene::hdr::SPP).unwrap_or(0);
        dev.write(spp, 2).expect("spp word");
        assert_eq!(
            dev.write(axi_lite::AP_CTRL, ctrl::AP_START),
            Err(AxiError::SlvErr {
                addr: axi_lite::AP_CTRL,
                write: true
            }),
            "a start with 2 samples per pixel"
        );
        assert_eq!(
            dev.read(spp),
            Ok(2),
            "the scene window reads back what was written"
        );
        assert_eq!(
            dev.read(axi_lite::AP_CTRL),
            Ok(ctrl::AP_IDLE),
            "nothing started"
        );
        dev.idle(2000);
        assert!(
            dev.take_records().is_empty(),
            "no pixel left the refused frames"
        );
    });
}
