//! Frame comparison for fpgfx, with no I/O: callers (the `fpgfx compare` command, the C
//! library, tests) read files and hand over buffers, so one kernel serves all of them.
//!
//! [`compare()`] takes two [`Frame`]s and [`Options`] and returns a [`Report`]: every pixel
//! counted as equal, within the tolerance, allowed near an edge, or failing as missing,
//! unexpected or differing; the error figures (levels and PSNR, or absolute and relative
//! error for float planes); the first failing pixels; an error mask. The edge allowance
//! is measured from plain segments ([`Edge`]), which [`raster_edges`] derives from a
//! raster job and any other caller can state itself. docs/compare.md defines every figure.
//!
//! [`memh`] is the `$readmemh` text format the test vectors are written in; it lives here
//! because both the writer (`fpgfx vectors`) and the readers (`fpgfx compare`, the C test)
//! depend on this crate, which keeps the format in one place.
#![warn(missing_docs)]

mod edge;
mod kernel;
pub mod memh;
mod raster;

pub use edge::Edge;
pub use kernel::{
    compare, psnr, Class, CompareError, Coverage, Errors, FloatErrors, Frame, LevelErrors,
    Mismatch, Options, Pixels, Report, Side, MASK_ALLOWED, MASK_FAIL, MAX_CHANNELS,
};
pub use raster::raster_edges;
