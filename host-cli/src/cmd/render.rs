//! `fpgfx render`: a scene file through the target's ray tracer to a PNG (and PFM AOVs).

use std::path::PathBuf;

use anyhow::{Context, Result};
use host_cli::run::render::{scene_regs, AovFiles, Aovs, Packing, RenderOutput, Renderer};
use protocol::frame::Numeric;
use sim_target::scene_regs::Regs;

use super::{check_output_file, flag_path, parse_size, phase_line, TargetArgs};

/// Arguments of `fpgfx render`.
#[derive(clap::Args)]
pub struct Args {
    /// The scene file.
    scene: PathBuf,
    /// Output PNG.
    #[arg(short, long, default_value = "frame.png")]
    output: PathBuf,
    /// Frame size WxH (overrides the scene; the field of view is kept).
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Number format.
    #[arg(long, default_value_t = Numeric::F32, ignore_case = true)]
    numeric: Numeric,
    /// Samples per pixel (overrides the scene).
    #[arg(long)]
    spp: Option<u32>,
    /// AOVs to write, e.g. depth=d.pfm,normal=n.pfm.
    #[arg(long)]
    aov: Option<String>,
    /// Read-back packing (kcu116: ViRAY's 16-bit mode, reconstructed).
    #[arg(long, default_value_t = Packing::Rgb888)]
    packing: Packing,
    /// Print rays, time, board-time estimate and link counters.
    #[arg(long)]
    stats: bool,
    /// Reduce the scene to what the target's ray tracer builds (a core without textures,
    /// spot lights, …), printing each change, instead of refusing it.
    #[arg(long)]
    fit: bool,
}

/// Renders the scene on the target, writes the PNG and the AOVs and, with `--stats`,
/// prints the counters.
pub fn run(target: &TargetArgs, a: &Args) -> Result<()> {
    // Every output is checked before the target is opened: a frame can take minutes.
    check_output_file(
        &flag_path("-o/--output", &a.output),
        &a.output,
        "the frame",
        &["png"],
    )?;
    let aov_files = match &a.aov {
        Some(spec) => spec
            .parse::<AovFiles>()
            .map_err(|e| anyhow::anyhow!("--aov {e}"))?,
        None => AovFiles::default(),
    };
    for (aov, path) in &aov_files.0 {
        check_output_file(
            &format!("--aov {aov}={}", path.display()),
            path,
            &format!("the {aov} AOV"),
            &["pfm"],
        )?;
    }
    let mut session = target.connect()?;
    let name = a.scene.display().to_string();
    let text = std::fs::read_to_string(&a.scene).with_context(|| format!("cannot read {name}"))?;
    let mut scene = jobs::scene::parse(&text, &name)?;
    if let Some((w, h)) = a.size {
        scene.width = w;
        scene.height = h;
    }
    if let Some(spp) = a.spp {
        anyhow::ensure!((1..=256).contains(&spp), "--spp {spp} is outside 1..=256");
        scene.spp = spp;
    }
    let numeric = a.numeric;
    warn_out_of_range(&name, &scene, numeric);
    session.handshake().context("handshake with the target")?;
    if a.fit {
        if let Some(peer) = session.peer() {
            for change in jobs::scene::fit_build(&mut scene, &peer.caps.rt_build) {
                eprintln!("{name}: {change} (--fit)");
            }
        }
    }
    let regs = scene_regs(&session, &scene, numeric).with_context(|| name.clone())?;
    // The target renders a frame without answering in between: allow for a full-HD
    // frame in the slowest format.
    session.timeout = std::time::Duration::from_secs(3600);
    let started = std::time::Instant::now();
    let (out, words) =
        Renderer::new().frame(&mut session, &regs, numeric, a.packing, aov_files.aovs())?;
    let elapsed = started.elapsed();
    out.image
        .save(&a.output)
        .with_context(|| format!("cannot write {}", a.output.display()))?;
    aov_files.write(&out)?;
    if a.stats {
        println!(
            "frame         {}x{} {numeric:?}",
            out.image.width(),
            out.image.height()
        );
        println!("registers     {words} words sent");
        // docs/requirements.md §4.10 counts DEPTH × (1 + lights) rays per sample whether they are traced or
        // not (the seed's Mrays/s); the target reports the rays it actually traced. The
        // rates are over the render alone: the read-back is the link's speed, not the
        // block's.
        let nominal = sim_target::rt::nominal_rays(&scene, scene.width, scene.height, scene.spp);
        let secs = out.render.as_secs_f64().max(1e-9);
        println!(
            "rays          {nominal} nominal (the seed's count), {} traced",
            out.rays
        );
        println!(
            "render        {:.1} ms start to done: {:.2} Mrays/s nominal, {:.2} traced",
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
        if target.settings()?.port.as_deref() == Some("rtl:rt") {
            let model = model_beside_rtl(&regs, numeric, a.packing, aov_files.aovs(), &out)?;
            // the core has no saturation count (docs/rt-core.md): its counter's 0 is not
            // a measurement, so the model's count stands beside it, named as the model's
            println!(
                "saturations   not counted by the core (its counter reads {}); the model \
                 clips {model} results in this frame",
                out.stats.device.saturations
            );
        } else {
            println!(
                "saturations   {} results clipped to the format's range (fixed point; \
                 floats do not saturate)",
                out.stats.device.saturations
            );
        }
        let l = out.stats.link;
        println!(
            "link (target) sent {} resent {} delivered {} crc errors {} duplicates {}",
            l.sent, l.resent, l.delivered, l.crc_errors, l.duplicates
        );
        println!("{}", phase_line("registers →", out.send, target.baud));
        println!("{}", phase_line("read-back ←", out.read_back, target.baud));
        println!(
            "host time     {:.1} ms (registers, render and read-back)",
            elapsed.as_secs_f64() * 1e3
        );
    }
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// Says, before rendering, which scene fields make magnitudes `numeric` cannot hold: a
/// fixed-point datapath saturates and a float one overflows, either way silently, so the
/// user hears it here, field by field, largest first.
fn warn_out_of_range(name: &str, scene: &sim_target::rt::Scene, numeric: Numeric) {
    use jobs::scene::range::{format_max, out_of_range};
    use protocol::names::Named;
    let format = numeric.spellings()[0];
    for d in out_of_range(scene, numeric) {
        eprintln!(
            "fpgfx: warning: {name}: {}: the {} reaches {:.1}, beyond {format}'s range of \
             ±{}: that part of the frame will saturate; render in a wider format",
            d.field,
            d.what,
            d.value,
            format_max(numeric)
        );
    }
}

/// With `--port rtl:rt --stats`: the core's clock count from the model's schedule of it
/// (`sim_target::rt::core`) beside the RTL's `RT_CYCLES`, and whether the built-in
/// target's frame and planes for the same registers, format and packing agree with the
/// RTL's. Returns the model's saturation count for the frame.
fn model_beside_rtl(
    regs: &Regs,
    numeric: Numeric,
    packing: Packing,
    aovs: Aovs,
    rtl: &RenderOutput,
) -> Result<u64> {
    let scene = sim_target::scene_regs::from_regs(regs).context("the image the core read")?;
    let cycles = sim_target::rt::core::CoreFrame::of(&scene).cycles();
    let mut session = host_cli::session::Session::new(sim_board::in_process::sim_target());
    session
        .handshake()
        .context("handshake with the golden model")?;
    session.timeout = std::time::Duration::from_secs(3600);
    let (model, _) = Renderer::new().frame(&mut session, regs, numeric, packing, aovs)?;
    let differ = model
        .image
        .pixels()
        .zip(rtl.image.pixels())
        .filter(|(a, b)| a != b)
        .count();
    let planes = model.depth == rtl.depth && model.normal == rtl.normal;
    println!(
        "model cycles  {cycles} (the core's schedule, sim_target::rt::core; RTL {} = {:+})",
        rtl.cycles,
        rtl.cycles as i64 - cycles as i64
    );
    println!(
        "model frame   {}",
        match (differ, planes) {
            (0, true) => "identical to the RTL's (colour and AOV planes)".to_string(),
            (0, false) => "colour identical to the RTL's, AOV planes differ".to_string(),
            (n, _) => format!("{n} pixels differ from the RTL's"),
        }
    );
    Ok(model.stats.device.saturations)
}
