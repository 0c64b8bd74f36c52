//! The C shim's API (csrc/shim.cpp), or, when build.rs could not Verilate the RTL, stubs
//! whose constructor says why. Everything unsafe in the crate is here.

use std::ptr::NonNull;

use crate::RtlError;

// Input bits of one cycle and output bits after it, as csrc/shim.cpp defines them.
pub(crate) const IN_RST: u32 = 1 << 0;
pub(crate) const IN_SCK: u32 = 1 << 1;
pub(crate) const IN_CS_N: u32 = 1 << 2;
pub(crate) const IN_MOSI: u32 = 1 << 3;
pub(crate) const IN_MEM_WAIT: u32 = 1 << 4;
pub(crate) const IN_CLOCK_GATED: u32 = 1 << 5;
pub(crate) const OUT_MISO: u32 = 1 << 0;
pub(crate) const OUT_FIFO_FREE: u32 = 1 << 1;
pub(crate) const OUT_BUSY: u32 = 1 << 2;

/// The shim's model: opaque to Rust.
#[repr(C)]
pub(crate) struct FitkitRtl {
    _private: [u8; 0],
}

#[cfg(verilated)]
mod sys {
    use super::FitkitRtl;

    extern "C" {
        pub fn fitkit_rtl_new(no_ram: *mut i32, seed: u64, build: u32) -> *mut FitkitRtl;
        pub fn fitkit_rtl_trace(m: *mut FitkitRtl, path: *const std::ffi::c_char) -> i32;
        pub fn fitkit_rtl_free(m: *mut FitkitRtl);
        pub fn fitkit_rtl_tick(m: *mut FitkitRtl, inputs: u32) -> u32;
        pub fn fitkit_rtl_ram(m: *const FitkitRtl, len: *mut usize) -> *const u8;
    }
}

#[cfg(verilated)]
/// `build`: the index of one of [`crate::Build::ALL`] (the shim returns null for others).
pub(crate) fn new(seed: u64, build: u32) -> Result<NonNull<FitkitRtl>, RtlError> {
    let mut no_ram = 0i32;
    // SAFETY: the shim writes `no_ram` and returns a fresh model or null.
    let p = unsafe { sys::fitkit_rtl_new(&mut no_ram, seed, build) };
    match NonNull::new(p) {
        Some(m) => Ok(m),
        None if no_ram != 0 => Err(RtlError::NoRam),
        None => Err(RtlError::Construct),
    }
}

#[cfg(verilated)]
pub(crate) fn trace(m: NonNull<FitkitRtl>, path: &std::ffi::CStr) -> bool {
    // SAFETY: `m` is live; the shim copies the path before returning.
    unsafe { sys::fitkit_rtl_trace(m.as_ptr(), path.as_ptr()) != 0 }
}

#[cfg(verilated)]
pub(crate) fn free(m: NonNull<FitkitRtl>) {
    // SAFETY: `m` came from `new` and is freed once, by `Rtl`'s drop.
    unsafe { sys::fitkit_rtl_free(m.as_ptr()) }
}

#[cfg(verilated)]
pub(crate) fn tick(m: NonNull<FitkitRtl>, inputs: u32) -> u32 {
    // SAFETY: `m` is live (owned by the calling `Rtl`, which is not Send).
    unsafe { sys::fitkit_rtl_tick(m.as_ptr(), inputs) }
}

#[cfg(verilated)]
pub(crate) fn ram<'a>(m: NonNull<FitkitRtl>) -> &'a [u8] {
    let mut len = 0usize;
    // SAFETY: the RAM array lives as long as the model; the caller ties the slice to a
    // borrow of the `Rtl` that owns it, and nothing writes the RAM while it is borrowed
    // (ticking needs `&mut Rtl`).
    unsafe {
        let p = sys::fitkit_rtl_ram(m.as_ptr(), &mut len);
        std::slice::from_raw_parts(p, len)
    }
}

#[cfg(not(verilated))]
pub(crate) fn new(_: u64, _: u32) -> Result<NonNull<FitkitRtl>, RtlError> {
    match env!("VERILATED_MISSING") {
        "verilator" => Err(RtlError::NoVerilator),
        _ => Err(RtlError::NoRtl),
    }
}

// Without a model no `Rtl` is ever constructed, so these are never called.
#[cfg(not(verilated))]
pub(crate) fn free(_: NonNull<FitkitRtl>) {}

#[cfg(not(verilated))]
pub(crate) fn trace(_: NonNull<FitkitRtl>, _: &std::ffi::CStr) -> bool {
    false
}

#[cfg(not(verilated))]
pub(crate) fn tick(_: NonNull<FitkitRtl>, _: u32) -> u32 {
    0
}

#[cfg(not(verilated))]
pub(crate) fn ram<'a>(_: NonNull<FitkitRtl>) -> &'a [u8] {
    &[]
}
