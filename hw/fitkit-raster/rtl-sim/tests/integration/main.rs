//! The Verilated RTL against the golden model: the same FITkit commands into both (the
//! RTL over `RtlSpi`, framed by `protocol::fitkit_spi`; the model through
//! `sim_target::Device` with the FITkit layout), then equal framebuffers and
//! equal per-unit cycle counts. Without verilator every test fails with `Rtl::new`'s
//! message, never skips.

mod cases;
mod draw;
mod harness;
mod replay;
mod tally;

mod bad_input;
mod clears;
mod fifo;
mod firmware_driver;
mod gallery;
mod lines;
mod mem_wait;
mod mesh;
mod spi;
mod stimulus;
mod stuck;
mod triangles;
mod variants;
