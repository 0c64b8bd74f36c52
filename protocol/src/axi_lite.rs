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
//! slave decodes it by a bit test on the high address bits: 420 words are 1680 bytes, a
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

use crate::frame::{Numeric, StartFrame};
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

// The map must stay inside what the slave decodes and the scalars below the memory.
const _: () = assert!(LAST_SCALAR < SCENE_BASE && SCENE_BASE.is_multiple_of(SCENE_WINDOW));
const _: () = assert!(SCENE_WORDS * 4 <= SCENE_WINDOW as usize);

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
        assert_eq!(SCENE_WORDS, 420);
        assert_eq!(SCENE_WINDOW, 0x800);
        assert_eq!(SCENE_BASE, 0x800);
        assert_eq!(ADDR_BITS, 12);
        assert_eq!(scene_word_addr(0), Some(0x800));
        assert_eq!(scene_word_addr(4), Some(0x810), "WIDTH");
        assert_eq!(scene_word_addr(419), Some(0xE8C));
        assert_eq!(scene_word_addr(420), None);
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
        let seq: heapless::Vec<(u32, u32), 430> =
            write_sequence(&regs, &start(Numeric::Q16_16, true, false)).collect();
        assert_eq!(seq.len(), SCENE_WORDS + 3);
        assert_eq!(seq[0], (0x800, 0x1000));
        assert_eq!(seq[1], (0x804, 0x1001));
        assert_eq!(seq[419], (0xE8C, 0x1000 + 419));
        assert_eq!(&seq[420..], &[(0x10, 3), (0x18, 1), (0x00, 0x01)]);
    }

    #[test]
    fn auto_restart_rides_on_the_start_write() {
        let w: heapless::Vec<(u32, u32), 3> =
            start_writes(&start(Numeric::F32, false, true)).collect();
        assert_eq!(&w[..], &[(0x10, 1), (0x18, 0), (0x00, 0x81)]);
    }
}
