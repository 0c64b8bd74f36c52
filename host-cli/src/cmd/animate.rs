//! `fpgfx animate`: a Rhai script's frames through the target to a GIF or PNGs, with the
//! per-frame traffic printed; `--interactive` steers the camera from the keyboard.

use std::path::PathBuf;

use anyhow::{Context, Result};
use host_cli::run::animate::{CameraMove, Kind, Output, Script};
use host_cli::run::render::{scene_regs, Aovs, Packing, Renderer};
use protocol::frame::Numeric;

use super::{check_writable_file, parse_size, TargetArgs};

/// Arguments of `fpgfx animate`.
#[derive(clap::Args)]
pub struct Args {
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
    #[arg(long, default_value_t = Numeric::F32, ignore_case = true)]
    numeric: Numeric,
    /// Also write each frame's scene or command file (a pattern like the PNG one), to
    /// check or replay a frame with `fpgfx render` / `fpgfx raster`.
    #[arg(long, value_name = "PATTERN")]
    save_frames: Option<String>,
    /// Move the camera while frames render (scene scripts, in a terminal): ← → orbit,
    /// ↑ ↓ tilt, + − zoom, q or Esc stops. --frames is then the most frames rendered.
    #[arg(long)]
    interactive: bool,
    /// Reduce each scene to what the target's ray tracer builds (printing the first
    /// frame's changes), instead of refusing it.
    #[arg(long)]
    fit: bool,
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
    fn keys(&self, cam: &mut CameraMove) -> Result<bool> {
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

/// Renders the script's frames, printing each frame's traffic, and writes the output.
pub fn run(target: &TargetArgs, a: &Args) -> Result<()> {
    // The outputs are checked before the first frame renders (for a sequence, where
    // frame 0 goes): a GIF is written only after the last one.
    let output = Output::parse(&a.output).map_err(anyhow::Error::msg)?;
    let label = format!("-o/--output {}", a.output);
    match &output {
        Output::Gif(path) => check_writable_file(&label, path)?,
        Output::Pngs(pattern) => check_writable_file(&label, &Output::png_path(pattern, 0))?,
    }
    if let Some(pattern) = &a.save_frames {
        let first = Output::png_path(pattern, 0);
        check_writable_file(&format!("--save-frames {pattern}"), &first)?;
    }
    anyhow::ensure!(a.frames >= 1, "--frames must be at least 1");
    anyhow::ensure!(
        a.fps.is_finite() && a.fps > 0.0,
        "--fps {} must be a positive number",
        a.fps
    );
    let mut session = target.connect()?;
    let numeric = a.numeric;
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
    let mut camera = CameraMove::default();
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
                let mut scene = jobs::scene::parse(&text, &label)?;
                if let Some((w, h)) = a.size {
                    scene.width = w;
                    scene.height = h;
                }
                if a.fit {
                    if let Some(peer) = session.peer() {
                        let changes = jobs::scene::fit_build(&mut scene, &peer.caps.rt_build);
                        if f == 0 {
                            for change in changes {
                                eprintln!("{name}: {change} (--fit)");
                            }
                        }
                    }
                }
                let regs = scene_regs(&session, &scene, numeric).with_context(|| label.clone())?;
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
                let job = jobs::raster::parse(&text, &label)?;
                let out = host_cli::run::raster::run(&mut session, &job, &label)?;
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
        host_cli::run::animate::write_gif(path, &frames, a.fps)?;
        eprintln!("wrote {}", path.display());
    } else {
        eprintln!("wrote {rendered} frames");
    }
    Ok(())
}
