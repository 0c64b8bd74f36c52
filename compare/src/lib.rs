//! Frame comparison for fpgfx, with no I/O: callers (the `fpgfx compare` command, the C
//! library, tests) read files and hand over buffers, so one kernel serves all of them.
//!
//! [`memh`] is the `$readmemh` text format the test vectors are written in; it lives here
//! because both the writer (`fpgfx vectors`) and the readers (`fpgfx compare`, the C test)
//! depend on this crate, which keeps the format in one place.
//!
//! [`exact`] counts the pixels of two RGB888 frames that differ beyond a tolerance, on
//! borrowed buffers: the C library's comparison.
#![warn(missing_docs)]

pub mod exact;
pub mod memh;
