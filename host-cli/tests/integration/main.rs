//! host-cli's integration tests, one module per area: the `fpgfx` binary on good and bad
//! input, the built-in pipeline (recording bus, gallery goldens, FPGA link, the AXI4-Lite
//! register bus), the emulated board over a pty and TCP, flashing through the ROM
//! bootloader, the real board binary under QEMU, target selection, `animate`, `bench`,
//! `stress`, the raster file parser's property tests, `vectors` (its testbench under
//! Icarus and Verilator) and every command's refusal of an output it could not write. One binary rather than one per file: each test binary links
//! the whole stack again, so a single one is built and linked once.
//!
//! The tests share one process and run on parallel threads: scratch files go to a
//! folder per module ([`common::tmp`]), and nothing here sets environment variables or
//! listens on a fixed port. Proptest keeps the cases it shrinks to in
//! `tests/proptest-regressions/<module>.txt` (its default next to a `main.rs`); commit
//! them, and they run first on every later run.

mod common;

mod animate;
mod bench;
mod cli;
mod compare;
mod flash;
mod float_regs;
mod fpga_link;
mod gallery;
mod mmio;
mod outputs;
mod pipeline;
mod ports;
mod pty;
mod qemu;
mod qemu_riscv;
mod rt_rtl;
mod rtl;
mod stress;
mod vectors;
mod vectors_render;
