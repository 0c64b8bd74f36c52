//! The MicroBlaze V board binary (RV32IMAC, riscv-rt) in QEMU's `amd-microblaze-v-generic`,
//! the machine modelled on AMD's generic MicroBlaze V design: the AXI UART Lite is the host
//! link, the AXI UART 16550 the FPGA link served by `fpgfx-sim --fpga-link`. The same
//! end-to-end check as the STM32 board's (`qemu.rs`): raster and render images identical
//! to built-in mode, the defmt log over semihosting shows boot, FPGA and host session.
//! QEMU's machine has no device for the AXI4-Lite ray-trace block, so the FPGA is on the
//! serial link here too. `cargo test qemu_riscv` runs just this.

use crate::qemu::{draws_and_renders_like_built_in, Board, Load};

/// The MicroBlaze V board binary on QEMU's generic MicroBlaze V machine (QEMU 9.1 and
/// later; Debian's `qemu-system-misc` from bookworm-backports or trixie).
const MICROBLAZE_V: Board = Board {
    target: "riscv32imac-unknown-none-elf",
    feature: "board-riscv",
    bin: "fpgfx-firmware-riscv",
    qemu: "qemu-system-riscv32",
    package: "qemu-system-misc",
    machine: "amd-microblaze-v-generic",
    // The machine loads no firmware itself: QEMU's generic loader puts the ELF in the
    // LMB block RAM and starts the core at its entry.
    load: Load::Loader,
};

#[test]
fn qemu_riscv_board_draws_and_renders_like_built_in() {
    draws_and_renders_like_built_in(&MICROBLAZE_V);
}
