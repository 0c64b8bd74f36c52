//! The C shim's API (csrc/shim.cpp), or, when build.rs could not Verilate the RTL, stubs
//! whose constructor says why. Everything unsafe in the crate is here.

use std::ffi::CStr;
use std::ptr::NonNull;

use crate::RtlError;

/// The shim's model: opaque to Rust.
#[repr(C)]
pub(crate) struct RtMath {
    _private: [u8; 0],
}

/// The shim's intersection unit: opaque to Rust.
#[repr(C)]
pub(crate) struct RtIsect {
    _private: [u8; 0],
}

/// The shim's frame core: opaque to Rust.
#[repr(C)]
pub(crate) struct RtCast {
    _private: [u8; 0],
}

/// The shim's device (the core behind its AXI4-Lite slave): opaque to Rust.
#[repr(C)]
pub(crate) struct RtDevice {
    _private: [u8; 0],
}

#[cfg(verilated)]
mod sys {
    use super::{RtCast, RtDevice, RtIsect, RtMath};
    use std::ffi::c_char;

    extern "C" {
        pub fn rt_math_new() -> *mut RtMath;
        pub fn rt_math_free(m: *mut RtMath);
        pub fn rt_math_cycle(m: *mut RtMath, inputs: *const u32, outputs: *mut u32);
        pub fn rt_isect_new() -> *mut RtIsect;
        pub fn rt_isect_free(m: *mut RtIsect);
        pub fn rt_isect_cycle(m: *mut RtIsect, inputs: *const u32, outputs: *mut u32);
        pub fn rt_cast_new(seed: u64) -> *mut RtCast;
        pub fn rt_cast_free(m: *mut RtCast);
        pub fn rt_cast_cycle(m: *mut RtCast, inputs: *const u32, outputs: *mut u32);
        pub fn rt_device_new() -> *mut RtDevice;
        pub fn rt_device_free(m: *mut RtDevice);
        pub fn rt_device_cycle(m: *mut RtDevice, inputs: *const u32, outputs: *mut u32);
        pub fn rt_math_trace(m: *mut RtMath, path: *const c_char) -> i32;
        pub fn rt_isect_trace(m: *mut RtIsect, path: *const c_char) -> i32;
        pub fn rt_cast_trace(m: *mut RtCast, path: *const c_char) -> i32;
        pub fn rt_device_trace(m: *mut RtDevice, path: *const c_char) -> i32;
    }
}

#[cfg(verilated)]
pub(crate) fn math_trace(m: NonNull<RtMath>, path: &CStr) -> bool {
    // SAFETY: `m` came from `rt_math_new` and lives until its owner's Drop; `path` is
    // NUL-terminated and only read during the call.
    unsafe { sys::rt_math_trace(m.as_ptr(), path.as_ptr()) != 0 }
}

#[cfg(verilated)]
pub(crate) fn isect_trace(m: NonNull<RtIsect>, path: &CStr) -> bool {
    // SAFETY: `m` came from `rt_isect_new` and lives until its owner's Drop; `path` is
    // NUL-terminated and only read during the call.
    unsafe { sys::rt_isect_trace(m.as_ptr(), path.as_ptr()) != 0 }
}

#[cfg(verilated)]
pub(crate) fn cast_trace(m: NonNull<RtCast>, path: &CStr) -> bool {
    // SAFETY: `m` came from `rt_cast_new` and lives until its owner's Drop; `path` is
    // NUL-terminated and only read during the call.
    unsafe { sys::rt_cast_trace(m.as_ptr(), path.as_ptr()) != 0 }
}

#[cfg(verilated)]
pub(crate) fn device_trace(m: NonNull<RtDevice>, path: &CStr) -> bool {
    // SAFETY: `m` came from `rt_device_new` and lives until its owner's Drop; `path` is
    // NUL-terminated and only read during the call.
    unsafe { sys::rt_device_trace(m.as_ptr(), path.as_ptr()) != 0 }
}

#[cfg(not(verilated))]
pub(crate) fn math_trace(_: NonNull<RtMath>, _: &CStr) -> bool {
    false
}

#[cfg(not(verilated))]
pub(crate) fn isect_trace(_: NonNull<RtIsect>, _: &CStr) -> bool {
    false
}

#[cfg(not(verilated))]
pub(crate) fn cast_trace(_: NonNull<RtCast>, _: &CStr) -> bool {
    false
}

#[cfg(not(verilated))]
pub(crate) fn device_trace(_: NonNull<RtDevice>, _: &CStr) -> bool {
    false
}

#[cfg(verilated)]
pub(crate) fn device_new() -> Result<NonNull<RtDevice>, RtlError> {
    // SAFETY: the shim returns a fresh model or null.
    NonNull::new(unsafe { sys::rt_device_new() }).ok_or(RtlError::Construct)
}

#[cfg(verilated)]
pub(crate) fn device_free(m: NonNull<RtDevice>) {
    // SAFETY: `m` came from `rt_device_new` and is freed once (by its owner's Drop).
    unsafe { sys::rt_device_free(m.as_ptr()) }
}

#[cfg(verilated)]
pub(crate) fn device_cycle(m: NonNull<RtDevice>, inputs: &[u32; 18]) -> [u32; 21] {
    let mut out = [0u32; 21];
    // SAFETY: the shim reads 18 words and writes 21, the arrays' sizes.
    unsafe { sys::rt_device_cycle(m.as_ptr(), inputs.as_ptr(), out.as_mut_ptr()) };
    out
}

#[cfg(not(verilated))]
pub(crate) fn device_new() -> Result<NonNull<RtDevice>, RtlError> {
    new().map(|_| NonNull::dangling())
}

#[cfg(not(verilated))]
pub(crate) fn device_free(_: NonNull<RtDevice>) {}

#[cfg(not(verilated))]
pub(crate) fn device_cycle(_: NonNull<RtDevice>, _: &[u32; 18]) -> [u32; 21] {
    [0; 21]
}

#[cfg(verilated)]
pub(crate) fn cast_new(seed: u64) -> Result<NonNull<RtCast>, RtlError> {
    // SAFETY: the shim returns a fresh model or null.
    NonNull::new(unsafe { sys::rt_cast_new(seed) }).ok_or(RtlError::Construct)
}

#[cfg(verilated)]
pub(crate) fn cast_free(m: NonNull<RtCast>) {
    // SAFETY: `m` came from `rt_cast_new` and is freed once (by its owner's Drop).
    unsafe { sys::rt_cast_free(m.as_ptr()) }
}

#[cfg(verilated)]
pub(crate) fn cast_cycle(m: NonNull<RtCast>, inputs: &[u32; 5]) -> [u32; 14] {
    let mut out = [0u32; 14];
    // SAFETY: the shim reads 5 words and writes 14, the arrays' sizes.
    unsafe { sys::rt_cast_cycle(m.as_ptr(), inputs.as_ptr(), out.as_mut_ptr()) };
    out
}

#[cfg(not(verilated))]
pub(crate) fn cast_new(_: u64) -> Result<NonNull<RtCast>, RtlError> {
    new().map(|_| NonNull::dangling())
}

#[cfg(not(verilated))]
pub(crate) fn cast_free(_: NonNull<RtCast>) {}

#[cfg(not(verilated))]
pub(crate) fn cast_cycle(_: NonNull<RtCast>, _: &[u32; 5]) -> [u32; 14] {
    [0; 14]
}

#[cfg(verilated)]
pub(crate) fn isect_new() -> Result<NonNull<RtIsect>, RtlError> {
    // SAFETY: the shim returns a fresh model or null.
    NonNull::new(unsafe { sys::rt_isect_new() }).ok_or(RtlError::Construct)
}

#[cfg(verilated)]
pub(crate) fn isect_free(m: NonNull<RtIsect>) {
    // SAFETY: `m` came from `rt_isect_new` and is freed once (by its owner's Drop).
    unsafe { sys::rt_isect_free(m.as_ptr()) }
}

#[cfg(verilated)]
pub(crate) fn isect_cycle(m: NonNull<RtIsect>, inputs: &[u32; 12]) -> [u32; 5] {
    let mut out = [0u32; 5];
    // SAFETY: the shim reads 12 words and writes 5, the arrays' sizes.
    unsafe { sys::rt_isect_cycle(m.as_ptr(), inputs.as_ptr(), out.as_mut_ptr()) };
    out
}

#[cfg(not(verilated))]
pub(crate) fn isect_new() -> Result<NonNull<RtIsect>, RtlError> {
    new().map(|_| NonNull::dangling())
}

#[cfg(not(verilated))]
pub(crate) fn isect_free(_: NonNull<RtIsect>) {}

#[cfg(not(verilated))]
pub(crate) fn isect_cycle(_: NonNull<RtIsect>, _: &[u32; 12]) -> [u32; 5] {
    [0; 5]
}

#[cfg(verilated)]
pub(crate) fn new() -> Result<NonNull<RtMath>, RtlError> {
    // SAFETY: the shim returns a fresh model or null.
    NonNull::new(unsafe { sys::rt_math_new() }).ok_or(RtlError::Construct)
}

#[cfg(verilated)]
pub(crate) fn free(m: NonNull<RtMath>) {
    // SAFETY: `m` came from `rt_math_new` and is freed once (by its owner's Drop).
    unsafe { sys::rt_math_free(m.as_ptr()) }
}

#[cfg(verilated)]
pub(crate) fn cycle(m: NonNull<RtMath>, inputs: &[u32; 8]) -> [u32; 24] {
    let mut out = [0u32; 24];
    // SAFETY: the shim reads 8 words and writes 24, the arrays' sizes.
    unsafe { sys::rt_math_cycle(m.as_ptr(), inputs.as_ptr(), out.as_mut_ptr()) };
    out
}

#[cfg(not(verilated))]
pub(crate) fn new() -> Result<NonNull<RtMath>, RtlError> {
    match env!("VERILATED_MISSING") {
        "verilator" => Err(RtlError::NoVerilator),
        _ => Err(RtlError::NoRtl),
    }
}

// Without a model no `MathUnits` is ever constructed, so these are never called.
#[cfg(not(verilated))]
pub(crate) fn free(_: NonNull<RtMath>) {}

#[cfg(not(verilated))]
pub(crate) fn cycle(_: NonNull<RtMath>, _: &[u32; 8]) -> [u32; 24] {
    [0; 24]
}
