//! `fpgfx vectors`: test vectors for a hardware design (docs/vectors.md).

use std::path::PathBuf;

use anyhow::{Context, Result};
use protocol::fpga::LayoutId;

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
    }
}

/// Writes the vectors and lists the files with their word counts.
fn raster(a: &RasterArgs) -> Result<()> {
    let name = a.file.display().to_string();
    let text = std::fs::read_to_string(&a.file).with_context(|| format!("cannot read {name}"))?;
    let set = host_cli::vectors::raster::raster(&text, &name, a.layout.into())?;
    set.write_to(&a.output)?;
    for f in &set.files {
        match &f.entry {
            Some(e) => println!(
                "{:<26} {:>8} words of {:>2} bits",
                f.name, e.words, e.word_bits
            ),
            None => println!("{}", f.name),
        }
    }
    eprintln!("wrote {}", a.output.display());
    Ok(())
}
