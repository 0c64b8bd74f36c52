//! fpgfx's golden model as a C library (`libfpgfx.a`, header `include/fpgfx.h`), for a
//! testbench written in C or C++: a Vitis HLS C simulation, a Verilator harness, a
//! co-simulation driver. It renders a ray-traced frame from exactly what the block's AXI
//! writes carry ([`render`]), runs raster FIFO packets into a framebuffer ([`raster`]) and
//! compares frames ([`compare`]), with the same code the `fpgfx` tool's built-in target
//! runs, so a DUT checked against it is checked against the tool.
//!
//! # The boundary
//!
//! Every function returns an [`fpgfx_status`]; on anything but `FPGFX_OK`,
//! [`fpgfx_last_error`] says what was wrong, naming the argument. A null pointer, a
//! misaligned one or a length that does not match what the arguments describe is an
//! error, never undefined behaviour on this side; a panic (a bug) is caught before it
//! crosses into C and reported as `FPGFX_INTERNAL_ERROR`. What the library cannot check
//! is that a pointer really addresses as many bytes as its length says: that stays the
//! caller's promise, as with `memcpy`.
//!
//! Codes that C passes in (layouts, number formats, …) are plain `uint32_t` with
//! `#define`d values rather than C enums: a Rust enum received with a value outside its
//! variants is undefined behaviour, an integer is checked.
//!
//! The names are the C names (`fpgfx_*`, `FPGFX_*`), so that the header and this source
//! can be read side by side.
#![warn(missing_docs)]
#![allow(non_camel_case_types)]

pub mod compare;
pub mod raster;
pub mod render;

use std::cell::RefCell;
use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// What a call did. `FPGFX_OK` is 0, so `if (status)` tests for failure.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum fpgfx_status {
    /// The call did what it was asked.
    FPGFX_OK = 0,
    /// An argument is unusable: a null or misaligned pointer, or a code that names
    /// nothing. `fpgfx_last_error()` names the argument.
    FPGFX_BAD_ARGUMENT = 1,
    /// A length does not match what the other arguments describe (a buffer for another
    /// frame size, a register image of the wrong length).
    FPGFX_SIZE_MISMATCH = 2,
    /// The register image does not describe a scene (magic, version or a field refused).
    FPGFX_BAD_REGISTERS = 3,
    /// Valid input the model cannot follow: texture memory other than what the
    /// registers' procedural textures fill in.
    FPGFX_UNSUPPORTED = 4,
    /// The emulated device refused the work (a FIFO packet that does not decode, a
    /// command the raster block rejects, a scene the ray tracer rejects).
    FPGFX_DEVICE_ERROR = 5,
    /// A bug in the library, caught at the boundary: please report the message.
    FPGFX_INTERNAL_ERROR = 6,
}

/// A failed call: the status to return and the message for `fpgfx_last_error`.
#[derive(Debug)]
pub(crate) struct Failure {
    status: fpgfx_status,
    message: String,
}

impl Failure {
    pub(crate) fn new(status: fpgfx_status, message: impl Into<String>) -> Self {
        Failure {
            status,
            message: message.into(),
        }
    }

    pub(crate) fn argument(message: impl Into<String>) -> Self {
        Self::new(fpgfx_status::FPGFX_BAD_ARGUMENT, message)
    }

    pub(crate) fn size(message: impl Into<String>) -> Self {
        Self::new(fpgfx_status::FPGFX_SIZE_MISMATCH, message)
    }
}

thread_local! {
    /// Per thread, so that two testbench threads never read each other's message.
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_error(message: &str) {
    // A message with a NUL would end early in C; there is none, but it must not fail.
    let text = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = text);
}

/// Runs the body of an exported function: clears the last error, catches a panic, and
/// turns the outcome into a status (recording the message of a failure).
pub(crate) fn guard(body: impl FnOnce() -> Result<(), Failure>) -> fpgfx_status {
    set_last_error("");
    let failure = match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => return fpgfx_status::FPGFX_OK,
        Ok(Err(f)) => f,
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            Failure::new(
                fpgfx_status::FPGFX_INTERNAL_ERROR,
                format!("internal error (a bug in libfpgfx): {what}"),
            )
        }
    };
    set_last_error(&failure.message);
    failure.status
}

/// Borrows `len` elements at `ptr`, refusing null and misaligned pointers and lengths
/// no buffer can have; `name` is the C argument, for the message.
///
/// # Safety
/// `ptr` must address `len` readable elements when it is neither null nor misaligned.
pub(crate) unsafe fn input<'a, T>(
    ptr: *const T,
    len: usize,
    name: &str,
) -> Result<&'a [T], Failure> {
    check_pointer(ptr, len, name)?;
    // SAFETY: non-null, aligned, length bounded; that it addresses `len` elements is the
    // caller's promise.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// [`input`] for a buffer the library writes.
///
/// # Safety
/// `ptr` must address `len` writable elements when it is neither null nor misaligned,
/// not overlapping any other buffer of the same call.
pub(crate) unsafe fn output<'a, T>(
    ptr: *mut T,
    len: usize,
    name: &str,
) -> Result<&'a mut [T], Failure> {
    check_pointer(ptr, len, name)?;
    // SAFETY: as in `input`; the caller promises the buffer is not aliased.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, len) })
}

fn check_pointer<T>(ptr: *const T, len: usize, name: &str) -> Result<(), Failure> {
    if ptr.is_null() {
        return Err(Failure::argument(format!("{name} is NULL")));
    }
    if !ptr.is_aligned() {
        return Err(Failure::argument(format!(
            "{name} is not aligned to {} bytes",
            std::mem::align_of::<T>()
        )));
    }
    if len > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return Err(Failure::size(format!(
            "{name}: length {len} is larger than any buffer"
        )));
    }
    Ok(())
}

/// Writes `value` through an out-pointer argument.
///
/// # Safety
/// `ptr` must be writable when it is neither null nor misaligned.
pub(crate) unsafe fn put<T>(ptr: *mut T, value: T, name: &str) -> Result<(), Failure> {
    check_pointer(ptr, 1, name)?;
    // SAFETY: checked non-null and aligned; writable is the caller's promise.
    unsafe { ptr.write(value) };
    Ok(())
}

/// The message of the last call on this thread that did not return `FPGFX_OK`, or ""
/// after one that did: NUL-terminated, owned by the library, valid until the next
/// `fpgfx_*` call on the same thread.
#[no_mangle]
pub extern "C" fn fpgfx_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}
