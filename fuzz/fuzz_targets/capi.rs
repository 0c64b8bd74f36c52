//! The C library (`libfpgfx`, `capi/include/fpgfx.h`) called through its `extern "C"`
//! entry points as a C testbench calls them: a sequence of calls the input drives, with
//! NULL and misaligned pointers, codes that name nothing, and buffers exactly as long as
//! the header asks or one element shorter or longer. Beyond "never crosses into UB"
//! (ASan watches every buffer, each allocated at exactly its stated length):
//! - every call returns one of the header's seven statuses, never
//!   `FPGFX_INTERNAL_ERROR`; `fpgfx_last_error()` is "" after `FPGFX_OK` and a message
//!   otherwise, naming the argument (`layout`, `setup->cull`, `out_len`, `regs` …);
//! - a NULL or misaligned pointer is `FPGFX_BAD_ARGUMENT`, a length off by one is
//!   `FPGFX_SIZE_MISMATCH`, and neither writes anything;
//! - `fpgfx_raster_new` sets `*out` to a block exactly when it succeeds; a block reads
//!   back the same pixels twice and stays usable after a refused packet;
//! - the comparisons count exactly the pixels some channel of which differs by more than
//!   the tolerance, report the largest difference and the first failing pixel, and a
//!   frame compared with itself (or within 255) passes;
//! - `fpgfx_frame_size` gives a size within 1..=4096 and `fpgfx_render` accepts exactly
//!   the buffers that size asks for (register images from `common::image`, clamped to
//!   8 × 8, 1 spp, so that a frame stays short).
#![no_main]
#![allow(non_camel_case_types)]
use std::ffi::{c_char, CStr};

use fpgfx::compare::fpgfx_compare_result;
use fpgfx::raster::fpgfx_raster_setup;
use fpgfx::render::fpgfx_start;
use libfuzzer_sys::fuzz_target;

mod common;
use common::{Bytes, WORDS};

/// `struct fpgfx_raster` as C sees it: an opaque type behind a pointer.
#[repr(C)]
struct fpgfx_raster {
    _opaque: [u8; 0],
}

// The header's declarations, with the status as the C enum it is (an int).
extern "C" {
    fn fpgfx_last_error() -> *const c_char;
    fn fpgfx_compare_exact(
        expected: *const u8,
        actual: *const u8,
        len: usize,
        width: u32,
        height: u32,
        out: *mut fpgfx_compare_result,
    ) -> u32;
    fn fpgfx_compare_within(
        expected: *const u8,
        actual: *const u8,
        len: usize,
        width: u32,
        height: u32,
        tolerance: u8,
        out: *mut fpgfx_compare_result,
    ) -> u32;
    fn fpgfx_raster_new(
        layout: u32,
        setup: *const fpgfx_raster_setup,
        out: *mut *mut fpgfx_raster,
    ) -> u32;
    fn fpgfx_raster_push(
        raster: *mut fpgfx_raster,
        channel: u8,
        records: *const u64,
        n_records: usize,
    ) -> u32;
    fn fpgfx_raster_read(
        raster: *mut fpgfx_raster,
        format: u32,
        out: *mut u8,
        out_len: usize,
    ) -> u32;
    fn fpgfx_raster_free(raster: *mut fpgfx_raster) -> u32;
    fn fpgfx_frame_size(regs: *const u32, n_regs: usize, width: *mut u32, height: *mut u32) -> u32;
    fn fpgfx_render(
        regs: *const u32,
        n_regs: usize,
        texture: *const u8,
        tex_len: usize,
        start: *const fpgfx_start,
        rgb888_out: *mut u8,
        out_len: usize,
        depth_out: *mut f32,
        depth_len: usize,
        normal_out: *mut f32,
        normal_len: usize,
    ) -> u32;
}

const OK: u32 = 0;
const BAD_ARGUMENT: u32 = 1;
const SIZE_MISMATCH: u32 = 2;
const BAD_REGISTERS: u32 = 3;
const DEVICE_ERROR: u32 = 5;

/// Checks a status against `fpgfx_last_error` and returns it.
fn status(call: &str, s: u32) -> u32 {
    assert!(s <= 6, "{call}: status {s} is not an fpgfx_status");
    // SAFETY: the library promises a NUL-terminated string valid until the next call.
    let msg = unsafe { CStr::from_ptr(fpgfx_last_error()) }
        .to_str()
        .expect("UTF-8");
    assert!(s != 6, "{call}: FPGFX_INTERNAL_ERROR: {msg}");
    if s == OK {
        assert!(msg.is_empty(), "{call}: FPGFX_OK with last error {msg:?}");
    } else {
        assert!(!msg.is_empty(), "{call}: status {s} without a message");
    }
    s
}

fn last_error() -> String {
    // SAFETY: as in `status`.
    unsafe { CStr::from_ptr(fpgfx_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// How a buffer argument is passed: as the header asks, NULL, one element short or long.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Pass {
    Exact,
    Null,
    Short,
    Long,
}

fn pass(b: u8) -> Pass {
    // Mostly exact, so that calls get past their checks.
    match b % 8 {
        0 => Pass::Null,
        1 => Pass::Short,
        2 => Pass::Long,
        _ => Pass::Exact,
    }
}

fn len(p: Pass, n: usize) -> usize {
    match p {
        Pass::Short => n.saturating_sub(1),
        Pass::Long => n + 1,
        _ => n,
    }
}

/// A heap buffer of exactly `n` elements (so that ASan sees one past its end) and the
/// pointer to pass for it.
fn buffer<T: Clone>(p: Pass, n: usize, fill: T) -> (Vec<T>, bool) {
    (vec![fill; len(p, n)], p == Pass::Null)
}

fn ptr_mut<T>(v: &mut [T], null: bool) -> *mut T {
    if null {
        std::ptr::null_mut()
    } else {
        v.as_mut_ptr()
    }
}

fn raster_new(b: &mut Bytes, live: &mut Vec<(*mut fpgfx_raster, usize)>) {
    let layout = u32::from(b.u8() % 4);
    let setup = fpgfx_raster_setup {
        width: u16::from(b.u8() % 10),
        height: u16::from(b.u8() % 10),
        subpixel_bits: b.u8() % 10,
        background: [b.u8(), b.u8(), b.u8()],
        aa_pattern: u32::from(b.u8() % 7),
        aa_samples: b.u8() % 20,
        cull: u32::from(b.u8() % 4),
        traversal: u32::from(b.u8() % 6),
    };
    let how = b.u8();
    let mut out: *mut fpgfx_raster = 0x10 as *mut fpgfx_raster;
    let s = status("fpgfx_raster_new", unsafe {
        fpgfx_raster_new(
            layout,
            if how == 0 { std::ptr::null() } else { &setup },
            if how == 1 {
                std::ptr::null_mut()
            } else {
                &mut out
            },
        )
    });
    let msg = last_error();
    match how {
        0 => {
            assert_eq!(s, BAD_ARGUMENT);
            assert!(out.is_null(), "*out not cleared on failure");
            assert!(msg.contains("setup"), "{msg}");
            return;
        }
        1 => {
            assert_eq!((s, msg.contains("out")), (BAD_ARGUMENT, true), "{msg}");
            return;
        }
        _ => {}
    }
    let codes = [
        (layout > 2, "layout"),
        (setup.aa_pattern > 5, "setup->aa_pattern"),
        (setup.cull > 2, "setup->cull"),
        (setup.traversal > 4, "setup->traversal"),
    ];
    if let Some((_, name)) = codes.iter().find(|(bad, _)| *bad) {
        assert_eq!(s, BAD_ARGUMENT, "{name}");
        assert!(msg.starts_with(name), "{msg}");
    }
    if s == OK {
        assert!(!out.is_null());
        let pixels = usize::from(setup.width) * usize::from(setup.height);
        live.push((out, pixels));
    } else {
        assert!(out.is_null(), "*out not cleared on failure");
        assert!(matches!(s, BAD_ARGUMENT | DEVICE_ERROR), "{s}: {msg}");
    }
}

fn raster_push(b: &mut Bytes, live: &[(*mut fpgfx_raster, usize)]) {
    let pick = b.u8();
    let channel = b.u8() % 6;
    let n = usize::from(b.u8() % 16);
    let records: Vec<u64> = (0..n).map(|_| b.u64()).collect();
    let how = b.u8() % 8;
    let raster = match live.get(usize::from(pick) % (live.len() + 1)) {
        Some(&(r, _)) => r,
        None => std::ptr::null_mut(),
    };
    let rec = if how == 0 {
        std::ptr::null()
    } else {
        records.as_ptr()
    };
    let s = status("fpgfx_raster_push", unsafe {
        fpgfx_raster_push(raster, channel, rec, n)
    });
    let msg = last_error();
    if raster.is_null() {
        assert_eq!(s, BAD_ARGUMENT);
        assert!(msg.starts_with("raster"), "{msg}");
    } else if how == 0 {
        assert_eq!(s, BAD_ARGUMENT);
        assert!(msg.starts_with("records"), "{msg}");
    } else {
        assert!(matches!(s, OK | DEVICE_ERROR | BAD_ARGUMENT), "{s}: {msg}");
    }
}

fn raster_read(b: &mut Bytes, live: &[(*mut fpgfx_raster, usize)]) {
    let Some(&(raster, pixels)) = live.get(usize::from(b.u8()) % live.len().max(1)) else {
        return;
    };
    let format = u32::from(b.u8() % 3);
    let p = pass(b.u8());
    let per = if format == 1 { 1 } else { 3 };
    let (mut out, null) = buffer(p, pixels * per, 0xa5u8);
    let before = out.clone();
    let n = out.len();
    let s = status("fpgfx_raster_read", unsafe {
        fpgfx_raster_read(raster, format, ptr_mut(&mut out, null), n)
    });
    let msg = last_error();
    if format == 2 {
        assert_eq!(s, BAD_ARGUMENT);
        assert!(msg.starts_with("format"), "{msg}");
    } else if n != pixels * per {
        assert_eq!(s, SIZE_MISMATCH);
        assert!(msg.starts_with("out_len"), "{msg}");
    } else if null && n > 0 {
        assert_eq!(s, BAD_ARGUMENT, "{msg}");
        assert!(msg.starts_with("out"), "{msg}");
    } else if null {
        // A 0 × n framebuffer: NULL is still no buffer.
        assert!(matches!(s, OK | BAD_ARGUMENT), "{msg}");
    } else {
        assert_eq!(s, OK, "{msg}");
        let mut again = vec![0x5au8; n];
        let s2 = status("fpgfx_raster_read", unsafe {
            fpgfx_raster_read(raster, format, again.as_mut_ptr(), n)
        });
        assert_eq!(s2, OK);
        assert_eq!(again, out, "two reads differ");
    }
    if s != OK {
        assert_eq!(out, before, "a refused read wrote the buffer");
    }
}

fn compare(b: &mut Bytes) {
    let within = b.u8() & 1 == 1;
    let tolerance = if within { b.u8() } else { 0 };
    let (w, h) = (u32::from(b.u8() % 9), u32::from(b.u8() % 9));
    if b.u8().is_multiple_of(16) {
        // Sizes no buffer can have (their product may overflow): the length cannot match.
        let (w, h) = (b.u32() | 1 << 31, b.u32());
        let buf = b.take(3 * 64).to_vec();
        let mut out = fpgfx_compare_result::default();
        let s = status("fpgfx_compare_exact", unsafe {
            fpgfx_compare_exact(buf.as_ptr(), buf.as_ptr(), buf.len(), w, h, &mut out)
        });
        if h != 0 {
            assert_eq!(s, SIZE_MISMATCH, "{w}x{h}: {}", last_error());
            assert!(last_error().starts_with("len is"), "{}", last_error());
        }
        return;
    }
    let n = w as usize * h as usize * 3;
    let (pe, pa) = (pass(b.u8()), pass(b.u8()));
    let same = b.u8().is_multiple_of(4);
    let src = b.take(2 * n);
    let byte = |i: usize| {
        if src.is_empty() {
            0
        } else {
            src[i % src.len()]
        }
    };
    let (mut e, en) = buffer(pe, n, 0u8);
    let (mut a, an) = buffer(pa, n, 0u8);
    for (i, x) in e.iter_mut().enumerate() {
        *x = byte(i);
    }
    for (i, x) in a.iter_mut().enumerate() {
        *x = if same { byte(i) } else { byte(n + i) };
    }
    // Both buffers are passed with the first one's length, as a C caller with one `len`.
    let len = e.len().min(a.len());
    let mut out = fpgfx_compare_result::default();
    let (ep, ap) = (
        ptr_mut(&mut e, en) as *const u8,
        ptr_mut(&mut a, an) as *const u8,
    );
    let s = status("fpgfx_compare", unsafe {
        if within {
            fpgfx_compare_within(ep, ap, len, w, h, tolerance, &mut out)
        } else {
            fpgfx_compare_exact(ep, ap, len, w, h, &mut out)
        }
    });
    let msg = last_error();
    if en || an {
        assert_eq!(s, BAD_ARGUMENT, "{msg}");
        assert!(
            msg.starts_with(if en { "expected" } else { "actual" }),
            "{msg}"
        );
        return;
    }
    if len != n {
        assert_eq!(s, SIZE_MISMATCH, "{msg}");
        assert!(msg.starts_with("len is"), "{msg}");
        return;
    }
    assert_eq!(s, OK, "{msg}");
    assert_eq!(out.pixels, u64::from(w * h));
    // The count, the largest difference and the first failure, recomputed.
    let (mut failing, mut max, mut first) = (0u64, 0u8, None);
    for (i, (pe, pa)) in e.chunks_exact(3).zip(a.chunks_exact(3)).enumerate() {
        let d = pe
            .iter()
            .zip(pa)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0);
        max = max.max(d);
        if d > tolerance {
            failing += 1;
            first.get_or_insert((i, [pe[0], pe[1], pe[2]], [pa[0], pa[1], pa[2]]));
        }
    }
    assert_eq!(out.failing, failing, "{out:?}");
    assert_eq!(out.max_difference, max, "{out:?}");
    if let Some((i, pe, pa)) = first {
        let i = i as u32;
        assert_eq!((out.first_x, out.first_y), (i % w, i / w), "{out:?}");
        assert_eq!((out.first_expected, out.first_actual), (pe, pa), "{out:?}");
    }
    if same || tolerance == 255 {
        assert_eq!(out.failing, 0);
    }
}

fn render(b: &mut Bytes) {
    let ctl = b.u8();
    let numeric = u32::from(b.u8() % 8);
    let aovs = u32::from(b.u8() % 3);
    let (pr, po, pd, pn) = (pass(b.u8()), pass(b.u8()), b.u8() % 3, b.u8() % 3);
    let misalign = b.u8().is_multiple_of(16);
    let patches = b.take(6 * usize::from(b.0.first().copied().unwrap_or(0) % 8) + 1);
    let mut words = common::image(ctl | 0x80, patches.get(1..).unwrap_or(&[]));
    common::tiny(&mut words);

    // The image in a buffer of exactly its length (or one word short or long), possibly
    // at an address off by one byte.
    let (mut regs, null) = buffer(pr, WORDS, 0u32);
    let k = regs.len().min(WORDS);
    regs[..k].copy_from_slice(&words[..k]);
    // A copy one word longer, to pass an address one byte into it: never aligned for
    // u32, and still inside the allocation for all `regs.len()` words.
    let mut shifted = regs.clone();
    shifted.push(0);
    let regs_ptr = if null {
        std::ptr::null()
    } else if misalign {
        unsafe { (shifted.as_ptr() as *const u8).add(1) as *const u32 }
    } else {
        regs.as_ptr()
    };
    let misaligned = !regs_ptr.is_null() && !(regs_ptr as usize).is_multiple_of(4);

    let (mut w, mut h) = (0u32, 0u32);
    let s = status("fpgfx_frame_size", unsafe {
        fpgfx_frame_size(regs_ptr, regs.len(), &mut w, &mut h)
    });
    let msg = last_error();
    if null || misaligned {
        assert_eq!(s, BAD_ARGUMENT, "{msg}");
        assert!(msg.starts_with("regs"), "{msg}");
        return;
    }
    if regs.len() != WORDS {
        assert_eq!(s, SIZE_MISMATCH, "{msg}");
        assert!(msg.starts_with("n_regs"), "{msg}");
        return;
    }
    if s != OK {
        assert_eq!(s, BAD_REGISTERS, "{msg}");
        assert!(msg.starts_with("regs: "), "{msg}");
        return;
    }
    assert!((1..=8).contains(&w) && (1..=8).contains(&h), "{w}x{h}");
    let pixels = (w * h) as usize;

    let start = fpgfx_start { numeric, aovs };
    let (mut rgb, rgb_null) = buffer(po, pixels * 3, 0u8);
    // Planes: 0 none (NULL, 0), 1 exact, 2 one short.
    let plane = |k: u8, per: usize| -> Vec<f32> {
        match k {
            1 => vec![0.0; pixels * per],
            2 => vec![0.0; pixels * per - 1],
            _ => Vec::new(),
        }
    };
    let (mut depth, mut normal) = (plane(pd, 1), plane(pn, 3));
    let dptr = if pd == 0 {
        std::ptr::null_mut()
    } else {
        depth.as_mut_ptr()
    };
    let nptr = if pn == 0 {
        std::ptr::null_mut()
    } else {
        normal.as_mut_ptr()
    };
    let s = status("fpgfx_render", unsafe {
        fpgfx_render(
            regs_ptr,
            regs.len(),
            std::ptr::null(),
            0,
            &start,
            ptr_mut(&mut rgb, rgb_null),
            rgb.len(),
            dptr,
            depth.len(),
            nptr,
            normal.len(),
        )
    });
    let msg = last_error();
    // The checks in the order the function makes them.
    let expect: Option<(u32, &str)> = if numeric > 6 {
        Some((BAD_ARGUMENT, "start->numeric"))
    } else if aovs > 1 {
        Some((BAD_ARGUMENT, "start->aovs"))
    } else if pd != 0 && aovs == 0 {
        Some((BAD_ARGUMENT, "depth_out"))
    } else if pd == 2 {
        Some((SIZE_MISMATCH, "depth_out"))
    } else if pn != 0 && aovs == 0 {
        Some((BAD_ARGUMENT, "normal_out"))
    } else if pn == 2 {
        Some((SIZE_MISMATCH, "normal_out"))
    } else if rgb.len() != pixels * 3 {
        Some((SIZE_MISMATCH, "out_len"))
    } else if rgb_null {
        Some((BAD_ARGUMENT, "rgb888_out"))
    } else {
        None
    };
    match expect {
        Some((code, name)) => {
            assert_eq!(s, code, "{msg}");
            assert!(msg.starts_with(name), "{name}: {msg}");
        }
        None => assert!(
            s == OK || (s == DEVICE_ERROR && !msg.is_empty()),
            "{s}: {msg}"
        ),
    }
}

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    let mut live = Vec::new();
    // At most 16 calls, 2 of them renders (a render is ~100 times the cost of any other
    // call; more of them made every input slow without reaching new code).
    let (mut calls, mut renders) = (0, 0);
    while !b.is_empty() && calls < 16 {
        calls += 1;
        match b.u8() % 6 {
            0 => raster_new(&mut b, &mut live),
            1 => raster_push(&mut b, &live),
            2 => raster_read(&mut b, &live),
            3 => {
                let i = usize::from(b.u8());
                let r = if live.is_empty() {
                    std::ptr::null_mut()
                } else {
                    live.swap_remove(i % live.len()).0
                };
                assert_eq!(
                    status("fpgfx_raster_free", unsafe { fpgfx_raster_free(r) }),
                    OK
                );
            }
            4 => compare(&mut b),
            _ if renders < 2 => {
                renders += 1;
                render(&mut b)
            }
            _ => {}
        }
    }
    for (r, _) in live {
        assert_eq!(
            status("fpgfx_raster_free", unsafe { fpgfx_raster_free(r) }),
            OK
        );
    }
});
