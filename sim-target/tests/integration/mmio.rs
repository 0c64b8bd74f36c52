//! The register-file model (`sim_target::mmio`) word by word: the HLS control semantics
//! a driver relies on (ap_start held to the handshake, ap_done and ap_ready clear on
//! read, ISR toggle on write, auto-restart, done after N polls) and every refusal,
//! each naming its register.

use protocol::axi_lite::{self, ctrl, irq, raster, readback, sys, Location};
use protocol::frame::{PixelFormat, Plane, ReadRequest, Rect};
use sim_target::mmio::{RegisterError, RegisterFile, DONE_AFTER_POLLS};
use sim_target::Device;

fn model() -> RegisterFile {
    RegisterFile::new(Device::new(&protocol::bus::WIDE))
}

/// The reference scene at 8×6, written through the scene window.
fn with_scene() -> RegisterFile {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/reference.toml");
    let text = std::fs::read_to_string(path).expect("reference scene");
    let mut scene = jobs::scene::parse(&text, "reference.toml").expect("parses");
    scene.width = 8;
    scene.height = 6;
    let regs = jobs::scene::to_regs(&scene).expect("fits");
    let mut m = model();
    for (i, w) in regs.words().enumerate() {
        let addr = axi_lite::scene_word_addr(i).expect("in the image");
        m.write(addr, w).expect("scene word");
    }
    m
}

fn ok(m: &mut RegisterFile, addr: u32) -> u32 {
    m.read(addr)
        .unwrap_or_else(|e| panic!("read {addr:#x}: {e}"))
}

fn ctrl_word(m: &mut RegisterFile) -> u32 {
    ok(m, axi_lite::AP_CTRL)
}

#[test]
fn ap_done_rises_after_the_polls_and_clears_on_read() {
    let mut m = with_scene();
    assert_eq!(ctrl_word(&mut m), ctrl::AP_IDLE);
    m.write(axi_lite::IER, irq::DONE).expect("IER");
    m.write(axi_lite::GIE, 1).expect("GIE");
    m.write(axi_lite::AP_CTRL, ctrl::AP_START).expect("start");
    for poll in 1..=DONE_AFTER_POLLS {
        assert_eq!(ctrl_word(&mut m), ctrl::AP_START, "poll {poll}: running");
        assert!(!m.interrupt());
    }
    assert_eq!(
        ctrl_word(&mut m),
        ctrl::AP_DONE | ctrl::AP_IDLE | ctrl::AP_READY,
        "done: ap_start taken, done and ready up"
    );
    assert_eq!(
        ctrl_word(&mut m),
        ctrl::AP_IDLE,
        "done and ready clear on read"
    );
    assert_eq!(ok(&mut m, axi_lite::ISR), irq::DONE, "only enabled events");
    assert!(m.interrupt());
    m.write(axi_lite::ISR, irq::DONE).expect("toggle");
    assert_eq!(ok(&mut m, axi_lite::ISR), 0);
    assert!(!m.interrupt());
    // The frame's results and the counters, 64-bit, low word first.
    let rays = ok(&mut m, sys::RT_WORK);
    assert_eq!(ok(&mut m, sys::RT_WORK + 4), 0);
    assert!(rays >= 48, "at least a ray per pixel: {rays}");
    let frames = axi_lite::COUNTERS
        .iter()
        .position(|c| c.name == "frames")
        .expect("a frames counter");
    assert_eq!(ok(&mut m, axi_lite::counter_addr(frames)), 1);
    // The frame reads back.
    for (addr, v) in axi_lite::read_request_writes(&ReadRequest {
        plane: Plane::Color,
        rect: Rect {
            x: 0,
            y: 0,
            w: 8,
            h: 6,
        },
        format: PixelFormat::Rgb888,
    }) {
        m.write(addr, v).expect("read-back request");
    }
    assert_eq!(ok(&mut m, readback::LEN), 8 * 6 * 3);
    ok(&mut m, axi_lite::READ_BASE + 140);
    let err = m
        .read(axi_lite::READ_BASE + 144)
        .expect_err("past the frame");
    assert!(
        matches!(err, RegisterError::PastReadBack { len: 144, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("READ_WINDOW"), "{err}");
}

#[test]
fn auto_restart_runs_until_cleared() {
    let mut m = with_scene();
    m.set_done_after(0);
    m.write(axi_lite::AP_CTRL, ctrl::AP_START | ctrl::AUTO_RESTART)
        .expect("start");
    for _ in 0..3 {
        let w = ctrl_word(&mut m);
        assert_eq!(
            w,
            ctrl::AP_START | ctrl::AP_DONE | ctrl::AP_READY | ctrl::AUTO_RESTART,
            "done, and running again at once: {w:#x}"
        );
    }
    // A write without ap_start only clears auto_restart: the running frame ends.
    m.write(axi_lite::AP_CTRL, 0).expect("stop");
    assert_eq!(
        ctrl_word(&mut m),
        ctrl::AP_DONE | ctrl::AP_READY | ctrl::AP_IDLE
    );
    assert_eq!(ctrl_word(&mut m), ctrl::AP_IDLE);
    assert_eq!(ok(&mut m, axi_lite::counter_addr(2)), 4, "four frames ran");
}

#[test]
fn bad_accesses_name_their_register() {
    let mut m = with_scene();
    let msg = |r: Result<u32, RegisterError>| r.expect_err("refused").to_string();
    let wmsg = |r: Result<(), RegisterError>| r.expect_err("refused").to_string();

    assert!(wmsg(m.write(0x14, 1)).contains("0x14: outside the AXI4-Lite map"));
    assert!(msg(m.read(0x802)).contains("outside"), "unaligned");
    assert!(
        msg(m.read(0x800 + 4 * 494)).contains("outside"),
        "past the image"
    );
    assert!(msg(m.read(0x20_0000)).contains("outside"));
    assert!(wmsg(m.write(sys::ID, 0)).contains("write to ID (0x1000), which is read-only"));
    assert!(wmsg(m.write(axi_lite::READ_BASE, 0)).contains("READ_WINDOW byte 0"));
    assert!(msg(m.read(raster::PUSH_LO)).contains("read of PUSH_LO (0x2010), which is write-only"));
    assert!(msg(m.read(axi_lite::TEXTURE_BASE)).contains("texel 0"));
    let e = wmsg(m.write(axi_lite::NUMERIC, 7));
    assert!(
        e.contains("NUMERIC = 0x7") && e.contains("no number format"),
        "{e}"
    );
    let e = wmsg(m.write(readback::FORMAT, 9));
    assert!(
        e.contains("READ_FORMAT = 0x9: unsupported value format"),
        "{e}"
    );
    assert!(wmsg(m.write(readback::PLANE, 3)).contains("READ_PLANE"));
    assert!(wmsg(m.write(raster::AA, 0x40_0000)).contains("RASTER_AA"));
    assert!(wmsg(m.write(raster::MODE, 9 << 8)).contains("RASTER_MODE"));
    let e = msg(m.read(sys::RT_CYCLES + 4));
    assert!(e.contains("RT_CYCLES_HI read without its low word"), "{e}");
    let e = msg(m.read(axi_lite::counter_addr(0) + 4));
    assert!(e.contains("COUNTER[fragments]_HI"), "{e}");

    m.write(axi_lite::AP_CTRL, ctrl::AP_START).expect("start");
    let e = wmsg(m.write(axi_lite::AP_CTRL, ctrl::AP_START));
    assert!(
        e.contains("ap_start written to AP_CTRL while the ray tracer is still running"),
        "{e}"
    );
    let e = msg(m.read(readback::LEN));
    assert!(
        e.contains("READ_LEN read while the ray tracer is still running"),
        "{e}"
    );
    let e = msg(m.read(axi_lite::READ_BASE));
    assert!(e.contains("READ_WINDOW read while the ray tracer"), "{e}");
}

#[test]
fn packets_are_staged_whole_and_bounded() {
    let mut m = model();
    for _ in 0..protocol::bus::MAX_RECORDS {
        m.write(raster::PUSH_LO, 1).expect("lo");
        m.write(raster::PUSH_HI, 0).expect("hi");
    }
    let e = m
        .write(raster::PUSH_HI, 0)
        .expect_err("one record too many");
    assert!(
        e.to_string()
            .contains("PUSH_HI: more than 24 records staged"),
        "{e}"
    );
    assert!(m.write(raster::COMMIT, 256).is_err(), "a channel is a byte");
    let free = ok(&mut m, raster::FIFO_FREE) as usize;
    m.write(raster::COMMIT, 0)
        .expect("the staged packet is still there");
    // Nothing reads FIFO_FREE now, so nothing drains: commits fill the FIFO until one is
    // refused for the space it needs.
    let mut pushed = protocol::bus::MAX_RECORDS;
    let err = loop {
        for _ in 0..protocol::bus::MAX_RECORDS {
            m.write(raster::PUSH_LO, 1).expect("lo");
            m.write(raster::PUSH_HI, 0).expect("hi");
        }
        match m.write(raster::COMMIT, 0) {
            Ok(()) => pushed += protocol::bus::MAX_RECORDS,
            Err(e) => break e,
        }
        assert!(pushed <= free, "the FIFO took more than it has");
    };
    let e = err.to_string();
    assert!(
        e.starts_with("COMMIT: input FIFO overrun: 24 records pushed with"),
        "{e}"
    );
}

#[test]
fn reset_returns_to_power_on() {
    let mut m = with_scene();
    m.write(axi_lite::AOVS, 1).expect("aovs");
    m.write(raster::SIZE, axi_lite::pair16(4, 4)).expect("size");
    m.write(axi_lite::AP_CTRL, ctrl::AP_START).expect("start");
    m.write(sys::RESET, 1).expect("reset");
    assert_eq!(ctrl_word(&mut m), ctrl::AP_IDLE);
    assert_eq!(ok(&mut m, axi_lite::AOVS), 0);
    assert_eq!(ok(&mut m, raster::SIZE), 0);
    assert_eq!(ok(&mut m, sys::ID), axi_lite::DEVICE_ID);
    assert_eq!(ok(&mut m, axi_lite::counter_addr(2)), 0, "no frames");
    assert_eq!(
        axi_lite::locate(sys::RESET).map(|l| l.access()),
        Some(axi_lite::Access::Write)
    );
    assert!(matches!(
        axi_lite::locate(0x1110),
        Some(Location::Counter {
            index: 2,
            high: false
        })
    ));
}

/// Every register of the map's table is served by the model as its access says.
#[test]
fn the_model_serves_every_register_of_the_table() {
    for r in axi_lite::REGISTERS {
        let mut m = model();
        if r.access.readable() && !r.name.ends_with("_HI") {
            assert!(m.read(r.addr).is_ok(), "{}", r.name);
        }
        if r.access.writable() {
            let e = m.write(r.addr, 0).err();
            assert!(
                !matches!(e, Some(RegisterError::Unmapped { .. })),
                "{}: {e:?}",
                r.name
            );
        }
    }
}
