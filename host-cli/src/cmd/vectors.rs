//! `fpgfx vectors`: test vectors for a hardware design (docs/vectors.md).

use std::path::PathBuf;

use anyhow::{Context, Result};
use protocol::bus::LayoutId;
use protocol::frame::Numeric;
use vectors::{render, VectorSet};

use super::{check_output_dir, flag_path, parse_size};

/// Arguments of `fpgfx vectors`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    what: What,
}

#[derive(clap::Subcommand)]
enum What {
    /// A raster job as vectors for the raster block: SPI stream, FIFO records, the
    /// memory write stream and the final framebuffer, a manifest and (FITkit) a
    /// self-checking Verilog testbench with run-iverilog.sh / run-verilator.sh RTL_DIR.
    Raster(RasterArgs),
    /// A scene as vectors for the ray-trace block: AXI4-Lite writes, register image,
    /// texture memory, and the expected frame (RGB888, KCU116), depth and normal planes.
    Render(RenderArgs),
}

/// Arguments of `fpgfx vectors raster`.
#[derive(clap::Args)]
struct RasterArgs {
    /// The raster job (the TOML or JSON `fpgfx raster` reads).
    file: PathBuf,
    /// Directory to write the vectors into (created if missing).
    #[arg(short, long)]
    output: PathBuf,
    /// Bus layout of the block's input FIFO; only the FITkit's has SPI framing and RTL
    /// here, so only it gets the testbench.
    #[arg(long, value_enum, default_value_t = Layout::Fitkit)]
    layout: Layout,
}

/// Arguments of `fpgfx vectors render`.
#[derive(clap::Args)]
struct RenderArgs {
    /// The scene file.
    scene: PathBuf,
    /// Directory to write the vectors into (created if missing).
    #[arg(short, long)]
    output: PathBuf,
    /// Number format of the frame (the block's NUMERIC register).
    #[arg(long, default_value_t = Numeric::F32, ignore_case = true)]
    numeric: Numeric,
    /// Frame size WxH (overrides the scene; the field of view is kept).
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
}

/// `--layout`'s spellings, as `protocol::bus`'s layout names.
#[derive(Clone, Copy, clap::ValueEnum)]
enum Layout {
    Fitkit,
    Extended,
    Wide,
}

impl From<Layout> for LayoutId {
    fn from(l: Layout) -> Self {
        match l {
            Layout::Fitkit => LayoutId::Fitkit,
            Layout::Extended => LayoutId::Extended,
            Layout::Wide => LayoutId::Wide,
        }
    }
}

/// Runs `fpgfx vectors …`.
pub fn run(a: &Args) -> Result<()> {
    match &a.what {
        What::Raster(r) => raster(r),
        What::Render(r) => render(r),
    }
}

/// Writes the vectors and lists the files with their word counts.
fn raster(a: &RasterArgs) -> Result<()> {
    check_output_dir(&flag_path("-o/--output", &a.output), &a.output)?;
    let name = a.file.display().to_string();
    let text = std::fs::read_to_string(&a.file).with_context(|| format!("cannot read {name}"))?;
    let set = vectors::raster::raster(&text, &name, a.layout.into())?;
    set.write_to(&a.output)?;
    list(&set);
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// Renders the scene on the golden model and writes its vectors.
fn render(a: &RenderArgs) -> Result<()> {
    check_output_dir(&flag_path("-o/--output", &a.output), &a.output)?;
    let name = a.scene.display().to_string();
    let text = std::fs::read_to_string(&a.scene).with_context(|| format!("cannot read {name}"))?;
    let scene = jobs::scene::parse(&text, &name)?;
    let opts = render::Options {
        numeric: a.numeric,
        size: a.size,
    };
    let vectors = render::render(&scene, &opts).with_context(|| name.clone())?;
    let set = vectors.set(&name)?;
    set.write_to(&a.output)?;
    list(&set);
    eprintln!(
        "wrote a {}x{} frame's vectors to {}",
        vectors.width,
        vectors.height,
        a.output.display()
    );
    Ok(())
}

/// One line per file written, with its word count where the set lists one.
fn list(set: &VectorSet) {
    for f in &set.files {
        match &f.entry {
            Some(e) => println!(
                "{:<26} {:>8} words of {:>2} bits",
                f.name, e.words, e.word_bits
            ),
            None => println!("{}", f.name),
        }
    }
}
