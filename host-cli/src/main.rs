//! `fpgfx`: the desktop tool. Each subcommand is a thin layer over `host_cli`; this file
//! parses arguments and turns errors into messages.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use host_cli::raster_file;
use host_cli::session::{Session, Transport};

mod cmd {
    pub mod bench;
    pub mod stress;
}

#[derive(Parser)]
#[command(
    name = "fpgfx",
    version,
    about = "Drive an FPGA graphics accelerator, or its golden model"
)]
struct Cli {
    #[command(flatten)]
    target: TargetArgs,
    #[command(subcommand)]
    command: Command,
}

/// Options every command shares; each falls back to `fpgfx.toml` (see `fpgfx ports
/// --help`), then to its default.
#[derive(clap::Args)]
struct TargetArgs {
    /// Target: a serial port (a board, `fpgfx-sim --pty`, QEMU), `tcp:HOST:PORT`
    /// (`fpgfx-sim --tcp`) or `builtin`. Default: the one known USB-serial adapter if
    /// exactly one is plugged in, else the built-in target.
    #[arg(long, global = true, env = "FPGFX_PORT")]
    port: Option<String>,
    /// Line rate of a serial --port [default: 115200].
    #[arg(long, global = true)]
    baud: Option<u32>,
    /// Seconds to wait for the target to answer the handshake [default: 10].
    #[arg(long, global = true)]
    timeout: Option<f64>,
}

/// Opens the target the options, the environment and the config file name.
fn connect(args: &TargetArgs) -> Result<Session<Box<dyn Transport>>> {
    use host_cli::connect::{choose, load_config, open, Target};
    let config = load_config()?.map(|(_, c)| c).unwrap_or_default();
    let port = args.port.clone().or(config.port);
    let baud = args.baud.or(config.baud).unwrap_or(115_200);
    let timeout = args.timeout.or(config.timeout).unwrap_or(10.0);
    anyhow::ensure!(
        timeout.is_finite() && timeout > 0.0,
        "--timeout {timeout}: must be a positive number of seconds"
    );
    // Listing ports only matters when none was named.
    let ports = if port.is_none() {
        host_cli::ports::list().unwrap_or_default()
    } else {
        Vec::new()
    };
    let (target, why) = choose(port.as_deref(), baud, &ports);
    if target != Target::BuiltIn && port.is_none() {
        eprintln!("using {why}");
    }
    let mut session = Session::new(open(&target)?);
    session.timeout = std::time::Duration::from_secs_f64(timeout);
    Ok(session)
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
    Stress(cmd::stress::Args),
    /// Animate a scene (or raster commands) with a Rhai script; write a GIF or PNGs.
    ///
    /// The script defines `fn scene(s, frame, time)` (gets the scene file as a map, returns
    /// the frame's scene; base scene from `const SCENE = "file.toml";` or --scene) or
    /// `fn raster(frame, time)` (returns a raster job map: size, background, cmd). Between
    /// frames only the changed ray-tracer registers are sent; each frame's bytes are
    /// printed.
    Animate(AnimateArgs),
    /// List serial ports with their USB identity; known adapters are marked.
    ///
    /// Defaults for --port, --baud and --timeout are read from the first of $FPGFX_CONFIG,
    /// ./fpgfx.toml, $XDG_CONFIG_HOME/fpgfx/config.toml, ~/.config/fpgfx/config.toml
    /// (keys: port, baud, timeout).
    Ports,
    /// Program the board's STM32F405 through its ROM bootloader (AN3155) on --port.
    Flash(host_cli::flash::FlashArgs),
    /// Sweep number formats × approximations (ray tracer) and sub-pixel bits × AA
    /// (rasterizer): error, host time and hardware cost, with Pareto plots.
    Bench(cmd::bench::Args),
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
    match cli.command {
        Command::Raster {
            file,
            output,
            traversal,
            stats,
        } => raster(
            connect(&cli.target)?,
            cli.target.baud,
            &file,
            &output,
            traversal.as_deref(),
            stats,
        ),
        Command::Render(args) => render(connect(&cli.target)?, cli.target.baud, &args),
        Command::Ports => ports(),
        Command::Animate(args) => animate(connect(&cli.target)?, &args),
        Command::Flash(args) => {
            host_cli::flash::run(cli.target.port.as_deref(), cli.target.baud, &args)
                .map(|_| ())
                .with_context(|| format!("flash {}", args.image.display()))
        }
        Command::Bench(args) => cmd::bench::run(&args),
        Command::Stress(args) => cmd::stress::run(&args),
    }
}

fn ports() -> Result<()> {
    let ports = host_cli::ports::list().context("cannot list serial ports")?;
    if ports.is_empty() {
        println!("no serial ports");
    }
    for p in &ports {
        println!("{}", host_cli::ports::describe(p));
    }
    if let Some(one) = host_cli::ports::the_one_adapter(&ports) {
        println!("without --port, fpgfx uses {}", one.path);
    }
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

fn render(
    mut session: Session<Box<dyn Transport>>,
    line_rate: Option<u32>,
    a: &RenderArgs,
) -> Result<()> {
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
    session.handshake().context("handshake with the target")?;
    // The target renders a frame without answering in between: allow for a full-HD
    // frame in the slowest format.
    session.timeout = std::time::Duration::from_secs(3600);
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
        println!(
            "frame         {}x{} {numeric:?}",
            out.image.width(),
            out.image.height()
        );
        println!("registers     {words} words sent");
        // SPEC-RT counts DEPTH × (1 + lights) rays per sample whether they are traced or
        // not (the seed's Mrays/s); the target reports the rays it actually traced. The
        // rates are over the render alone: the read-back is the link's speed, not the
        // block's.
        let nominal = sim_target::rt::nominal_rays(&scene, scene.width, scene.height, scene.spp);
        let secs = out.render.as_secs_f64().max(1e-9);
        println!(
            "rays          {nominal} as SPEC-RT counts them, {} traced",
            out.rays
        );
        println!(
            "render        {:.1} ms start to done: {:.2} Mrays/s as SPEC-RT counts them, {:.2} traced",
            secs * 1e3,
            nominal as f64 / secs / 1e6,
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
        println!("{}", phase_line("registers →", out.send, line_rate));
        println!("{}", phase_line("read-back ←", out.read_back, line_rate));
        println!(
            "host time     {:.1} ms (registers, render and read-back)",
            elapsed.as_secs_f64() * 1e3
        );
    }
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

fn raster(
    mut session: Session<Box<dyn Transport>>,
    line_rate: Option<u32>,
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
        for (what, phase) in [("commands →", out.send), ("read-back ←", out.read_back)] {
            println!("{}", phase_line(what, phase, line_rate));
        }
    }
    eprintln!("wrote {}", output.display());
    Ok(())
}

/// One direction of a run's traffic for `--stats`: payload, time, rate and, on a serial
/// port, how much of the line it used.
fn phase_line(what: &str, phase: host_cli::session::Phase, line_rate: Option<u32>) -> String {
    let mut line = format!(
        "{what:<13} {} B payload in {:.1} ms = {:.1} KB/s",
        phase.payload_bytes,
        phase.time.as_secs_f64() * 1e3,
        phase.rate() / 1e3
    );
    if let Some(baud) = line_rate {
        // 8N1: ten bit times per byte on the wire.
        line.push_str(&format!(
            " = {:.1} % of {baud} baud",
            phase.rate() / (f64::from(baud) / 10.0) * 100.0
        ));
    }
    line
}

/// Arguments of `fpgfx animate`.
#[derive(clap::Args)]
struct AnimateArgs {
    /// The Rhai script.
    script: PathBuf,
    /// Output: NAME.gif, or a PNG pattern such as frames/f-%04d.png.
    #[arg(short, long)]
    output: String,
    /// Frames to render.
    #[arg(long, default_value_t = 24)]
    frames: u32,
    /// Frames per second (the script's time is frame / fps; the GIF plays at this rate).
    #[arg(long, default_value_t = 12.0)]
    fps: f64,
    /// Base scene (overrides the script's SCENE constant).
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Frame size WxH for scene scripts (overrides the scene).
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Number format of the ray tracer.
    #[arg(long, default_value = "f32")]
    numeric: String,
    /// Also write each frame's scene or command file (a pattern like the PNG one), to
    /// check or replay a frame with `fpgfx render` / `fpgfx raster`.
    #[arg(long, value_name = "PATTERN")]
    save_frames: Option<String>,
    /// Move the camera while frames render (scene scripts, in a terminal): ← → orbit,
    /// ↑ ↓ tilt, + − zoom, q or Esc stops. --frames is then the most frames rendered.
    #[arg(long)]
    interactive: bool,
}

/// Raw terminal mode for `--interactive`, restored however the loop ends.
struct RawMode;

impl RawMode {
    fn enter() -> Result<Self> {
        use std::io::IsTerminal;
        anyhow::ensure!(
            std::io::stdin().is_terminal(),
            "--interactive needs a terminal on stdin"
        );
        crossterm::terminal::enable_raw_mode().context("cannot put the terminal in raw mode")?;
        Ok(RawMode)
    }

    /// Applies the keys pressed since the last frame; `false` when the user quits.
    fn keys(&self, cam: &mut host_cli::animate::CameraMove) -> Result<bool> {
        use crossterm::event::{self, Event, KeyCode, KeyEventKind};
        let step = 10f64.to_radians();
        while event::poll(std::time::Duration::ZERO)? {
            if let Event::Key(k) = event::read()? {
                if k.kind == KeyEventKind::Release {
                    continue;
                }
                match k.code {
                    KeyCode::Left => cam.yaw -= step,
                    KeyCode::Right => cam.yaw += step,
                    KeyCode::Up => cam.pitch += step,
                    KeyCode::Down => cam.pitch -= step,
                    KeyCode::Char('+') | KeyCode::Char('=') => cam.zoom *= 0.9,
                    KeyCode::Char('-') => cam.zoom /= 0.9,
                    KeyCode::Char('q') | KeyCode::Esc => return Ok(false),
                    KeyCode::Char('c') if k.modifiers.contains(event::KeyModifiers::CONTROL) => {
                        return Ok(false)
                    }
                    _ => {}
                }
            }
        }
        Ok(true)
    }
}

impl Drop for RawMode {
    fn drop(&mut self) {
        let _ = crossterm::terminal::disable_raw_mode();
    }
}

fn animate(mut session: Session<Box<dyn Transport>>, a: &AnimateArgs) -> Result<()> {
    use host_cli::animate::{Kind, Output, Script};
    use host_cli::render::{Aovs, Packing, Renderer};
    let output = Output::parse(&a.output).map_err(anyhow::Error::msg)?;
    anyhow::ensure!(a.frames >= 1, "--frames must be at least 1");
    anyhow::ensure!(
        a.fps.is_finite() && a.fps > 0.0,
        "--fps {} must be a positive number",
        a.fps
    );
    let numeric = sim_target::rt::parse_numeric(&a.numeric).ok_or_else(|| {
        anyhow::anyhow!(
            "--numeric {:?}: expected f64, f32, f16, q16.16, q8.24, q24.8 or q32.32",
            a.numeric
        )
    })?;
    let mut script = Script::load(&a.script)?;
    let name = a.script.display().to_string();
    if script.kind() == Kind::Scene {
        let file = a
            .scene
            .clone()
            .or_else(|| script.scene_file.clone())
            .ok_or_else(|| {
                anyhow::anyhow!(
                    "{name}: a scene script needs `const SCENE = \"file.toml\";` or --scene"
                )
            })?;
        let text = std::fs::read_to_string(&file)
            .with_context(|| format!("cannot read {}", file.display()))?;
        script.set_base_scene(&text, &file.display().to_string())?;
    }
    session.handshake().context("handshake with the target")?;
    session.timeout = std::time::Duration::from_secs(3600);
    let mut renderer = Renderer::new();
    let mut frames: Vec<image::RgbImage> = Vec::new();
    anyhow::ensure!(
        !a.interactive || script.kind() == Kind::Scene,
        "--interactive moves the camera: it needs a scene script"
    );
    let raw = if a.interactive {
        eprint!("← → orbit, ↑ ↓ tilt, + − zoom, q quits\r\n");
        Some(RawMode::enter()?)
    } else {
        None
    };
    let mut camera = host_cli::animate::CameraMove::default();
    let mut rendered = 0;
    let (mut total_payload, mut total_wire) = (0u64, 0u64);
    for f in 0..a.frames {
        let time = f64::from(f) / a.fps;
        if let Some(raw) = &raw {
            if !raw.keys(&mut camera)? {
                break;
            }
        }
        let text = script.frame(f, time)?;
        let text = camera
            .apply(&text)
            .map_err(|e| anyhow::anyhow!("{name} frame {f}: {e}"))?;
        let label = format!("{name} frame {f}");
        if let Some(pattern) = &a.save_frames {
            let path = Output::png_path(pattern, f);
            std::fs::write(&path, &text)
                .with_context(|| format!("cannot write {}", path.display()))?;
        }
        let (payload0, wire0) = (session.traffic().payload_sent, session.traffic().sent);
        let started = std::time::Instant::now();
        let (image, what) = match script.kind() {
            Kind::Scene => {
                let mut scene = sim_target::rt::scene_file::parse(&text, &label)?;
                if let Some((w, h)) = a.size {
                    scene.width = w;
                    scene.height = h;
                }
                let regs =
                    sim_target::scene_regs::to_regs(&scene).with_context(|| label.clone())?;
                let (out, words) = renderer
                    .frame(
                        &mut session,
                        &regs,
                        numeric,
                        Packing::Rgb888,
                        Aovs::default(),
                    )
                    .with_context(|| label.clone())?;
                (out.image, format!("{words:>4} register words"))
            }
            Kind::Raster => {
                let job = raster_file::parse(&text, &label)?;
                let out = host_cli::raster::run(&mut session, &job, &label)?;
                (out.image, format!("{:>4} commands", job.cmds.len()))
            }
        };
        let payload = session.traffic().payload_sent - payload0;
        let wire = session.traffic().sent - wire0;
        total_payload += payload;
        total_wire += wire;
        // Raw mode does not turn \n into \r\n.
        print!(
            "frame {f:>4}  t={time:>7.3} s  {what}  {payload:>7} B payload  {wire:>7} B on the wire  {:>8.1} ms{}",
            started.elapsed().as_secs_f64() * 1e3,
            if raw.is_some() { "\r\n" } else { "\n" }
        );
        rendered += 1;
        match &output {
            Output::Pngs(pattern) => {
                let path = Output::png_path(pattern, f);
                image
                    .save(&path)
                    .with_context(|| format!("cannot write {}", path.display()))?;
            }
            Output::Gif(_) => frames.push(image),
        }
    }
    drop(raw);
    println!("total {rendered} frames: {total_payload} B payload, {total_wire} B host → target");
    if let Output::Gif(path) = &output {
        write_gif(path, &frames, a.fps)?;
        eprintln!("wrote {}", path.display());
    } else {
        eprintln!("wrote {rendered} frames");
    }
    Ok(())
}

fn write_gif(path: &Path, frames: &[image::RgbImage], fps: f64) -> Result<()> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let file =
        std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let mut enc = GifEncoder::new_with_speed(std::io::BufWriter::new(file), 10);
    enc.set_repeat(Repeat::Infinite)?;
    let delay = image::Delay::from_numer_denom_ms(1000, (fps.round() as u32).max(1));
    for f in frames {
        let rgba = image::DynamicImage::ImageRgb8(f.clone()).into_rgba8();
        enc.encode_frame(image::Frame::from_parts(rgba, 0, 0, delay))
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}
