//! The MicroBlaze V board binary (RV32IMAC, riscv-rt) in QEMU's `amd-microblaze-v-generic`,
//! the machine modelled on AMD's generic MicroBlaze V design: the AXI UART Lite is the host
//! link, the AXI UART 16550 the FPGA link served by `fpgfx-sim --fpga-link`. The same
//! end-to-end check as the STM32 board's (`qemu.rs`): raster and render images identical
//! to built-in mode, the defmt log over semihosting shows boot, FPGA and host session.
//! QEMU's machine has no device for the AXI4-Lite ray-trace block, so the FPGA is on the
//! serial link here too. `cargo test qemu_riscv` runs just this.

use crate::common::{example, fails, ok, rgb, tmp};
use crate::qemu::{assert_board_log, draws_and_renders_like_built_in, start, Board, Load};

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

/// The MicroBlaze V board with the ray-casting core's RTL as its FPGA: `fpgfx-sim
/// --fpga-link --fpga rtl:rt` answers the link with the register driver on the Verilated
/// `rt_device`, as the STM32 board reaches the raster block's RTL. The board learns the
/// core's build from its identity; its frame must equal the model's, and a scene asking
/// for more than the core builds is refused by name before anything is sent.
#[test]
fn qemu_riscv_board_renders_on_the_rt_core() {
    let elf = MICROBLAZE_V.elf();
    let (qemu, host_pty, _fpga) = start(&MICROBLAZE_V, &elf, &["--fpga", "rtl:rt"]);
    let scene = crate::rt_rtl::core_scene();
    let (board, built_in) = (tmp("rt-core-board.png"), tmp("rt-core-model.png"));
    let args = |port: &str, out: &str| {
        ok(&[
            "--port",
            port,
            "render",
            &scene,
            "--numeric",
            "q16.16",
            "--size",
            "32x18",
            "-o",
            out,
        ])
    };
    args(&host_pty, &board);
    args("builtin", &built_in);
    assert_eq!(
        rgb(&board),
        rgb(&built_in),
        "board frame differs from the model"
    );
    let err = fails(&[
        "--port",
        &host_pty,
        "render",
        &example("reference.toml"),
        "--numeric",
        "q16.16",
        "-o",
        &tmp("never-rt.png"),
    ]);
    assert!(err.contains("a spot light"), "{err}");
    assert_board_log(&qemu, &elf);
}
