//! `fpgfx`: the desktop tool. Each subcommand is a thin layer over `host_cli`; this file
//! parses arguments and turns errors into messages.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use host_cli::builtin;
use host_cli::raster_file;
use host_cli::session::{Session, Transport};

#[derive(Parser)]
#[command(
    name = "fpgfx",
    version,
    about = "Drive an FPGA graphics accelerator, or its golden model"
)]
struct Cli {
    /// Serial port of a board or of `fpgfx-sim --pty` (default: the built-in target).
    #[arg(long, global = true, env = "FPGFX_PORT")]
    port: Option<String>,
    /// Line rate of --port.
    #[arg(long, global = true, default_value_t = 115_200)]
    baud: u32,
    #[command(subcommand)]
    command: Command,
}

/// The target: a serial port if one was named, else the built-in one.
fn connect(port: Option<&str>, baud: u32) -> Result<Session<Box<dyn Transport>>> {
    let transport: Box<dyn Transport> = match port {
        Some(p) => Box::new(
            host_cli::serial::SerialTransport::open(p, baud)
                .with_context(|| format!("cannot open serial port {p} at {baud} baud"))?,
        ),
        None => Box::new(builtin::sim_target()),
    };
    Ok(Session::new(transport))
}

#[derive(Subcommand)]
enum Command {
    /// Draw a raster command file (TOML or JSON) and write the framebuffer as PNG.
    Raster {
        /// The command file.
        file: PathBuf,
        /// Output PNG.
        #[arg(short, long, default_value = "raster.png")]
        output: PathBuf,
        /// Triangle traversal: bbox, scanline, zigzag, tiles or simd8 (overrides the file).
        #[arg(long)]
        traversal: Option<String>,
        /// Print fragments, cycles, FIFO stalls, link counters and a board-time estimate.
        #[arg(long)]
        stats: bool,
    },
    /// Ray-trace a scene file (SPEC-RT's TOML) and write the frame as PNG.
    Render(RenderArgs),
    /// Adversarial cases (SPEC §5) through the kernels; exits non-zero on any panic,
    /// NaN/∞, crack or wrap-around.
    Stress(StressArgs),
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s:?} is not WxH"))?;
    let w: u32 = w
        .parse()
        .map_err(|_| format!("width {w:?} is not a number"))?;
    let h: u32 = h
        .parse()
        .map_err(|_| format!("height {h:?} is not a number"))?;
    if w == 0 || h == 0 || w > 4096 || h > 4096 {
        return Err(format!("{w}x{h} is outside 1..=4096 per side"));
    }
    Ok((w, h))
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // The chain ("what: why"), not a backtrace: these are the user's mistakes or
            // the target's refusals, and the message already says where.
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    let port = cli.port.as_deref();
    let baud = cli.baud;
    match cli.command {
        Command::Raster {
            file,
            output,
            traversal,
            stats,
        } => raster(
            connect(port, baud)?,
            &file,
            &output,
            traversal.as_deref(),
            stats,
        ),
        Command::Render(args) => render(connect(port, baud)?, &args),
        Command::Stress(args) => stress(&args),
    }
}

/// Arguments of `fpgfx stress`.
#[derive(clap::Args)]
struct StressArgs {
    /// Number of cases.
    #[arg(long, default_value_t = 100_000)]
    cases: u64,
    /// Generator seed: a case is a function of (seed, index).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Only one category: raster, rt or parse.
    #[arg(long)]
    only: Option<String>,
    /// Run only case K (as printed by a failure, with the same --seed and --only).
    #[arg(long)]
    case: Option<u64>,
    /// Worker threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
}

fn stress(a: &StressArgs) -> Result<()> {
    use host_cli::stress;
    let only = match &a.only {
        Some(name) => Some(
            stress::Category::parse(name)
                .ok_or_else(|| anyhow::anyhow!("--only {name:?}: expected raster, rt or parse"))?,
        ),
        None => None,
    };
    let report = stress::run(&stress::Config {
        cases: a.cases,
        seed: a.seed,
        only,
        case: a.case,
        threads: a.threads,
    })?;
    print!("{}", report.table());
    anyhow::ensure!(
        !report.failed(),
        "stress found failures (panics, NaN/inf, cracks, double writes, coverage, wraps or accepted non-finite input)"
    );
    Ok(())
}

/// Arguments of `fpgfx render`.
#[derive(clap::Args)]
struct RenderArgs {
    /// The scene file.
    scene: PathBuf,
    /// Output PNG.
    #[arg(short, long, default_value = "frame.png")]
    output: PathBuf,
    /// Frame size WxH (overrides the scene; the field of view is kept).
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Number format: f64, f32, f16, q16.16, q8.24, q24.8, q32.32.
    #[arg(long, default_value = "f32")]
    numeric: String,
    /// Samples per pixel (overrides the scene).
    #[arg(long)]
    spp: Option<u32>,
    /// AOVs to write, e.g. depth=d.pfm,normal=n.pfm.
    #[arg(long)]
    aov: Option<String>,
    /// Read-back packing: rgb888 or kcu116 (ViRAY's 16-bit mode, reconstructed).
    #[arg(long, default_value = "rgb888")]
    packing: String,
    /// Print rays, time, board-time estimate and link counters.
    #[arg(long)]
    stats: bool,
}

fn render(mut session: Session<Box<dyn Transport>>, a: &RenderArgs) -> Result<()> {
    use host_cli::render::{Aovs, Packing, Renderer};
    let name = a.scene.display().to_string();
    let text = std::fs::read_to_string(&a.scene).with_context(|| format!("cannot read {name}"))?;
    let mut scene = sim_target::rt::scene_file::parse(&text, &name)?;
    if let Some((w, h)) = a.size {
        scene.width = w;
        scene.height = h;
    }
    if let Some(spp) = a.spp {
        anyhow::ensure!((1..=256).contains(&spp), "--spp {spp} is outside 1..=256");
        scene.spp = spp;
    }
    let numeric = sim_target::rt::parse_numeric(&a.numeric).ok_or_else(|| {
        anyhow::anyhow!(
            "--numeric {:?}: expected f64, f32, f16, q16.16, q8.24, q24.8 or q32.32",
            a.numeric
        )
    })?;
    let packing = match a.packing.as_str() {
        "rgb888" => Packing::Rgb888,
        "kcu116" => Packing::Kcu116,
        other => anyhow::bail!("--packing {other:?}: expected rgb888 or kcu116"),
    };
    let mut aovs = Aovs::default();
    let mut aov_paths: Vec<(String, PathBuf)> = Vec::new();
    if let Some(spec) = &a.aov {
        for item in spec.split(',') {
            let (kind, path) = item
                .split_once('=')
                .ok_or_else(|| anyhow::anyhow!("--aov {item:?}: expected NAME=FILE.pfm"))?;
            match kind {
                "depth" => aovs.depth = true,
                "normal" => aovs.normal = true,
                other => anyhow::bail!("--aov {other:?}: expected depth or normal"),
            }
            aov_paths.push((kind.to_string(), PathBuf::from(path)));
        }
    }
    let regs = sim_target::scene_regs::to_regs(&scene).with_context(|| name.clone())?;
    // The target renders a frame without answering in between: allow for a full-HD
    // frame in the slowest format.
    session.timeout = std::time::Duration::from_secs(3600);
    session.handshake().context("handshake with the target")?;
    let started = std::time::Instant::now();
    let (out, words) = Renderer::new().frame(&mut session, &regs, numeric, packing, aovs)?;
    let elapsed = started.elapsed();
    out.image
        .save(&a.output)
        .with_context(|| format!("cannot write {}", a.output.display()))?;
    for (kind, path) in &aov_paths {
        let (data, channels) = match kind.as_str() {
            "depth" => (out.depth.as_deref(), 1),
            _ => (out.normal.as_deref(), 3),
        };
        let data = data.ok_or_else(|| anyhow::anyhow!("the target sent no {kind} AOV"))?;
        let file = std::fs::File::create(path)
            .with_context(|| format!("cannot create {}", path.display()))?;
        sim_target::rt::write_pfm(
            std::io::BufWriter::new(file),
            out.image.width(),
            out.image.height(),
            channels,
            data,
        )
        .with_context(|| format!("cannot write {}", path.display()))?;
    }
    if a.stats {
        let secs = elapsed.as_secs_f64();
        println!(
            "frame         {}x{} {numeric:?}",
            out.image.width(),
            out.image.height()
        );
        println!("registers     {words} words sent");
        println!(
            "rays          {} ({:.2} Mrays/s host)",
            out.rays,
            out.rays as f64 / secs / 1e6
        );
        println!(
            "board time    {:.1} ms ({} cycles at {:.0} MHz, II = {})",
            out.cycles as f64 / sim_target::rt::BOARD_CLOCK_HZ * 1e3,
            out.cycles,
            sim_target::rt::BOARD_CLOCK_HZ / 1e6,
            sim_target::rt::BOARD_II
        );
        let l = out.stats.link;
        println!(
            "link (target) sent {} resent {} delivered {} crc errors {} duplicates {}",
            l.sent, l.resent, l.delivered, l.crc_errors, l.duplicates
        );
        println!("host time     {:.1} ms", secs * 1e3);
    }
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

fn raster(
    mut session: Session<Box<dyn Transport>>,
    file: &Path,
    output: &Path,
    traversal: Option<&str>,
    stats: bool,
) -> Result<()> {
    let name = file.display().to_string();
    let text = std::fs::read_to_string(file).with_context(|| format!("cannot read {name}"))?;
    let mut job = raster_file::parse(&text, &name)?;
    if let Some(t) = traversal {
        job.setup.traversal =
            raster_file::parse_traversal(t).map_err(|m| anyhow::anyhow!("--traversal: {m}"))?;
    }
    session.handshake().context("handshake with the target")?;
    let started = std::time::Instant::now();
    let out = host_cli::raster::run(&mut session, &job, &name)?;
    let elapsed = started.elapsed();
    out.image
        .save(output)
        .with_context(|| format!("cannot write {}", output.display()))?;
    if stats {
        let d = out.stats.device;
        let l = out.stats.link;
        let clock = sim_target::raster::hw::CLOCK_HZ;
        println!("commands      {}", d.commands);
        println!("bus records   {}", d.bus_words);
        println!("fragments     {}", d.fragments);
        println!("FPGA cycles   {}", d.cycles);
        println!(
            "board time    {:.3} ms at {:.0} MHz",
            d.cycles as f64 / clock * 1e3,
            clock / 1e6
        );
        println!("FIFO stalls   {}", d.fifo_stalls);
        println!(
            "link (target) sent {} resent {} delivered {} crc errors {} duplicates {}",
            l.sent, l.resent, l.delivered, l.crc_errors, l.duplicates
        );
        println!("host time     {:.1} ms", elapsed.as_secs_f64() * 1e3);
    }
    eprintln!("wrote {}", output.display());
    Ok(())
}
