//! The FITkit block's RTL as a target: `fpgfx --port rtl` (the controller in process,
//! driving the Verilated block over its SPI pins) and `fpgfx-sim --pty --fpga rtl` (the
//! same behind a pseudo-terminal). Frames must equal the golden model's and the committed
//! goldens byte for byte; the RTL's cycle count must equal the model's estimate; what the
//! FITkit cannot draw is refused before anything is sent, naming the command.

use crate::common::{assert_model_cycles_equal, example, fails, ok, rgb, start_sim, tmp};

fn fitkit() -> String {
    example("raster/fitkit.toml")
}

#[test]
fn rtl_port_draws_the_fitkit_golden_with_the_models_cycles() {
    let out = tmp("fitkit-rtl.png");
    let run = ok(&["--port", "rtl", "raster", &fitkit(), "-o", &out, "--stats"]);
    assert!(
        rgb(&out) == rgb(&example("raster/golden/fitkit.png")),
        "the RTL's frame differs from the golden"
    );
    // `--stats` on the RTL prints the model's estimate beside the RTL's count: equal.
    assert_model_cycles_equal(&run.stdout);
    assert!(
        run.stdout.contains("model frame   identical to the RTL's"),
        "{}",
        run.stdout
    );
}

#[test]
fn fpga_rtl_behind_a_pty_draws_the_same() {
    let sim = start_sim(&["--fpga", "rtl"]);
    let out = tmp("fitkit-pty-rtl.png");
    ok(&["--port", &sim.pty, "raster", &fitkit(), "-o", &out]);
    assert!(
        rgb(&out) == rgb(&example("raster/golden/fitkit.png")),
        "the RTL behind a pty differs from the golden"
    );
}

#[test]
fn what_the_fitkit_cannot_draw_is_refused_naming_the_command() {
    // gallery.toml's first command is a clear to a colour outside RGB332.
    let err = fails(&[
        "--port",
        "rtl",
        "raster",
        &example("raster/gallery.toml"),
        "-o",
        &tmp("never.png"),
    ]);
    assert!(
        err.contains("gallery.toml: cmd[0] (clear)") && err.contains("fitkit layout"),
        "{err}"
    );
    let err = fails(&[
        "--port",
        "rtl",
        "render",
        &example("reference.toml"),
        "-o",
        &tmp("never-render.png"),
    ]);
    assert!(err.contains("has no ray-trace block"), "{err}");
}
