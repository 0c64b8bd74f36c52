//! One render of a scene, for instruction counts that do not depend on the machine's load
//! (`perf stat -e instructions:u`, or callgrind) when the shared machine is too busy for
//! wall-clock figures:
//! `cargo run --release -p sim-target --example rt_once -- SCENE.toml FORMAT [WxH]
//! [general|scalar|nocull] [seed] [aovs] [spheres|noshadows|notextures|depth1]` (the last: a feature
//! subset, `rt::Subset`; `aovs` also fills the depth and normal planes, as the device does).

use sim_target::rt::{self, Kernel, RenderOptions, Subset};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [path, format, rest @ ..] = args.as_slice() else {
        return Err("usage: rt_once SCENE.toml FORMAT [WxH] [general|scalar|nocull] [seed] [aovs] [spheres|noshadows|notextures|depth1]".into());
    };
    let text = std::fs::read_to_string(path)?;
    let mut scene = jobs::scene::parse(&text, path)?;
    let numeric: rt::Numeric = format.parse()?;
    let mut opts = RenderOptions {
        numeric,
        ..Default::default()
    };
    for a in rest {
        match a.as_str() {
            "general" => opts.kernel = Kernel::General,
            "scalar" => opts.kernel = Kernel::Scalar,
            "nocull" => opts.cull = false,
            "seed" => opts.math = rt::Math::SEED,
            "aovs" => opts.aovs = true,
            "spheres" => scene = Subset::SpheresFlat.apply(&scene),
            "noshadows" => scene = Subset::NoShadows.apply(&scene),
            "notextures" => scene = Subset::NoTextures.apply(&scene),
            "depth1" => scene = Subset::Depth1.apply(&scene),
            size => {
                let (w, h) = size.split_once('x').ok_or_else(|| {
                    format!("expected WxH, general, scalar or nocull, got {size}")
                })?;
                opts.size = Some((w.parse()?, h.parse()?));
            }
        }
    }
    let frame = rt::render(&scene, &opts)?;
    let s = frame.stats;
    println!(
        "{numeric:?} {}x{} kernel {:?} cull {}: {:.3} s, {} rays nominal ({:.2} Mrays/s), {} traced ({:.2} Mrays/s), image hash {:016x}",
        frame.width,
        frame.height,
        opts.kernel,
        opts.cull,
        s.seconds,
        s.nominal_rays,
        s.nominal_mrays_per_s(),
        s.rays(),
        s.mrays_per_s(),
        frame
            .rgb8
            .iter()
            .fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ *b as u64).wrapping_mul(0x100_0000_01b3))
    );
    Ok(())
}
