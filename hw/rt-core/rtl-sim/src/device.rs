//! The Verilated `rt_device`: the core behind its AXI4-Lite slave, driven as a soft core
//! drives it, one 32-bit access at a time, each a real handshake on the RTL's clock,
//! and its memory ports served by a memory that can stall them: the write port's records
//! are kept by index, and the read port (the read-back window's) answers from them.

use std::ptr::NonNull;

use crate::{ffi, RtlError};

/// AXI's SLVERR response code.
const SLVERR: u32 = 0b10;

/// A bus access that did not complete with OKAY.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum AxiError {
    /// The slave answered SLVERR: the address is not on the device, the access goes
    /// against the register's direction, or the register refused the value.
    #[error("{} {addr:#07x}: the slave answered SLVERR", if *.write { "write to" } else { "read of" })]
    SlvErr {
        /// The byte address.
        addr: u32,
        /// A write (else a read).
        write: bool,
    },
    /// A channel's handshake did not happen within the bound.
    #[error("{} {addr:#07x}: no {channel} handshake within {cycles} clocks", if *.write { "write to" } else { "read of" })]
    Stuck {
        /// The byte address.
        addr: u32,
        /// A write (else a read).
        write: bool,
        /// The channel waited on (AW, W, B, AR, R).
        channel: &'static str,
        /// The bound.
        cycles: u64,
    },
}

/// One pixel's record as the memory port gave it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemRecord {
    /// y·W + x.
    pub index: u32,
    /// RGB888, R in bits 23:16.
    pub rgb: u32,
    /// The KCU116 16-bit word.
    pub kcu116: u16,
    /// The nearest object's index, 0xFF for a miss.
    pub obj: u8,
    /// Its distance (Q16.16 bits).
    pub t: i32,
    /// The unit normal (Q16.16 bits).
    pub n: [i32; 3],
    /// Whether the frame asked for the AOV planes.
    pub aovs: bool,
}

/// What memory holds where the write port never wrote (a real memory's old contents).
const BLANK: MemRecord = MemRecord {
    index: 0,
    rgb: 0,
    kcu116: 0,
    obj: 0,
    t: 0,
    n: [0; 3],
    aovs: false,
};

/// How the master and the memory behave: random delays before each channel's VALID and
/// READY, and clocks on which the memory is not ready, from a seeded generator so a
/// failing run repeats.
#[derive(Debug, Clone, Copy)]
pub struct Jitter {
    /// Seed of the generator.
    pub seed: u64,
    /// Largest number of clocks a VALID or READY waits (0: none).
    pub max_delay: u32,
    /// Percent of clocks on which a memory port is not ready.
    pub mem_busy_percent: u32,
}

impl Jitter {
    /// No delays, the memory always ready.
    pub const NONE: Jitter = Jitter {
        seed: 0,
        max_delay: 0,
        mem_busy_percent: 0,
    };
}

/// Clocks a handshake may take before [`AxiError::Stuck`].
pub const HANDSHAKE_BOUND: u64 = 10_000;

/// The Verilated `rt_device` with every shape built, the default object capacity, one
/// point-light lane and shadows.
pub struct Device {
    model: NonNull<ffi::RtDevice>,
    cycle: u64,
    held: u64,
    jitter: Jitter,
    state: u64,
    records: Vec<MemRecord>,
    /// The frame memory by index (a map: a broken index must not allocate gigabytes).
    memory: std::collections::HashMap<u32, MemRecord>,
    /// The read port's answer: the clocks until it is given, and the index read.
    reading: Option<(u32, u32)>,
    irq: bool,
}

// SAFETY: the model is owned by this value alone and only used through `&mut self`.
unsafe impl Send for Device {}

/// The AXI master's pins for one clock.
#[derive(Default, Clone, Copy)]
struct Master {
    aw: Option<u32>,
    w: Option<(u32, u32)>,
    bready: bool,
    ar: Option<u32>,
    rready: bool,
}

/// What the device drives, sampled before the clock edge.
struct Pins([u32; 21]);

impl Pins {
    fn awready(&self) -> bool {
        self.0[0] != 0
    }
    fn wready(&self) -> bool {
        self.0[1] != 0
    }
    fn bvalid(&self) -> bool {
        self.0[2] != 0
    }
    fn bresp(&self) -> u32 {
        self.0[3]
    }
    fn arready(&self) -> bool {
        self.0[4] != 0
    }
    fn rvalid(&self) -> bool {
        self.0[5] != 0
    }
    fn rdata(&self) -> u32 {
        self.0[6]
    }
    fn rresp(&self) -> u32 {
        self.0[7]
    }
}

impl Device {
    /// A fresh device after reset.
    pub fn new(jitter: Jitter) -> Result<Self, RtlError> {
        Ok(Self {
            model: ffi::device_new()?,
            cycle: 0,
            held: 0,
            jitter,
            state: jitter.seed ^ 0x9e37_79b9_7f4a_7c15,
            records: Vec::new(),
            memory: std::collections::HashMap::new(),
            reading: None,
            irq: false,
        })
    }

    /// xorshift64*: enough randomness for delays, without a dependency.
    fn next(&mut self) -> u64 {
        self.state ^= self.state >> 12;
        self.state ^= self.state << 25;
        self.state ^= self.state >> 27;
        self.state.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn delay(&mut self) -> u32 {
        match self.jitter.max_delay {
            0 => 0,
            m => (self.next() % (u64::from(m) + 1)) as u32,
        }
    }

    /// Whether a memory port is busy on this clock ([`Jitter::mem_busy_percent`]).
    fn mem_busy(&mut self) -> bool {
        self.jitter.mem_busy_percent > 0
            && (self.next() % 100) < u64::from(self.jitter.mem_busy_percent)
    }

    /// One clock with the master's pins `m`; the memory's write port takes a waiting
    /// record unless it is busy on this clock, and its read port takes a read likewise
    /// and answers it after up to [`Jitter::max_delay`] more clocks.
    fn clock(&mut self, m: Master) -> Pins {
        let busy = self.mem_busy();
        let rd_busy = self.mem_busy();
        let (awaddr, wdata, wstrb) = (
            m.aw.unwrap_or(0),
            m.w.map_or(0, |w| w.0),
            m.w.map_or(0, |w| w.1),
        );
        let answer = match self.reading {
            Some((0, index)) => {
                self.reading = None;
                Some(self.memory.get(&index).copied().unwrap_or(BLANK))
            }
            Some((n, index)) => {
                self.reading = Some((n - 1, index));
                None
            }
            None => None,
        };
        let r = answer.unwrap_or(BLANK);
        let inputs = [
            u32::from(m.aw.is_some()),
            awaddr,
            u32::from(m.w.is_some()),
            wdata,
            wstrb,
            u32::from(m.bready),
            u32::from(m.ar.is_some()),
            m.ar.unwrap_or(0),
            u32::from(m.rready),
            u32::from(!busy),
            u32::from(!rd_busy && self.reading.is_none()),
            u32::from(answer.is_some()),
            r.rgb,
            u32::from(r.obj),
            r.t as u32,
            r.n[0] as u32,
            r.n[1] as u32,
            r.n[2] as u32,
        ];
        let o = ffi::device_cycle(self.model, &inputs);
        self.cycle += 1;
        self.irq = o[8] != 0;
        if o[9] != 0 {
            if busy {
                self.held += 1;
            } else {
                let rec = MemRecord {
                    index: o[10],
                    rgb: o[11],
                    kcu116: o[12] as u16,
                    obj: o[13] as u8,
                    t: o[14] as i32,
                    n: [o[15] as i32, o[16] as i32, o[17] as i32],
                    aovs: o[18] != 0,
                };
                self.memory.insert(rec.index, rec);
                self.records.push(rec);
            }
        }
        if o[19] != 0 && inputs[10] != 0 {
            let wait = self.delay();
            self.reading = Some((wait, o[20]));
        }
        Pins(o)
    }

    /// `n` clocks with the bus idle.
    pub fn idle(&mut self, n: u64) {
        for _ in 0..n {
            self.clock(Master::default());
        }
    }

    /// Writes `value` to byte address `addr` with full strobes.
    pub fn write(&mut self, addr: u32, value: u32) -> Result<(), AxiError> {
        self.write_strobed(addr, value, 0xF)
    }

    /// Writes with the byte strobes `strb` (the device refuses anything but 0xF).
    pub fn write_strobed(&mut self, addr: u32, value: u32, strb: u32) -> Result<(), AxiError> {
        let (aw_at, w_at, b_at) = (self.delay(), self.delay(), self.delay());
        let stuck = |channel| AxiError::Stuck {
            addr,
            write: true,
            channel,
            cycles: HANDSHAKE_BOUND,
        };
        let (mut aw_done, mut w_done) = (false, false);
        let mut n = 0u32;
        while !(aw_done && w_done) {
            if u64::from(n) > HANDSHAKE_BOUND {
                return Err(stuck(if aw_done { "W" } else { "AW" }));
            }
            let m = Master {
                aw: (!aw_done && n >= aw_at).then_some(addr),
                w: (!w_done && n >= w_at).then_some((value, strb)),
                ..Master::default()
            };
            let p = self.clock(m);
            aw_done |= m.aw.is_some() && p.awready();
            w_done |= m.w.is_some() && p.wready();
            n += 1;
        }
        for k in 0..=HANDSHAKE_BOUND {
            let m = Master {
                bready: k >= u64::from(b_at),
                ..Master::default()
            };
            let p = self.clock(m);
            if m.bready && p.bvalid() {
                return match p.bresp() {
                    SLVERR => Err(AxiError::SlvErr { addr, write: true }),
                    _ => Ok(()),
                };
            }
        }
        Err(stuck("B"))
    }

    /// Reads the word at byte address `addr`.
    pub fn read(&mut self, addr: u32) -> Result<u32, AxiError> {
        let (ar_at, r_at) = (self.delay(), self.delay());
        let stuck = |channel| AxiError::Stuck {
            addr,
            write: false,
            channel,
            cycles: HANDSHAKE_BOUND,
        };
        let mut k = 0u64;
        loop {
            if k > HANDSHAKE_BOUND {
                return Err(stuck("AR"));
            }
            let m = Master {
                ar: (k >= u64::from(ar_at)).then_some(addr),
                ..Master::default()
            };
            k += 1;
            let p = self.clock(m);
            if m.ar.is_some() && p.arready() {
                break;
            }
        }
        for k in 0..=HANDSHAKE_BOUND {
            let m = Master {
                rready: k >= u64::from(r_at),
                ..Master::default()
            };
            let p = self.clock(m);
            if m.rready && p.rvalid() {
                return match p.rresp() {
                    SLVERR => Err(AxiError::SlvErr { addr, write: false }),
                    _ => Ok(p.rdata()),
                };
            }
        }
        Err(stuck("R"))
    }

    /// The records the memory port has given since the last call, in order.
    pub fn take_records(&mut self) -> Vec<MemRecord> {
        std::mem::take(&mut self.records)
    }

    /// Clocks since reset.
    pub fn cycles(&self) -> u64 {
        self.cycle
    }

    /// Starts a VCD of every signal at `path` from the next clock edge on, closed when the
    /// model is dropped (the replay of a failing case); only with the `trace` feature.
    pub fn trace_to(&mut self, path: &std::path::Path) -> Result<(), RtlError> {
        crate::trace(path, |c| ffi::device_trace(self.model, c))
    }

    /// Clocks on which a record waited for the memory (each holds the core one clock).
    pub fn held(&self) -> u64 {
        self.held
    }

    /// The interrupt line as of the last clock.
    pub fn irq(&self) -> bool {
        self.irq
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        ffi::device_free(self.model);
    }
}
