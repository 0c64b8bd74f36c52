//! `fpgfx vectors`: test vectors for a block's testbench, one subcommand per block.

use std::path::PathBuf;

use anyhow::{Context, Result};
use host_cli::vectors::render;
use protocol::frame::Numeric;

use super::parse_size;

/// Arguments of `fpgfx vectors`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    block: Block,
}

#[derive(clap::Subcommand)]
enum Block {
    /// The ray-trace block: AXI4-Lite writes, texture memory and the expected frame, depth
    /// and normal planes (docs/vectors-render.md).
    Render(RenderArgs),
}

/// Arguments of `fpgfx vectors render`.
#[derive(clap::Args)]
struct RenderArgs {
    /// The scene file.
    scene: PathBuf,
    /// Directory the vectors are written to (created if missing).
    #[arg(short, long)]
    output: PathBuf,
    /// Number format.
    #[arg(long, default_value_t = Numeric::F32, ignore_case = true)]
    numeric: Numeric,
    /// Frame size WxH (overrides the scene; the field of view is kept).
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
}

/// Writes the vectors the subcommand names.
pub fn run(a: &Args) -> Result<()> {
    match &a.block {
        Block::Render(r) => run_render(r),
    }
}

fn run_render(a: &RenderArgs) -> Result<()> {
    let name = a.scene.display().to_string();
    let text = std::fs::read_to_string(&a.scene).with_context(|| format!("cannot read {name}"))?;
    let scene = sim_target::rt::scene_file::parse(&text, &name)?;
    let opts = render::Options {
        numeric: a.numeric,
        size: a.size,
    };
    let vectors = render::render(&scene, &opts).with_context(|| name.clone())?;
    let written = vectors.write(&a.output, &name)?;
    eprintln!(
        "wrote {} files for a {}x{} frame to {}",
        written.len(),
        vectors.width,
        vectors.height,
        a.output.display()
    );
    Ok(())
}
