//! `fpgfx`: the desktop tool. Each subcommand is a thin layer over `host_cli`, one file
//! per command under `cmd/`; this file lists the commands and turns errors into messages.

mod cmd;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "fpgfx",
    version,
    about = "Drive an FPGA graphics accelerator, or its golden model"
)]
struct Cli {
    #[command(flatten)]
    target: cmd::TargetArgs,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Draw a raster command file (TOML or JSON) and write the framebuffer as PNG.
    Raster(cmd::raster::Args),
    /// Ray-trace a scene file (TOML) and write the frame as PNG.
    Render(cmd::render::Args),
    /// Adversarial cases (docs/stress.md) through the kernels; exits non-zero on any panic,
    /// NaN/∞, crack or wrap-around.
    Stress(cmd::stress::Args),
    /// Animate a scene (or raster commands) with a Rhai script; write a GIF or PNGs.
    ///
    /// The script defines `fn scene(s, frame, time)` (gets the scene file as a map, returns
    /// the frame's scene; base scene from `const SCENE = "file.toml";` or --scene) or
    /// `fn raster(frame, time)` (returns a raster job map: size, background, cmd). Between
    /// frames only the changed ray-tracer registers are sent; each frame's bytes are
    /// printed.
    Animate(cmd::animate::Args),
    /// List serial ports with their USB identity; known adapters are marked.
    ///
    /// Defaults for --port, --baud and --timeout are read from the first of $FPGFX_CONFIG,
    /// ./fpgfx.toml, $XDG_CONFIG_HOME/fpgfx/config.toml, ~/.config/fpgfx/config.toml
    /// (keys: port, baud, timeout).
    Ports(cmd::ports::Args),
    /// Program the board's STM32F405 through its ROM bootloader (AN3155) on --port, or
    /// with --chip msp430f168 the FITkit's MSP430 through its ROM BSL (SLAU319, 9600 baud
    /// unless --baud).
    Flash(cmd::flash::Args),
    /// Sweep number formats × approximations (ray tracer) and sub-pixel bits × AA
    /// (rasterizer): error, host time and hardware cost, with Pareto plots.
    Bench(cmd::bench::Args),
    /// Compare a frame (PNG, PFM or $readmemh framebuffer) with a reference.
    ///
    /// Exit status: 0 within tolerance, 1 beyond it, 2 on unusable input (docs/compare.md).
    Compare(cmd::compare::Args),
    /// Write test vectors and a self-checking testbench for a hardware design.
    Vectors(cmd::vectors::Args),
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let t = &cli.target;
    let result = match &cli.command {
        Command::Raster(a) => cmd::raster::run(t, a),
        Command::Render(a) => cmd::render::run(t, a),
        Command::Stress(a) => cmd::stress::run(a),
        Command::Animate(a) => cmd::animate::run(t, a),
        Command::Ports(a) => cmd::ports::run(a),
        Command::Flash(a) => cmd::flash::run(t, a),
        Command::Bench(a) => cmd::bench::run(a),
        Command::Compare(a) => return cmd::compare::run(a),
        Command::Vectors(a) => cmd::vectors::run(a),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // The chain ("what: why"), not a backtrace: these are the user's mistakes or
            // the target's refusals, and the message already says where.
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
