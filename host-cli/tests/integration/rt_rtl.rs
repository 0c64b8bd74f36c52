//! The ray-casting core's RTL as a target: `fpgfx --port rtl:rt` (the controller in
//! process, its AXI4-Lite register driver on the Verilated `rt_device`'s pins, the frame
//! read back through the device's own window). Frames and AOV planes must equal
//! `--port builtin --numeric q16.16` byte for byte; `--stats` must put the model's
//! schedule of the core beside the RTL's count, equal; what the core does not build is
//! refused naming the field, or reduced with `--fit`.

use crate::common::{assert_model_cycles_equal, example, fails, ok, tmp};

/// `hw/rt-core/scenes/core.toml`: what the core builds, unreduced.
pub(crate) fn core_scene() -> String {
    crate::common::workspace()
        .join("hw/rt-core/scenes/core.toml")
        .display()
        .to_string()
}

fn bytes(path: &str) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn rtl_rt_renders_the_core_scene_as_builtin_does() {
    let scene = core_scene();
    let mut files = Vec::new();
    for port in ["builtin", "rtl:rt"] {
        let tag = port.replace(':', "-");
        let (png, depth, normal) = (
            tmp(&format!("core-{tag}.png")),
            tmp(&format!("core-{tag}-d.pfm")),
            tmp(&format!("core-{tag}-n.pfm")),
        );
        ok(&[
            "--port",
            port,
            "render",
            &scene,
            "--numeric",
            "q16.16",
            "--size",
            "40x24",
            "--aov",
            &format!("depth={depth},normal={normal}"),
            "-o",
            &png,
        ]);
        files.push([bytes(&png), bytes(&depth), bytes(&normal)]);
    }
    for (i, what) in ["frame", "depth plane", "normal plane"].iter().enumerate() {
        assert!(!files[0][i].is_empty(), "{what}: nothing written");
        assert!(
            files[0][i] == files[1][i],
            "{what}: rtl:rt differs from builtin"
        );
    }
}

#[test]
fn rtl_rt_stats_put_the_models_count_beside_the_rtls() {
    let run = ok(&[
        "--port",
        "rtl:rt",
        "render",
        &example("reference.toml"),
        "--fit",
        "--numeric",
        "q16.16",
        "--size",
        "32x18",
        "--stats",
        "--aov",
        &format!("depth={}", tmp("ref-d.pfm")),
        "-o",
        &tmp("ref.png"),
    ]);
    assert_model_cycles_equal(&run.stdout);
    assert!(
        run.stdout
            .contains("model frame   identical to the RTL's (colour and AOV planes)"),
        "{}",
        run.stdout
    );
    // the core's counter of clipped results is not a count: the line says so
    assert!(
        run.stdout
            .contains("saturations   not counted by the core (its counter reads 0); the model"),
        "{}",
        run.stdout
    );
    // --fit says what the reference scene lost, by field
    for what in [
        "spot light → point light",
        "texture removed",
        "render.depth",
    ] {
        assert!(run.stderr.contains(what), "{what}: {}", run.stderr);
    }
}

#[test]
fn rtl_rt_refuses_what_the_core_does_not_build() {
    let err = fails(&[
        "--port",
        "rtl:rt",
        "render",
        &example("reference.toml"),
        "--numeric",
        "q16.16",
        "-o",
        &tmp("never.png"),
    ]);
    assert!(err.contains("a spot light"), "{err}");
    let err = fails(&[
        "--port",
        "rtl:rt",
        "render",
        &core_scene(),
        "--numeric",
        "f32",
        "-o",
        &tmp("never-f32.png"),
    ]);
    assert!(err.to_lowercase().contains("f32"), "{err}");
    let help = ok(&["render", "--help"]).stdout;
    assert!(help.contains("rtl:rt"), "{help}");
}

#[test]
fn rtl_rt_animates_a_fitted_script() {
    let pngs = tmp("viray-%02d.png");
    ok(&[
        "--port",
        "rtl:rt",
        "animate",
        &example("anim/viray.rhai"),
        "--fit",
        "--numeric",
        "q16.16",
        "--frames",
        "3",
        "--size",
        "24x14",
        "-o",
        &pngs,
    ]);
    let frames: Vec<Vec<u8>> = (0..3)
        .map(|i| bytes(&pngs.replace("%02d", &format!("{i:02}"))))
        .collect();
    assert!(frames[0] != frames[2], "the animation does not move");
}

/// A memory that never takes the core's records holds the core for good, so `ap_done`
/// never rises: the driver's wait ends within its poll bound with the register named,
/// and the session reports it.
#[test]
fn rtl_rt_stuck_memory_is_an_error_naming_the_register() {
    use host_cli::run::render::{Aovs, Packing, Renderer};
    use host_cli::session::Session;
    use rt_core_rtl_sim::{Device, Jitter};

    let device = Device::new(Jitter {
        seed: 1,
        max_delay: 0,
        mem_busy_percent: 100,
    })
    .expect("Verilated rt_device");
    let mut target = sim_board::rt_rtl::rt_rtl_target_on(device).expect("the core probes");
    target.bus().poll_limit = 2000;
    let mut session = Session::new(target);
    session.timeout = std::time::Duration::from_secs(60);
    session.handshake().expect("handshake");
    let text = std::fs::read_to_string(core_scene()).expect("core.toml");
    let mut scene = jobs::scene::parse(&text, "core.toml").expect("parses");
    (scene.width, scene.height) = (8, 6);
    let regs = jobs::scene::to_regs(&scene).expect("fits");
    let started = std::time::Instant::now();
    let err = match Renderer::new().frame(
        &mut session,
        &regs,
        protocol::frame::Numeric::Q16_16,
        Packing::Rgb888,
        Aovs::default(),
    ) {
        Ok(_) => panic!("a core whose memory never takes a record cannot finish"),
        Err(e) => format!("{:#}", anyhow::Error::from(e)),
    };
    assert!(err.contains("AP_CTRL (0x0000)"), "{err}");
    assert!(err.contains("ap_done not seen after 2000 polls"), "{err}");
    assert!(
        started.elapsed() < std::time::Duration::from_secs(30),
        "took {:?}",
        started.elapsed()
    );
}

/// An access the device does not have answers SLVERR, and the driver's error names the
/// register (or the window) it went to.
#[test]
fn rtl_rt_slverr_names_the_register() {
    use firmware::Registers;
    use protocol::axi_lite::{self, raster, sys};
    use rt_core_rtl_sim::{Device, Jitter};
    use sim_board::rt_rtl::RtlRegisters;

    let mut regs = RtlRegisters(Device::new(Jitter::NONE).expect("Verilated rt_device"));
    let cases = [
        (regs.read(raster::CTRL).map(|_| ()), "RASTER_CTRL"),
        (regs.write(sys::ID, 1), "ID"),
        (
            regs.read(axi_lite::READ_BASE).map(|_| ()),
            "the read-back window",
        ),
        (regs.read(0x1_F000).map(|_| ()), "no register of the map"),
    ];
    for (result, name) in cases {
        let e = result.expect_err("the device refuses it").to_string();
        assert!(e.starts_with(name) && e.contains("SLVERR"), "{name}: {e}");
    }
}
