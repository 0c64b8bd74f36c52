//! `MmioBus` against a tiny scripted register file: which words each `FpgaBus` call
//! writes and reads at `protocol::axi_lite`'s addresses, and that every wait on the
//! device ends in `MmioError::Stuck` naming the register instead of a hang. (The real
//! model, `sim_target::mmio`, is driven end to end by host-cli's `mmio` tests.)

use std::convert::Infallible;

use firmware::{FpgaBus, MmioBus, MmioError, Registers};
use protocol::axi_lite::{self, ctrl, raster, readback, sys, READ_BASE, READ_WINDOW};
use protocol::frame::{Block, Numeric, PixelFormat, Plane, ReadRequest, Rect, StartFrame};

/// A ray tracer that finishes after `done_after` control reads (never with `None`), and
/// takes ap_start only if `takes_start`; other registers read fixed patterns.
struct Fake {
    writes: Vec<(u32, u32)>,
    done_after: Option<u32>,
    takes_start: bool,
    running: bool,
    ctrl_reads: u32,
    page: u32,
    id: u32,
}

impl Fake {
    fn new() -> Self {
        Self {
            writes: Vec::new(),
            done_after: Some(2),
            takes_start: true,
            running: false,
            ctrl_reads: 0,
            page: 0,
            id: axi_lite::DEVICE_ID,
        }
    }
}

impl Registers for Fake {
    type Error = Infallible;

    fn read(&mut self, addr: u32) -> Result<u32, Infallible> {
        Ok(match addr {
            sys::ID => self.id,
            sys::VERSION => axi_lite::MAP_VERSION,
            axi_lite::AP_CTRL if self.running => {
                self.ctrl_reads += 1;
                if self.done_after.is_some_and(|n| self.ctrl_reads > n) {
                    self.running = false;
                    ctrl::AP_DONE | ctrl::AP_IDLE | ctrl::AP_READY
                } else {
                    ctrl::AP_START
                }
            }
            axi_lite::AP_CTRL => ctrl::AP_IDLE,
            sys::RT_CYCLES => 5,
            a if a == sys::RT_CYCLES + 4 => 1,
            sys::RT_WORK => 7,
            a if (sys::COUNTERS..sys::COUNTERS + 0x100).contains(&a) => {
                let off = a - sys::COUNTERS;
                if off.is_multiple_of(8) {
                    10 + off / 8
                } else {
                    0
                }
            }
            a if (READ_BASE..READ_BASE + READ_WINDOW).contains(&a) => {
                self.page << 16 | (a - READ_BASE)
            }
            _ => 0,
        })
    }

    fn write(&mut self, addr: u32, value: u32) -> Result<(), Infallible> {
        self.writes.push((addr, value));
        match addr {
            axi_lite::AP_CTRL if value & ctrl::AP_START != 0 && self.takes_start => {
                self.running = true;
                self.ctrl_reads = 0;
            }
            readback::PAGE => self.page = value,
            _ => {}
        }
        Ok(())
    }
}

fn frame(id: u32) -> StartFrame {
    StartFrame {
        frame_id: id,
        block: Block::RayTrace,
        numeric: Numeric::Q16_16,
        auto_restart: false,
        aovs: true,
    }
}

fn bus(fake: Fake) -> MmioBus<Fake> {
    let mut bus = MmioBus::new(fake);
    bus.poll_limit = 50;
    bus
}

#[test]
fn probe_checks_id_and_version() {
    assert_eq!(bus(Fake::new()).probe(), Ok(()));
    let mut wrong = Fake::new();
    wrong.id = 0xDEAD_BEEF;
    let err = bus(wrong).probe().expect_err("not our device");
    assert!(matches!(
        err,
        MmioError::Identity {
            id: 0xDEAD_BEEF,
            ..
        }
    ));
    assert!(err.to_string().contains("no fpgfx device"), "{err}");
}

#[test]
fn a_frame_is_its_scene_words_then_the_start_then_polls() {
    let mut b = bus(Fake::new());
    b.write_regs(4, &[64, 36]).expect("regs");
    b.start(&frame(9)).expect("start");
    let mut polls = 0;
    let done = loop {
        if let Some(d) = b.poll_done().expect("poll") {
            break d;
        }
        polls += 1;
    };
    assert_eq!((done.frame_id, done.cycles, done.work), (9, 1 << 32 | 5, 7));
    assert_eq!(polls, 1, "one poll after the start's own read, then done");
    let writes = &b.registers().writes;
    let mut want = vec![(0x810, 64), (0x814, 36)];
    want.extend(axi_lite::start_writes(&frame(9)));
    assert_eq!(writes, &want);
    assert_eq!(b.poll_done(), Ok(None), "nothing runs");
    // Per frame: the scene words and 3 writes; reads: the start's check, the polls, and
    // two 64-bit results.
    assert_eq!(b.accesses().writes, 2 + 3);
    assert_eq!(b.accesses().reads, 1 + 2 + 4);
}

#[test]
fn a_block_that_never_finishes_is_stuck_on_ap_ctrl() {
    let mut fake = Fake::new();
    fake.done_after = None;
    let mut b = bus(fake);
    b.start(&frame(1)).expect("start");
    let err = (0..1000)
        .find_map(|_| b.poll_done().err())
        .expect("gives up within the bound");
    assert_eq!(
        err.to_string(),
        "AP_CTRL (0x0000): ap_done not seen after 50 polls"
    );
}

#[test]
fn a_block_that_never_takes_ap_start_is_stuck() {
    let mut fake = Fake::new();
    fake.takes_start = false;
    let err = bus(fake).start(&frame(1)).expect_err("never taken");
    assert!(
        matches!(
            err,
            MmioError::Stuck {
                register: "AP_CTRL",
                polls: 50,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("ap_start taken"), "{err}");
}

#[test]
fn a_packet_is_its_records_then_the_commit() {
    let mut b = bus(Fake::new());
    b.push_packet(3, &[0x1_2345_6789, 0xA]).expect("push");
    assert_eq!(
        b.registers().writes,
        vec![
            (raster::PUSH_LO, 0x2345_6789),
            (raster::PUSH_HI, 1),
            (raster::PUSH_LO, 0xA),
            (raster::PUSH_HI, 0),
            (raster::COMMIT, 3),
        ]
    );
    // The FIFO never frees (the fake reads 0): the wait gives up, naming FIFO_FREE.
    assert_eq!(b.fifo_free(), Ok(0));
    let err = (0..100).find_map(|_| b.wait().err()).expect("bounded");
    assert!(err.to_string().starts_with("FIFO_FREE (0x2004)"), "{err}");
}

#[test]
fn a_read_back_pages_through_the_window() {
    let mut b = bus(Fake::new());
    let req = ReadRequest {
        plane: Plane::Color,
        rect: Rect {
            x: 0,
            y: 0,
            w: 64,
            h: 64,
        },
        format: PixelFormat::Rgb888,
    };
    let mut out = [0u8; 6];
    // Bytes 0x3FFD..0x4003: the last three of page 0, the first three of page 1.
    b.read(&req, READ_WINDOW - 3, &mut out).expect("read");
    let last = (READ_WINDOW - 4).to_le_bytes();
    let first = (1u32 << 16).to_le_bytes();
    assert_eq!(
        out,
        [last[1], last[2], last[3], first[0], first[1], first[2]]
    );
    let w = &b.registers().writes;
    assert_eq!(
        w.len(),
        4 + 2,
        "the request once, then a page write per page"
    );
    assert_eq!(&w[4..], &[(readback::PAGE, 0), (readback::PAGE, 1)]);
    // The same request again needs no register writes.
    b.read(&req, 0, &mut out[..2]).expect("read");
    assert_eq!(b.registers().writes.len(), 7, "only the page changes");
}

#[test]
fn counters_are_read_from_the_table() {
    let mut b = bus(Fake::new());
    let c = b.counters().expect("counters");
    assert_eq!((c.fragments, c.cycles, c.frames), (10, 11, 12));
    assert_eq!(b.accesses().reads, 2 * axi_lite::COUNTERS.len() as u64);
}
