//! The ray tracer's AXI4-Lite slave: where each register the controller writes sits on the
//! bus, laid out the way Vivado HLS lays out an `s_axilite` block such as seed 002's
//! ViRAY.
//!
//! [`crate::scene`] says what the words of the register image mean; this module says
//! where they go: a register-bus driver writes [`write_sequence`] and nothing else, and a
//! testbench replaying the same writes against an HLS-generated block sees the same
//! addresses. It is the one home of the map; the firmware's driver, `fpgfx vectors render`
//! and the C library's header all take their addresses from here.
//!
//! # Address map (byte addresses, 12 address bits)
//!
//! | address | register | bits |
//! |---|---|---|
//! | `0x00` | [`AP_CTRL`] | 0 `ap_start` (R/W, cleared by the handshake), 1 `ap_done` (R, clear on read), 2 `ap_idle` (R), 3 `ap_ready` (R, clear on read), 7 `auto_restart` (R/W) |
//! | `0x04` | [`GIE`] | 0 global interrupt enable |
//! | `0x08` | [`IER`] | 0 `ap_done`, 1 `ap_ready` interrupt enable |
//! | `0x0C` | [`ISR`] | 0 `ap_done`, 1 `ap_ready` status (toggle on write) |
//! | `0x10` | [`NUMERIC`] | number format, [`numeric_code`] (`0x14` reserved) |
//! | `0x18` | [`AOVS`] | bit 0: also write the depth and normal planes (`0x1C` reserved) |
//! | `0x800`–`0xFFF` | [`SCENE_BASE`] | the scene register image, word `i` at `0x800 + 4·i` ([`SCENE_WORDS`] words) |
//!
//! Why these places: HLS puts the block-level control registers at `0x00`–`0x0C`, then
//! every scalar argument from `0x10` in declaration order, 8 bytes apart for a 32-bit one
//! (a data word and a reserved word that would hold a 64-bit argument's high half, or an
//! output's valid bit). An array argument becomes a memory in the bundle with a window of
//! the next power of two at or above its byte size, aligned to that size, so that the
//! slave decodes it by a bit test on the high address bits: 494 words are 1976 bytes, a
//! 2 KiB window, and the first 2 KiB-aligned address after the scalars is `0x800`. (A
//! 10-word array would get a 64-byte window at `0x40`, the smallest aligned place past
//! the control registers.)
//!
//! The start parameters of [`StartFrame`] map as follows: `numeric` and `aovs` are the
//! scalars above, `auto_restart` is `AP_CTRL` bit 7 written with `ap_start`. The frame
//! size is not a start parameter on this block: it is in the scene image
//! ([`crate::scene::hdr::WIDTH`], [`crate::scene::hdr::HEIGHT`]), so it is written with
//! the scene. `frame_id` stays with the controller, which tags the `FrameDone` it sends
//! when `ap_done` rises, and `block` chose this bus in the first place.
//!
//! Interrupts ([`GIE`], [`IER`], [`ISR`]) are the driver's choice between polling
//! `ap_done` and waiting for the interrupt line, so [`write_sequence`] leaves them alone.
//!
//! # The whole device
//!
//! A soft core beside ViRAY-style IP (a MicroBlaze, a RISC-V) drives everything the
//! controller's `FpgaBus` needs over the same AXI4-Lite interconnect, so the rest of the
//! device sits beside the ray tracer as further slaves, each in its own 4 KiB
//! ([`SLAVE_SPAN`], the smallest range Vivado's address editor assigns) or, for a memory,
//! in a power-of-two window aligned to its size, the way HLS places one. Every access is
//! one aligned 32-bit word; anything not listed here is outside the map.
//!
//! | address | register | access | meaning |
//! |---|---|---|---|
//! | `0x0000`–`0x0FFF` | the ray tracer, above | | |
//! | `0x1000` | [`sys::ID`] | R | [`DEVICE_ID`], "FPGX": a driver checks it before anything else |
//! | `0x1004` | [`sys::VERSION`] | R | [`MAP_VERSION`], bumped on any change of this map |
//! | `0x1008` | [`sys::RESET`] | W | any value: back to the power-on state |
//! | `0x1010`, `0x1014` | [`sys::RT_CYCLES`] lo, hi | R | FPGA cycles of the ray tracer's last frame |
//! | `0x1018`, `0x101C` | [`sys::RT_WORK`] lo, hi | R | rays of the ray tracer's last frame |
//! | `0x1100` + 8·i | [`COUNTERS`]`[i]` lo, hi | R | device counter i (table below) |
//! | `0x2000` | [`raster::CTRL`] | R/W | the raster block's frame: [`ctrl`] bits as at `0x00` |
//! | `0x2004` | [`raster::FIFO_FREE`] | R | records the input FIFO can take |
//! | `0x2008` | [`raster::IDLE`] | R | 1 when every committed record has executed |
//! | `0x2010`, `0x2014` | [`raster::PUSH_LO`], [`raster::PUSH_HI`] | W | a record's low and high word; writing the high word stages the record |
//! | `0x2018` | [`raster::COMMIT`] | W | the channel: the staged records enter the FIFO as one packet |
//! | `0x2020` | [`raster::SIZE`] | R/W | width \| height << 16 |
//! | `0x2024` | [`raster::SUBPIXEL`] | R/W | sub-pixel bits |
//! | `0x2028` | [`raster::BACKGROUND`] | R/W | `0x00RRGGBB` |
//! | `0x202C` | [`raster::AA`] | R/W | [`aa_pattern_code`] \| samples << 8 |
//! | `0x2030` | [`raster::MODE`] | R/W | [`cull_code`] \| [`traversal_code`] << 8 |
//! | `0x2034` | [`raster::SETUP`] | W | any value: apply `0x2020`–`0x2030` and clear the framebuffer |
//! | `0x2040`, `0x2044` | [`raster::CYCLES`] lo, hi | R | FPGA cycles up to the raster frame's end |
//! | `0x2048`, `0x204C` | [`raster::WORK`] lo, hi | R | fragments up to the raster frame's end |
//! | `0x3000` | [`readback::PLANE`] | R/W | [`plane_code`] |
//! | `0x3004` | [`readback::FORMAT`] | R/W | [`format_code`] |
//! | `0x3008` | [`readback::RECT_XY`] | R/W | x \| y << 16 |
//! | `0x300C` | [`readback::RECT_WH`] | R/W | w \| h << 16 |
//! | `0x3010` | [`readback::LEN`] | R | bytes of the read-back, or [`readback::NONE`] |
//! | `0x3014` | [`readback::PAGE`] | R/W | which [`READ_WINDOW`] bytes the window shows |
//! | `0x4000`–`0x7FFF` | [`READ_BASE`] | R | read-back bytes `PAGE·0x4000 + a`, little-endian words |
//! | `0x10_0000`–`0x1F_FFFF` | [`TEXTURE_BASE`] | W | texture memory, texel `i` at `0x10_0000 + 4·i` |
//!
//! Device counters, 64 bits each as a low and a high word ([`COUNTERS`] is the table;
//! adding one is a line there):
//!
//! | i | counter |
//! |---|---|
//! | 0 | fragments written to the framebuffer |
//! | 1 | FPGA cycles spent by the blocks |
//! | 2 | frames completed |
//! | 3 | saturating results of the last ray-traced frame (fixed-point formats) |
//!
//! A 64-bit value is read low word first: that read latches the high word, so a value
//! that changes between the two reads still reads whole; a high word read without its
//! low word just before is refused by the model.
//!
//! The raster block's packet is atomic: records are staged by `PUSH_LO`/`PUSH_HI`
//! and enter the FIFO only at `COMMIT`, so the decoder never sees half a packet, as the
//! FITkit's SPI frames guarantee on that board. A read-back is programmed by its four
//! request registers, sized by `LEN` and then read through the window, a page at a time
//! when it is larger than the window.

use crate::frame::{
    Block, DeviceCounters, Numeric, PixelFormat, Plane, ReadRequest, Rect, StartFrame,
};
use crate::raster::{Aa, AaPattern, Cull, RasterSetup, Rgb, Traversal};
use crate::scene::SceneRegs;

/// Block-level control: `ap_start`, `ap_done`, `ap_idle`, `ap_ready`, `auto_restart`
/// ([`ctrl`] bits).
pub const AP_CTRL: u32 = 0x00;
/// Global interrupt enable: bit 0 gates the block's interrupt line.
pub const GIE: u32 = 0x04;
/// IP interrupt enable: which events ([`irq`] bits) raise the interrupt.
pub const IER: u32 = 0x08;
/// IP interrupt status ([`irq`] bits): set by the event, toggled by writing a 1, which
/// is how an interrupt handler acknowledges it.
pub const ISR: u32 = 0x0C;
/// Scalar argument `numeric`: the number format the frame is computed in, as
/// [`numeric_code`] encodes it. A block synthesised for one format ignores it; the golden
/// model and a multi-format build read it.
pub const NUMERIC: u32 = 0x10;
/// Scalar argument `aovs`: bit 0 set makes the block write its depth and normal planes
/// too ([`StartFrame::aovs`]); they cost memory bandwidth, so a frame asks only when read.
pub const AOVS: u32 = 0x18;

/// Words of the scene register image: the seed's OBJ_NUM = 8 objects and LIGHTS_NUM = 2
/// lights, the capacities the block is built for.
pub const SCENE_WORDS: usize = <SceneRegs>::WORDS;
/// Bytes of the scene memory's address window: the next power of two at or above its
/// size, as HLS sizes a memory in an `s_axilite` bundle.
pub const SCENE_WINDOW: u32 = (SCENE_WORDS * 4).next_power_of_two() as u32;
/// Byte address of scene word 0: the first [`SCENE_WINDOW`]-aligned address after the
/// scalar registers, where HLS places the memory.
pub const SCENE_BASE: u32 = SCENE_WINDOW * (LAST_SCALAR / SCENE_WINDOW + 1);
/// Address bits the slave decodes: enough for the scene window's last byte.
pub const ADDR_BITS: u32 = u32::BITS - (SCENE_BASE + SCENE_WINDOW - 1).leading_zeros();

/// The last byte of the scalar registers (AOVS's reserved word).
const LAST_SCALAR: u32 = AOVS + 7;

/// Bits of [`AP_CTRL`].
pub mod ctrl {
    /// Start a frame (R/W); the block clears it when it takes the start.
    pub const AP_START: u32 = 1 << 0;
    /// The frame finished (read only, clear on read).
    pub const AP_DONE: u32 = 1 << 1;
    /// The block is not running (read only).
    pub const AP_IDLE: u32 = 1 << 2;
    /// The block can take new inputs (read only, clear on read).
    pub const AP_READY: u32 = 1 << 3;
    /// Start again by itself after each frame (R/W): ViRAY's driver auto-restart.
    pub const AUTO_RESTART: u32 = 1 << 7;
}

/// Bits of [`IER`] and [`ISR`].
pub mod irq {
    /// `ap_done`: a frame finished.
    pub const DONE: u32 = 1 << 0;
    /// `ap_ready`: the block took its inputs.
    pub const READY: u32 = 1 << 1;
}

/// The [`NUMERIC`] register's value for `n`: its index in [`Numeric::ALL`], the same
/// numbering as [`crate::frame::NumericSet`]'s bits, so one table serves both.
pub const fn numeric_code(n: Numeric) -> u32 {
    n as u32
}

/// The format a [`NUMERIC`] value names, or `None` for a code no format has.
pub fn numeric_from_code(code: u32) -> Option<Numeric> {
    Numeric::ALL.get(code as usize).copied()
}

/// Byte address of scene register word `index`, or `None` past the image: what a
/// driver forwarding a `RegWrite` run computes per word.
pub const fn scene_word_addr(index: usize) -> Option<u32> {
    if index < SCENE_WORDS {
        Some(SCENE_BASE + 4 * index as u32)
    } else {
        None
    }
}

/// The writes that start a frame with the scene already in place: the scalar
/// parameters, then `AP_CTRL` with `ap_start` (and `auto_restart` if asked). `block` and
/// `frame_id` of `start` are not registers of this block (see the module docs).
pub fn start_writes(start: &StartFrame) -> impl Iterator<Item = (u32, u32)> {
    let restart = if start.auto_restart {
        ctrl::AUTO_RESTART
    } else {
        0
    };
    [
        (NUMERIC, numeric_code(start.numeric)),
        (AOVS, u32::from(start.aovs)),
        (AP_CTRL, ctrl::AP_START | restart),
    ]
    .into_iter()
}

/// Every write of one frame, in bus order: the whole scene image word by word, then
/// [`start_writes`]. The image is written whole because the block keeps no state between
/// frames that a testbench could rely on; a driver that knows what the block holds sends
/// only the changed words ([`crate::scene::diff`]) through [`scene_word_addr`].
pub fn write_sequence<'a>(
    regs: &'a [u32; SCENE_WORDS],
    start: &StartFrame,
) -> impl Iterator<Item = (u32, u32)> + 'a {
    (SCENE_BASE..)
        .step_by(4)
        .zip(regs.iter().copied())
        .chain(start_writes(start))
}

/// Bytes of address space of each register slave beside the ray tracer.
pub const SLAVE_SPAN: u32 = 0x1000;
/// What [`sys::ID`] reads: "FPGX".
pub const DEVICE_ID: u32 = 0x4650_4758;
/// What [`sys::VERSION`] reads: bumped on any change of this map, so that a driver
/// refuses a bitstream laid out for another one instead of writing the wrong registers.
pub const MAP_VERSION: u32 = 1;

/// The system slave: identity, reset, the ray tracer's frame results (the HLS block
/// itself has no output registers for them) and the device counters.
pub mod sys {
    /// First byte of the slave.
    pub const BASE: u32 = super::SLAVE_SPAN;
    /// Reads [`super::DEVICE_ID`].
    pub const ID: u32 = BASE;
    /// Reads [`super::MAP_VERSION`].
    pub const VERSION: u32 = BASE + 0x04;
    /// Any write returns the device to its power-on state.
    pub const RESET: u32 = BASE + 0x08;
    /// Low word of the ray tracer's last frame's cycles (high word at +4).
    pub const RT_CYCLES: u32 = BASE + 0x10;
    /// Low word of the rays the ray tracer's last frame traced (high word at +4).
    pub const RT_WORK: u32 = BASE + 0x18;
    /// Counter 0's low word; counter i at `COUNTERS + 8·i` ([`super::COUNTERS`]).
    pub const COUNTERS: u32 = BASE + 0x100;
}

/// The raster slave: its frame control, the input FIFO and the set-up registers.
pub mod raster {
    /// First byte of the slave.
    pub const BASE: u32 = 2 * super::SLAVE_SPAN;
    /// The raster frame's control word, [`super::ctrl`] bits as the ray tracer's: a
    /// raster frame is the records committed before its start, done once they ran.
    pub const CTRL: u32 = BASE;
    /// Records the input FIFO can take now (the FITkit's FIFO_FREE line).
    pub const FIFO_FREE: u32 = BASE + 0x04;
    /// 1 when every committed record has executed (FIFO empty, pipeline idle).
    pub const IDLE: u32 = BASE + 0x08;
    /// Low word of the record being staged.
    pub const PUSH_LO: u32 = BASE + 0x10;
    /// High word of the record being staged; writing it appends the record to the
    /// staged packet.
    pub const PUSH_HI: u32 = BASE + 0x14;
    /// Writing a channel moves the staged packet into the FIFO, whole, on that channel.
    pub const COMMIT: u32 = BASE + 0x18;
    /// Framebuffer width | height << 16.
    pub const SIZE: u32 = BASE + 0x20;
    /// Fractional bits of the coordinates in the following records.
    pub const SUBPIXEL: u32 = BASE + 0x24;
    /// The background the set-up clears to, `0x00RRGGBB`.
    pub const BACKGROUND: u32 = BASE + 0x28;
    /// Anti-aliasing: [`super::aa_pattern_code`] | samples << 8.
    pub const AA: u32 = BASE + 0x2C;
    /// [`super::cull_code`] | [`super::traversal_code`] << 8.
    pub const MODE: u32 = BASE + 0x30;
    /// Any write applies [`SIZE`] … [`MODE`] once the FIFO has drained and clears the
    /// framebuffer: the set-up is one event, not five.
    pub const SETUP: u32 = BASE + 0x34;
    /// Low word of the cycles up to the last raster frame's end (high word at +4).
    pub const CYCLES: u32 = BASE + 0x40;
    /// Low word of the fragments up to the last raster frame's end (high word at +4).
    pub const WORK: u32 = BASE + 0x48;
}

/// The read-back slave: which buffer, rectangle and format [`READ_BASE`] shows.
pub mod readback {
    /// First byte of the slave.
    pub const BASE: u32 = 3 * super::SLAVE_SPAN;
    /// The buffer, [`super::plane_code`].
    pub const PLANE: u32 = BASE;
    /// The byte layout, [`super::format_code`].
    pub const FORMAT: u32 = BASE + 0x04;
    /// The rectangle's x | y << 16.
    pub const RECT_XY: u32 = BASE + 0x08;
    /// The rectangle's w | h << 16.
    pub const RECT_WH: u32 = BASE + 0x0C;
    /// Bytes of the read-back the four registers above describe, or [`NONE`].
    pub const LEN: u32 = BASE + 0x10;
    /// Which [`super::READ_WINDOW`]-byte page of the read-back the window shows.
    pub const PAGE: u32 = BASE + 0x14;
    /// What [`LEN`] reads when the device has no such buffer, rectangle or format.
    pub const NONE: u32 = u32::MAX;
}

/// Bytes of the read-back window: a power of two, so a page is a shift.
pub const READ_WINDOW: u32 = 0x4000;
/// Byte address of the read-back window: the first [`READ_WINDOW`]-aligned address after
/// the register slaves.
pub const READ_BASE: u32 = READ_WINDOW * ((readback::BASE + SLAVE_SPAN - 1) / READ_WINDOW + 1);
/// Texels (32-bit words) of the texture memory both blocks sample.
pub const TEXTURE_WORDS: u32 = 1 << 18;
/// Bytes of the texture memory's window: its size, a power of two.
pub const TEXTURE_WINDOW: u32 = TEXTURE_WORDS * 4;
/// Byte address of texel 0: the first [`TEXTURE_WINDOW`]-aligned address after the
/// read-back window.
pub const TEXTURE_BASE: u32 = TEXTURE_WINDOW * ((READ_BASE + READ_WINDOW - 1) / TEXTURE_WINDOW + 1);
/// Address bits the device's interconnect decodes: enough for the texture window.
pub const DEVICE_ADDR_BITS: u32 = u32::BITS - (TEXTURE_BASE + TEXTURE_WINDOW - 1).leading_zeros();

/// Who may do what with a register.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Reading only; a write is a driver bug.
    Read,
    /// Writing only (an action or a staging port); a read is a driver bug.
    Write,
    /// Both.
    ReadWrite,
}

impl Access {
    /// Whether a read is allowed.
    pub const fn readable(self) -> bool {
        !matches!(self, Access::Write)
    }

    /// Whether a write is allowed.
    pub const fn writable(self) -> bool {
        !matches!(self, Access::Read)
    }
}

/// One register of the map: its name is what an error about it says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Register {
    /// Byte address.
    pub addr: u32,
    /// The name the docs and error messages use.
    pub name: &'static str,
    /// Who may read or write it.
    pub access: Access,
}

const fn reg(addr: u32, name: &'static str, access: Access) -> Register {
    Register { addr, name, access }
}

/// Every single register of the map (the counters and memory windows are ranges, see
/// [`locate`]): the table a model decodes and checks access with.
pub const REGISTERS: &[Register] = {
    use Access::{Read as R, ReadWrite as RW, Write as W};
    &[
        reg(AP_CTRL, "AP_CTRL", RW),
        reg(GIE, "GIE", RW),
        reg(IER, "IER", RW),
        reg(ISR, "ISR", RW),
        reg(NUMERIC, "NUMERIC", RW),
        reg(AOVS, "AOVS", RW),
        reg(sys::ID, "ID", R),
        reg(sys::VERSION, "VERSION", R),
        reg(sys::RESET, "RESET", W),
        reg(sys::RT_CYCLES, "RT_CYCLES_LO", R),
        reg(sys::RT_CYCLES + 4, "RT_CYCLES_HI", R),
        reg(sys::RT_WORK, "RT_WORK_LO", R),
        reg(sys::RT_WORK + 4, "RT_WORK_HI", R),
        reg(raster::CTRL, "RASTER_CTRL", RW),
        reg(raster::FIFO_FREE, "FIFO_FREE", R),
        reg(raster::IDLE, "RASTER_IDLE", R),
        reg(raster::PUSH_LO, "PUSH_LO", W),
        reg(raster::PUSH_HI, "PUSH_HI", W),
        reg(raster::COMMIT, "COMMIT", W),
        reg(raster::SIZE, "RASTER_SIZE", RW),
        reg(raster::SUBPIXEL, "RASTER_SUBPIXEL", RW),
        reg(raster::BACKGROUND, "RASTER_BACKGROUND", RW),
        reg(raster::AA, "RASTER_AA", RW),
        reg(raster::MODE, "RASTER_MODE", RW),
        reg(raster::SETUP, "RASTER_SETUP", W),
        reg(raster::CYCLES, "RASTER_CYCLES_LO", R),
        reg(raster::CYCLES + 4, "RASTER_CYCLES_HI", R),
        reg(raster::WORK, "RASTER_WORK_LO", R),
        reg(raster::WORK + 4, "RASTER_WORK_HI", R),
        reg(readback::PLANE, "READ_PLANE", RW),
        reg(readback::FORMAT, "READ_FORMAT", RW),
        reg(readback::RECT_XY, "READ_RECT_XY", RW),
        reg(readback::RECT_WH, "READ_RECT_WH", RW),
        reg(readback::LEN, "READ_LEN", R),
        reg(readback::PAGE, "READ_PAGE", RW),
    ]
};

/// A device counter's registers: its name and how it is taken from and put into
/// [`DeviceCounters`], so the model that serves it and the driver that reads it use
/// one table.
#[derive(Clone, Copy)]
pub struct CounterReg {
    /// The name the docs and error messages use.
    pub name: &'static str,
    /// The counter's value in the model's counters.
    pub get: fn(&DeviceCounters) -> u64,
    /// Stores a value read from the registers in the driver's counters.
    pub set: fn(&mut DeviceCounters, u64),
}

impl core::fmt::Debug for CounterReg {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name)
    }
}

/// The FPGA's counters in address order, counter i at [`counter_addr`]`(i)`.
pub const COUNTERS: &[CounterReg] = &[
    CounterReg {
        name: "fragments",
        get: |c| c.fragments,
        set: |c, v| c.fragments = v,
    },
    CounterReg {
        name: "cycles",
        get: |c| c.cycles,
        set: |c, v| c.cycles = v,
    },
    CounterReg {
        name: "frames",
        get: |c| c.frames as u64,
        set: |c, v| c.frames = v as u32,
    },
    CounterReg {
        name: "saturations",
        get: |c| c.saturations,
        set: |c, v| c.saturations = v,
    },
];

/// Byte address of counter `index`'s low word (its high word follows).
pub const fn counter_addr(index: usize) -> u32 {
    sys::COUNTERS + 8 * index as u32
}

/// The registers of one block's frames: where a driver starts one and where it finds
/// what [`crate::frame::FrameDone`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockRegs {
    /// The block, as error messages name it.
    pub name: &'static str,
    /// Its control word ([`ctrl`] bits).
    pub ctrl: u32,
    /// Low word of its last frame's cycles.
    pub cycles: u32,
    /// Low word of its last frame's work (rays or fragments).
    pub work: u32,
}

/// The frame registers of `block`.
pub const fn block_regs(block: Block) -> BlockRegs {
    match block {
        Block::RayTrace => BlockRegs {
            name: "ray tracer",
            ctrl: AP_CTRL,
            cycles: sys::RT_CYCLES,
            work: sys::RT_WORK,
        },
        Block::Raster => BlockRegs {
            name: "raster block",
            ctrl: raster::CTRL,
            cycles: raster::CYCLES,
            work: raster::WORK,
        },
    }
}

/// What an address selects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// One of [`REGISTERS`].
    Register(&'static Register),
    /// A word of counter `index` of [`COUNTERS`].
    Counter {
        /// Index in [`COUNTERS`].
        index: usize,
        /// The high word (else the low one).
        high: bool,
    },
    /// Scene register word `index` ([`SCENE_BASE`]).
    Scene(usize),
    /// The read-back window's word at this byte offset in the window ([`READ_BASE`]).
    ReadBack(u32),
    /// Texel `index` of the texture memory ([`TEXTURE_BASE`]).
    Texture(u32),
}

impl Location {
    /// Who may read or write it.
    pub fn access(&self) -> Access {
        match self {
            Location::Register(r) => r.access,
            Location::Counter { .. } | Location::ReadBack(_) => Access::Read,
            Location::Scene(_) => Access::ReadWrite,
            Location::Texture(_) => Access::Write,
        }
    }
}

impl core::fmt::Display for Location {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Location::Register(r) => f.write_str(r.name),
            Location::Counter { index, high } => {
                let name = COUNTERS.get(*index).map_or("?", |c| c.name);
                let half = if *high { "HI" } else { "LO" };
                write!(f, "COUNTER[{name}]_{half}")
            }
            Location::Scene(i) => write!(f, "scene word {i}"),
            Location::ReadBack(off) => write!(f, "READ_WINDOW byte {off}"),
            Location::Texture(i) => write!(f, "texel {i}"),
        }
    }
}

/// What `addr` selects, or `None` outside the map (unaligned addresses included: every
/// access is a whole word). Scene words past the image are outside too, though inside
/// the window: HLS backs only the array's words.
pub fn locate(addr: u32) -> Option<Location> {
    if !addr.is_multiple_of(4) {
        return None;
    }
    if (SCENE_BASE..SCENE_BASE + SCENE_WINDOW).contains(&addr) {
        let i = ((addr - SCENE_BASE) / 4) as usize;
        return (i < SCENE_WORDS).then_some(Location::Scene(i));
    }
    if (READ_BASE..READ_BASE + READ_WINDOW).contains(&addr) {
        return Some(Location::ReadBack(addr - READ_BASE));
    }
    if (TEXTURE_BASE..TEXTURE_BASE + TEXTURE_WINDOW).contains(&addr) {
        return Some(Location::Texture((addr - TEXTURE_BASE) / 4));
    }
    let counters = sys::COUNTERS..counter_addr(COUNTERS.len());
    if counters.contains(&addr) {
        let off = addr - sys::COUNTERS;
        return Some(Location::Counter {
            index: (off / 8) as usize,
            high: off % 8 == 4,
        });
    }
    REGISTERS
        .iter()
        .find(|r| r.addr == addr)
        .map(Location::Register)
}

/// The name of the register at `addr`, for messages ("?" for an address that is not
/// one of [`REGISTERS`]).
pub fn register_name(addr: u32) -> &'static str {
    match locate(addr) {
        Some(Location::Register(r)) => r.name,
        _ => "?",
    }
}

/// The [`readback::PLANE`] value for `p`.
pub const fn plane_code(p: Plane) -> u32 {
    p as u32
}

/// The plane a [`readback::PLANE`] value names.
pub fn plane_from_code(code: u32) -> Option<Plane> {
    PLANES.get(code as usize).copied()
}

/// Every plane, in [`plane_code`] order.
pub const PLANES: [Plane; 3] = [Plane::Color, Plane::Depth, Plane::Normal];

/// Every read-back format, in [`format_code`] order.
pub const FORMATS: [PixelFormat; 5] = [
    PixelFormat::Rgb888,
    PixelFormat::Rgb332,
    PixelFormat::Kcu116,
    PixelFormat::DepthF32,
    PixelFormat::NormalF32,
];

/// The [`readback::FORMAT`] value for `f`.
pub const fn format_code(f: PixelFormat) -> u32 {
    f as u32
}

/// The format a [`readback::FORMAT`] value names.
pub fn format_from_code(code: u32) -> Option<PixelFormat> {
    FORMATS.get(code as usize).copied()
}

/// The [`raster::AA`] pattern field for `p`.
pub const fn aa_pattern_code(p: AaPattern) -> u32 {
    p as u32
}

/// The pattern a [`raster::AA`] pattern field names.
pub fn aa_pattern_from_code(code: u32) -> Option<AaPattern> {
    AaPattern::ALL.get(code as usize).copied()
}

/// The [`raster::MODE`] cull field for `c`.
pub const fn cull_code(c: Cull) -> u32 {
    c as u32
}

/// The culling a [`raster::MODE`] cull field names.
pub fn cull_from_code(code: u32) -> Option<Cull> {
    Cull::ALL.get(code as usize).copied()
}

/// The [`raster::MODE`] traversal field for `t`: its index in [`Traversal::ALL`].
pub const fn traversal_code(t: Traversal) -> u32 {
    t as u32
}

/// The traversal a [`raster::MODE`] traversal field names.
pub fn traversal_from_code(code: u32) -> Option<Traversal> {
    Traversal::ALL.get(code as usize).copied()
}

/// Two 16-bit fields in one register, `a | b << 16` (sizes, corners).
pub const fn pair16(a: u16, b: u16) -> u32 {
    a as u32 | (b as u32) << 16
}

/// The two fields of a [`pair16`] register.
pub const fn unpair16(v: u32) -> (u16, u16) {
    (v as u16, (v >> 16) as u16)
}

/// The [`raster::AA`] value of `aa`.
pub const fn aa_reg(aa: Aa) -> u32 {
    aa_pattern_code(aa.pattern) | (aa.samples as u32) << 8
}

/// The anti-aliasing a [`raster::AA`] value names, or `None` for an unknown pattern or
/// bits set above the samples.
pub fn aa_from_reg(v: u32) -> Option<Aa> {
    (v >> 16 == 0).then_some(())?;
    Some(Aa {
        pattern: aa_pattern_from_code(v & 0xFF)?,
        samples: (v >> 8) as u8,
    })
}

/// The [`raster::MODE`] value of `cull` and `traversal`.
pub const fn mode_reg(cull: Cull, traversal: Traversal) -> u32 {
    cull_code(cull) | traversal_code(traversal) << 8
}

/// The culling and traversal a [`raster::MODE`] value names.
pub fn mode_from_reg(v: u32) -> Option<(Cull, Traversal)> {
    (v >> 16 == 0).then_some(())?;
    Some((cull_from_code(v & 0xFF)?, traversal_from_code(v >> 8)?))
}

/// The [`raster::BACKGROUND`] value of `c`.
pub const fn rgb_reg(c: Rgb) -> u32 {
    (c.r as u32) << 16 | (c.g as u32) << 8 | c.b as u32
}

/// The colour a [`raster::BACKGROUND`] value holds (bits 24–31 ignored).
pub const fn rgb_from_reg(v: u32) -> Rgb {
    Rgb::new((v >> 16) as u8, (v >> 8) as u8, v as u8)
}

/// The writes that program the raster block with `s`, ending with [`raster::SETUP`]
/// which applies them.
pub fn raster_setup_writes(s: &RasterSetup) -> impl Iterator<Item = (u32, u32)> {
    [
        (raster::SIZE, pair16(s.width, s.height)),
        (raster::SUBPIXEL, u32::from(s.subpixel_bits)),
        (raster::BACKGROUND, rgb_reg(s.background)),
        (raster::AA, aa_reg(s.aa)),
        (raster::MODE, mode_reg(s.cull, s.traversal)),
        (raster::SETUP, 1),
    ]
    .into_iter()
}

/// The writes that select `req` for [`readback::LEN`] and the read-back window.
pub fn read_request_writes(req: &ReadRequest) -> impl Iterator<Item = (u32, u32)> {
    let Rect { x, y, w, h } = req.rect;
    [
        (readback::PLANE, plane_code(req.plane)),
        (readback::FORMAT, format_code(req.format)),
        (readback::RECT_XY, pair16(x, y)),
        (readback::RECT_WH, pair16(w, h)),
    ]
    .into_iter()
}

/// One number of the map's generated Verilog header (`RT_AXI_NAME`): what a testbench in
/// any language needs besides the register table, from one place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MapNumber {
    /// Name after the `RT_AXI_` prefix.
    pub name: &'static str,
    /// The value: an address, a bit number, a count or a code.
    pub value: u32,
    /// One line saying what it is, written above it.
    pub doc: &'static str,
}

const fn number(name: &'static str, value: u32, doc: &'static str) -> MapNumber {
    MapNumber { name, value, doc }
}

const fn bit_of(mask: u32) -> u32 {
    mask.trailing_zeros()
}

/// The map's numbers in the order [`write_verilog_header`] writes them (the plane,
/// format and counter codes follow there, from their own tables), so the Verilog header
/// and the Python package's `fpgfx.axi` constants are both generated from here.
pub const MAP: [MapNumber; 43] = [
    number(
        "ADDR_BITS",
        DEVICE_ADDR_BITS,
        "address bits the device decodes",
    ),
    number("AP_CTRL", AP_CTRL, "block-level control"),
    number("GIE", GIE, "global interrupt enable"),
    number("IER", IER, "interrupt enable"),
    number("ISR", ISR, "interrupt status (toggle on write)"),
    number("NUMERIC", NUMERIC, "scalar: number format code"),
    number("AOVS", AOVS, "scalar: bit 0 writes the AOV planes"),
    number("AP_START", bit_of(ctrl::AP_START), "AP_CTRL bit: ap_start"),
    number(
        "AP_DONE",
        bit_of(ctrl::AP_DONE),
        "AP_CTRL bit: ap_done (clear on read)",
    ),
    number("AP_IDLE", bit_of(ctrl::AP_IDLE), "AP_CTRL bit: ap_idle"),
    number(
        "AP_READY",
        bit_of(ctrl::AP_READY),
        "AP_CTRL bit: ap_ready (clear on read)",
    ),
    number(
        "AUTO_RESTART",
        bit_of(ctrl::AUTO_RESTART),
        "AP_CTRL bit: auto_restart",
    ),
    number("IRQ_DONE", bit_of(irq::DONE), "IER / ISR bit: ap_done"),
    number("IRQ_READY", bit_of(irq::READY), "IER / ISR bit: ap_ready"),
    number("SCENE_BASE", SCENE_BASE, "scene word 0"),
    number("SCENE_WINDOW", SCENE_WINDOW, "bytes of the scene window"),
    number(
        "SCENE_WORDS",
        SCENE_WORDS as u32,
        "words of the scene image",
    ),
    number("SYS_ID", sys::ID, "reads DEVICE_ID"),
    number("SYS_VERSION", sys::VERSION, "reads MAP_VERSION"),
    number("SYS_RESET", sys::RESET, "any write: power-on state"),
    number(
        "SYS_RT_CYCLES",
        sys::RT_CYCLES,
        "last frame's cycles, low word (high at +4)",
    ),
    number(
        "SYS_RT_WORK",
        sys::RT_WORK,
        "last frame's rays, low word (high at +4)",
    ),
    number(
        "SYS_COUNTERS",
        sys::COUNTERS,
        "counter 0's low word; counter i at +8 i",
    ),
    number("COUNTER_COUNT", COUNTERS.len() as u32, "device counters"),
    number("DEVICE_ID", DEVICE_ID, "\"FPGX\""),
    number("MAP_VERSION", MAP_VERSION, "this map's version"),
    number(
        "NUMERIC_Q16_16",
        numeric_code(Numeric::Q16_16),
        "NUMERIC code of Q16.16",
    ),
    number(
        "NUMERIC_CODES",
        Numeric::ALL.len() as u32,
        "NUMERIC codes that name a format",
    ),
    number("READ_PLANE", readback::PLANE, "read-back: plane code"),
    number("READ_FORMAT", readback::FORMAT, "read-back: format code"),
    number("READ_RECT_XY", readback::RECT_XY, "read-back: x | y << 16"),
    number("READ_RECT_WH", readback::RECT_WH, "read-back: w | h << 16"),
    number("READ_LEN", readback::LEN, "read-back: bytes, or READ_NONE"),
    number("READ_PAGE", readback::PAGE, "read-back: the window's page"),
    number("READ_NONE", readback::NONE, "READ_LEN without a read-back"),
    number("READ_SLAVE", readback::BASE, "the read-back slave"),
    number(
        "PLANE_CODES",
        PLANES.len() as u32,
        "READ_PLANE codes that name a plane",
    ),
    number(
        "FORMAT_CODES",
        FORMATS.len() as u32,
        "READ_FORMAT codes that name a format",
    ),
    number("READ_BASE", READ_BASE, "read-back window"),
    number("READ_WINDOW", READ_WINDOW, "bytes of the read-back window"),
    number(
        "RASTER_BASE",
        raster::BASE,
        "the raster slave (not on this device)",
    ),
    number("TEXTURE_BASE", TEXTURE_BASE, "texture window"),
    number("SLAVE_SPAN", SLAVE_SPAN, "bytes of each register slave"),
];

/// Writes `hw/rt-core/rtl/rt_axi_map.vh`, the ray-casting core's AXI4-Lite slave's view
/// of this map: every address, bit and code the slave decodes, so the Verilog never
/// types one the Rust defines. The test `rt_axi_map_header_matches_the_rust_map` fails
/// while the committed header differs (`FPGFX_BLESS=1` rewrites it).
pub fn write_verilog_header(out: &mut impl core::fmt::Write) -> core::fmt::Result {
    writeln!(
        out,
        "// rt_axi_map.vh -- the AXI4-Lite map of the ray-casting core's device."
    )?;
    writeln!(out, "//")?;
    writeln!(
        out,
        "// GENERATED from protocol::axi_lite (protocol/src/axi_lite.rs); do not edit."
    )?;
    writeln!(
        out,
        "// `FPGFX_BLESS=1 cargo test -p protocol --test integration rt_axi_map` rewrites it."
    )?;
    writeln!(out, "`ifndef RT_AXI_MAP_VH")?;
    writeln!(out, "`define RT_AXI_MAP_VH")?;
    for MapNumber {
        name,
        value,
        doc: what,
    } in MAP
    {
        writeln!(out, "// {what}")?;
        // bit numbers and counts in decimal, addresses and words in hex
        if value < 0x100 {
            writeln!(out, "`define RT_AXI_{name} {value}")?;
        } else {
            writeln!(out, "`define RT_AXI_{name} 32'h{value:08x}")?;
        }
    }
    // each plane's and format's code, and each format's bytes per pixel, named after the
    // variant (`DepthF32` as DEPTH_F32)
    for p in PLANES {
        writeln!(out, "// READ_PLANE code")?;
        write!(out, "`define RT_AXI_PLANE_")?;
        screaming(out, format_args!("{p:?}"))?;
        writeln!(out, " {}", plane_code(p))?;
    }
    for f in FORMATS {
        writeln!(out, "// READ_FORMAT code")?;
        write!(out, "`define RT_AXI_FORMAT_")?;
        screaming(out, format_args!("{f:?}"))?;
        writeln!(out, " {}", format_code(f))?;
        writeln!(out, "// bytes per pixel of the format")?;
        write!(out, "`define RT_AXI_BPP_")?;
        screaming(out, format_args!("{f:?}"))?;
        writeln!(out, " {}", f.bytes_per_pixel())?;
    }
    for (i, c) in COUNTERS.iter().enumerate() {
        writeln!(out, "// device counter index: {}", c.name)?;
        write!(out, "`define RT_AXI_COUNTER_")?;
        for ch in c.name.chars() {
            out.write_char(ch.to_ascii_uppercase())?;
        }
        writeln!(out, " {i}")?;
    }
    writeln!(out, "`endif")
}

/// Writes a CamelCase name as SCREAMING_SNAKE_CASE (`DepthF32` as `DEPTH_F32`, `Rgb888`
/// as `RGB888`): a word break where an upper-case letter follows a lower-case one. The
/// header's plane and format names are made by it, and so are the Python package's.
pub fn screaming(
    out: &mut impl core::fmt::Write,
    name: core::fmt::Arguments<'_>,
) -> core::fmt::Result {
    struct Screaming<'a, W> {
        out: &'a mut W,
        lower: bool,
    }
    impl<W: core::fmt::Write> core::fmt::Write for Screaming<'_, W> {
        fn write_str(&mut self, s: &str) -> core::fmt::Result {
            for ch in s.chars() {
                if ch.is_ascii_uppercase() && self.lower {
                    self.out.write_char('_')?;
                }
                self.lower = ch.is_ascii_lowercase();
                self.out.write_char(ch.to_ascii_uppercase())?;
            }
            Ok(())
        }
    }
    core::fmt::write(&mut Screaming { out, lower: false }, name)
}

// The map must stay inside what the slave decodes and the scalars below the memory.
const _: () = assert!(LAST_SCALAR < SCENE_BASE && SCENE_BASE.is_multiple_of(SCENE_WINDOW));
const _: () = assert!(SCENE_WORDS * 4 <= SCENE_WINDOW as usize);
// The other slaves sit after the ray tracer's, below the windows, and the windows do not
// overlap.
const _: () = assert!(SCENE_BASE + SCENE_WINDOW <= sys::BASE);
const _: () = assert!(counter_addr(COUNTERS.len()) <= sys::BASE + SLAVE_SPAN);
const _: () = assert!(readback::BASE + SLAVE_SPAN <= READ_BASE);
const _: () = assert!(READ_BASE.is_multiple_of(READ_WINDOW) && READ_WINDOW.is_power_of_two());
const _: () = assert!(TEXTURE_BASE.is_multiple_of(TEXTURE_WINDOW));
const _: () = assert!(TEXTURE_WINDOW.is_power_of_two() && READ_BASE + READ_WINDOW <= TEXTURE_BASE);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Block;

    fn start(numeric: Numeric, aovs: bool, auto_restart: bool) -> StartFrame {
        StartFrame {
            frame_id: 7,
            block: Block::RayTrace,
            numeric,
            auto_restart,
            aovs,
        }
    }

    #[test]
    fn addresses_are_where_hls_puts_them() {
        assert_eq!((AP_CTRL, GIE, IER, ISR), (0x00, 0x04, 0x08, 0x0C));
        assert_eq!((NUMERIC, AOVS), (0x10, 0x18));
        assert_eq!(SCENE_WORDS, 494);
        assert_eq!(SCENE_WINDOW, 0x800);
        assert_eq!(SCENE_BASE, 0x800);
        assert_eq!(ADDR_BITS, 12);
        assert_eq!(scene_word_addr(0), Some(0x800));
        assert_eq!(scene_word_addr(4), Some(0x810), "WIDTH");
        assert_eq!(scene_word_addr(419), Some(0xE8C));
        assert_eq!(scene_word_addr(494), None);
        assert_eq!(
            (ctrl::AP_START, ctrl::AP_DONE, ctrl::AP_IDLE, ctrl::AP_READY),
            (1, 2, 4, 8)
        );
        assert_eq!(ctrl::AUTO_RESTART, 0x80);
        assert_eq!((irq::DONE, irq::READY), (1, 2));
    }

    #[test]
    fn numeric_codes_follow_the_set_bits() {
        for n in Numeric::ALL {
            assert_eq!(1 << numeric_code(n), u32::from(n.bit()));
            assert_eq!(numeric_from_code(numeric_code(n)), Some(n));
        }
        assert_eq!(numeric_code(Numeric::F32), 1);
        assert_eq!(numeric_code(Numeric::Q16_16), 3);
        assert_eq!(numeric_from_code(7), None);
    }

    #[test]
    fn a_frame_is_the_scene_then_the_parameters_then_ap_start() {
        let mut regs = [0u32; SCENE_WORDS];
        for (i, w) in regs.iter_mut().enumerate() {
            *w = 0x1000 + i as u32;
        }
        let seq: heapless::Vec<(u32, u32), { SCENE_WORDS + 3 }> =
            write_sequence(&regs, &start(Numeric::Q16_16, true, false)).collect();
        assert_eq!(seq.len(), SCENE_WORDS + 3);
        assert_eq!(seq[0], (0x800, 0x1000));
        assert_eq!(seq[1], (0x804, 0x1001));
        assert_eq!(seq[493], (0x800 + 4 * 493, 0x1000 + 493));
        assert_eq!(&seq[494..], &[(0x10, 3), (0x18, 1), (0x00, 0x01)]);
    }

    #[test]
    fn auto_restart_rides_on_the_start_write() {
        let w: heapless::Vec<(u32, u32), 3> =
            start_writes(&start(Numeric::F32, false, true)).collect();
        assert_eq!(&w[..], &[(0x10, 1), (0x18, 0), (0x00, 0x81)]);
    }

    #[test]
    fn the_device_map_is_where_the_table_says() {
        assert_eq!(
            (sys::ID, sys::COUNTERS, raster::CTRL, readback::BASE),
            (0x1000, 0x1100, 0x2000, 0x3000)
        );
        assert_eq!((READ_BASE, READ_WINDOW), (0x4000, 0x4000));
        assert_eq!((TEXTURE_BASE, TEXTURE_WINDOW), (0x10_0000, 0x10_0000));
        assert_eq!(DEVICE_ADDR_BITS, 21);
        assert_eq!(counter_addr(2), 0x1110);
        // Every register decodes to itself, and no two share an address.
        for (i, r) in REGISTERS.iter().enumerate() {
            assert_eq!(locate(r.addr), Some(Location::Register(r)), "{}", r.name);
            assert!(
                REGISTERS[..i].iter().all(|o| o.addr != r.addr),
                "{}",
                r.name
            );
        }
        assert_eq!(locate(0x14), None, "NUMERIC's reserved word");
        assert_eq!(locate(0x801), None, "unaligned");
        assert_eq!(locate(0x800 + 4 * 494), None, "past the scene image");
        assert_eq!(locate(0x804), Some(Location::Scene(1)));
        assert_eq!(
            locate(0x1114),
            Some(Location::Counter {
                index: 2,
                high: true
            })
        );
        assert_eq!(locate(counter_addr(COUNTERS.len())), None);
        assert_eq!(locate(0x4008), Some(Location::ReadBack(8)));
        assert_eq!(locate(0x10_0010), Some(Location::Texture(4)));
        assert_eq!(locate(0x20_0000), None);
        let mut name = heapless::String::<32>::new();
        let _ = core::fmt::write(
            &mut name,
            format_args!(
                "{}",
                Location::Counter {
                    index: 2,
                    high: true
                }
            ),
        );
        assert_eq!(name, "COUNTER[frames]_HI");
    }

    #[test]
    fn codes_round_trip() {
        use crate::frame::{PixelFormat, Plane};
        use crate::raster::{Aa, AaPattern, Cull, Rgb, Traversal};
        for p in [Plane::Color, Plane::Depth, Plane::Normal] {
            assert_eq!(plane_from_code(plane_code(p)), Some(p));
        }
        use PixelFormat::*;
        for f in [Rgb888, Rgb332, Kcu116, DepthF32, NormalF32] {
            assert_eq!(format_from_code(format_code(f)), Some(f));
        }
        assert_eq!(format_from_code(5), Option::None);
        for t in Traversal::ALL {
            for c in Cull::ALL {
                assert_eq!(mode_from_reg(mode_reg(c, t)), Some((c, t)));
            }
        }
        // The codes are the `ALL` tables' indices, which the C library and the raster
        // vectors' set-up file number by too.
        for (i, p) in AaPattern::ALL.into_iter().enumerate() {
            assert_eq!(aa_pattern_code(p), i as u32);
        }
        for (i, c) in Cull::ALL.into_iter().enumerate() {
            assert_eq!(cull_code(c), i as u32);
        }
        for (i, t) in Traversal::ALL.into_iter().enumerate() {
            assert_eq!(traversal_code(t), i as u32);
        }
        for pattern in AaPattern::ALL {
            let aa = Aa {
                pattern,
                samples: 4,
            };
            assert_eq!(aa_from_reg(aa_reg(aa)), Some(aa));
        }
        assert_eq!(aa_from_reg(6), Option::None);
        let c = Rgb::new(0x12, 0x34, 0x56);
        assert_eq!((rgb_reg(c), rgb_from_reg(rgb_reg(c))), (0x123456, c));
        assert_eq!(unpair16(pair16(640, 480)), (640, 480));
    }
}
