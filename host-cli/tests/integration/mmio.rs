//! `--port builtin:mmio`: the controller's register-bus driver (`firmware::MmioBus`) on
//! the model's AXI4-Lite register file must produce exactly the frames of `--port
//! builtin`, whose controller calls the model directly; the register bus changes the
//! transport, never a bit. The model's refusals and a stuck block reach the user as
//! messages, and drivers broken on purpose fail these comparisons.

use host_cli::run::render::{Aovs, Packing, Renderer};
use host_cli::session::{Session, Transport};
use protocol::axi_lite::{self, ctrl, raster};
use protocol::frame::Numeric;
use sim_board::in_process::{
    mmio_target, sim_target, sim_target_mmio, BuiltIn, ModelMmioBus, ModelRegisters,
};
use sim_target::mmio::{Liveness, RegisterError, RegisterFile};

use crate::common::{example, ok, tmp};

fn bytes(path: &str) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// `fpgfx --port PORT ARGS… -o OUT` on both built-in targets; returns both stdouts
/// after checking the two files are byte for byte the same.
fn same_output(args: &[&str], out: &str) -> (String, String) {
    let mut stdouts = Vec::new();
    let mut files = Vec::new();
    for port in ["builtin", "builtin:mmio"] {
        let file = tmp(&format!("{}-{out}", port.replace(':', "-")));
        let run = ok(&[&["--port", port], args, &["-o", &file]].concat());
        stdouts.push(run.stdout);
        files.push(bytes(&file));
    }
    assert!(!files[0].is_empty());
    assert!(
        files[0] == files[1],
        "{args:?}: builtin:mmio wrote other bytes than builtin"
    );
    (stdouts.remove(0), stdouts.remove(0))
}

/// The value after `label` on the `--stats` line that starts with it.
fn stat(stdout: &str, label: &str) -> u64 {
    stdout
        .lines()
        .find(|l| l.starts_with(label))
        .and_then(|l| l[label.len()..].split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no {label:?} in {stdout}"))
}

#[test]
fn mmio_renders_the_reference_scene_as_builtin_does() {
    let scene = example("reference.toml");
    for numeric in ["q16.16", "f32", "q8.24"] {
        let (a, b) = same_output(
            &[
                "render",
                &scene,
                "--size",
                "48x27",
                "--numeric",
                numeric,
                "--stats",
            ],
            &format!("ref-{numeric}.png"),
        );
        for label in ["registers", "board time", "saturations"] {
            let line = |s: &str| s.lines().find(|l| l.starts_with(label)).map(str::to_owned);
            assert_eq!(line(&a), line(&b), "{numeric}: {label} differs");
        }
        // The saturation counter crosses the register bus too: Q8.24 clips the
        // reference scene's squared distances by the thousand, floats never clip.
        let saturations = stat(&b, "saturations");
        match numeric {
            "q8.24" => assert!(saturations > 1000, "{numeric}: {b}"),
            "f32" => assert_eq!(saturations, 0, "{numeric}: {b}"),
            _ => {}
        }
        assert!(
            stat(&b, "registers") > 200,
            "the first frame sends the scene: {b}"
        );
    }
}

#[test]
fn mmio_draws_every_primitive_as_builtin_does() {
    let file = example("raster/gallery.toml");
    let (a, b) = same_output(&["raster", &file, "--stats"], "gallery.png");
    // What the FPGA did is the same whichever bus fed it; FIFO stalls are the bus's.
    for label in ["commands", "bus records", "fragments", "FPGA cycles"] {
        assert_eq!(stat(&a, label), stat(&b, label), "{label}:\n{a}\n{b}");
    }
    assert!(stat(&b, "fragments") > 1000, "{b}");
    assert!(stat(&b, "commands") >= 5, "{b}");
}

#[test]
fn mmio_animates_as_builtin_does() {
    let script = example("anim/viray.rhai");
    let mut runs = Vec::new();
    for port in ["builtin", "builtin:mmio"] {
        let pngs = tmp(&format!("{}-v-%02d.png", port.replace(':', "-")));
        let run = ok(&[
            "--port", port, "animate", &script, "--frames", "3", "--size", "48x27", "-o", &pngs,
        ]);
        let frames: Vec<Vec<u8>> = (0..3)
            .map(|i| bytes(&pngs.replace("%02d", &format!("{i:02}"))))
            .collect();
        runs.push((run.stdout, frames));
    }
    assert!(runs[0].1 == runs[1].1, "an animation frame differs");
    assert!(runs[1].1[0] != runs[1].1[2], "the animation does not move");
    // The raster block animated too: a GIF, byte for byte.
    same_output(
        &["animate", &example("anim/spin.rhai"), "--frames", "3"],
        "spin.gif",
    );
}

#[test]
fn mmio_port_is_named_in_the_help_and_the_hello() {
    let help = ok(&["render", "--help"]).stdout;
    assert!(help.contains("builtin:mmio"), "{help}");
    let mut session = Session::new(sim_target_mmio().expect("the model probes"));
    let peer = session.handshake().expect("handshake");
    assert!(peer.ident.contains("AXI4-Lite"), "{}", peer.ident);
}

/// The model's register file for the WIDE layout, and its capabilities.
fn model() -> (RegisterFile, protocol::frame::Caps) {
    let device = sim_target::Device::new(&protocol::bus::WIDE);
    let caps = device.caps();
    (RegisterFile::new(device), caps)
}

fn reference_scene() -> sim_target::rt::Scene {
    let text = std::fs::read_to_string(example("reference.toml")).expect("reference scene");
    let mut scene = jobs::scene::parse(&text, "reference.toml").expect("parses");
    scene.width = 32;
    scene.height = 18;
    scene
}

fn reference_regs() -> sim_target::scene_regs::Regs {
    jobs::scene::to_regs(&reference_scene()).expect("fits")
}

/// An error with its causes, as the tool prints it (`{:#}`): the messages the tests look
/// for are often the cause's (the driver's register, the model's refusal).
fn chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        text = format!("{text}: {c}");
        cause = c.source();
    }
    text
}

/// One frame of the reference scene, or the session's message.
fn render<T: Transport>(target: T) -> Result<Vec<u8>, String> {
    let mut session = Session::new(target);
    session.timeout = std::time::Duration::from_secs(20);
    session.handshake().map_err(|e| chain(&e))?;
    Renderer::new()
        .frame(
            &mut session,
            &reference_regs(),
            Numeric::Q16_16,
            Packing::Rgb888,
            Aovs::default(),
        )
        .map(|(out, _)| out.image.into_raw())
        .map_err(|e| chain(&e))
}

/// The gallery's every-primitive job, or the session's message.
fn draw<T: Transport>(target: T) -> Result<Vec<u8>, String> {
    let path = example("raster/gallery.toml");
    let text = std::fs::read_to_string(&path).expect("gallery");
    let job = jobs::raster::parse(&text, &path).expect("parses");
    let mut session = Session::new(target);
    session.handshake().map_err(|e| chain(&e))?;
    host_cli::run::raster::run(&mut session, &job, &path)
        .map(|out| out.image.into_raw())
        .map_err(|e| chain(&e))
}

/// A stuck block ends the session with the driver's error naming the register, within
/// the poll bound, for both ways of being stuck.
#[test]
fn mmio_stuck_block_is_an_error_within_the_bound() {
    for (liveness, waiting_for) in [
        (Liveness::NeverDone, "ap_done not seen after"),
        (Liveness::IgnoresStart, "ap_start taken"),
    ] {
        let (mut regs, caps) = model();
        regs.set_liveness(liveness);
        let mut target =
            mmio_target(ModelRegisters(regs), caps, &protocol::bus::WIDE).expect("probes");
        target.bus().poll_limit = 2000;
        let started = std::time::Instant::now();
        let err = render(target).expect_err("a stuck block cannot render");
        assert!(err.contains("AP_CTRL (0x0000)"), "{liveness:?}: {err}");
        assert!(err.contains(waiting_for), "{liveness:?}: {err}");
        assert!(
            started.elapsed() < std::time::Duration::from_secs(10),
            "{liveness:?}: took {:?}",
            started.elapsed()
        );
    }
}

/// The model's refusals through the driver: what the host prints.
#[test]
fn mmio_model_refusals_reach_the_host() {
    // A numeric code the model has no format for, forced by a bus that rewrites it.
    struct BadNumeric(ModelRegisters);
    impl firmware::Registers for BadNumeric {
        type Error = RegisterError;
        fn read(&mut self, addr: u32) -> Result<u32, RegisterError> {
            self.0 .0.read(addr)
        }
        fn write(&mut self, addr: u32, value: u32) -> Result<(), RegisterError> {
            let value = if addr == axi_lite::NUMERIC { 9 } else { value };
            self.0 .0.write(addr, value)
        }
    }
    let (regs, caps) = model();
    let target =
        mmio_target(BadNumeric(ModelRegisters(regs)), caps, &protocol::bus::WIDE).expect("probes");
    let err = render(target).expect_err("refused");
    assert!(err.contains("NUMERIC = 0x9"), "{err}");
    assert!(err.contains("no number format"), "{err}");
}

/// A driver that pushes records without the packet commit, and one that does not wait
/// for ap_done, are caught by the comparisons above.
#[test]
fn mmio_broken_drivers_fail_the_comparison() {
    let want = draw(sim_target()).expect("builtin draws");
    assert_eq!(draw(sim_target_mmio().expect("probes")), Ok(want.clone()));

    struct NoCommit(ModelRegisters);
    impl firmware::Registers for NoCommit {
        type Error = RegisterError;
        fn read(&mut self, addr: u32) -> Result<u32, RegisterError> {
            self.0 .0.read(addr)
        }
        fn write(&mut self, addr: u32, value: u32) -> Result<(), RegisterError> {
            // Dropping the commit leaves the records staged: the next packet's records
            // overflow the staging, or nothing is drawn.
            if addr == raster::COMMIT {
                return Ok(());
            }
            self.0 .0.write(addr, value)
        }
    }
    let (regs, caps) = model();
    let broken =
        mmio_target(NoCommit(ModelRegisters(regs)), caps, &protocol::bus::WIDE).expect("probes");
    assert_ne!(
        draw(broken),
        Ok(want),
        "a driver without COMMIT drew the gallery"
    );

    struct NoWait(ModelRegisters);
    impl firmware::Registers for NoWait {
        type Error = RegisterError;
        fn read(&mut self, addr: u32) -> Result<u32, RegisterError> {
            // The driver sees ap_done at once, as one that never polled would assume.
            let word = self.0 .0.read(addr)?;
            Ok(match addr {
                axi_lite::AP_CTRL => word | ctrl::AP_DONE,
                _ => word,
            })
        }
        fn write(&mut self, addr: u32, value: u32) -> Result<(), RegisterError> {
            self.0 .0.write(addr, value)
        }
    }
    let (regs, caps) = model();
    let broken =
        mmio_target(NoWait(ModelRegisters(regs)), caps, &protocol::bus::WIDE).expect("probes");
    let err = render(broken).expect_err("a read-back before ap_done is refused");
    assert!(
        err.contains("while the ray tracer is still running"),
        "{err}"
    );
}

/// The bus words of a frame, the figures docs/axi-lite.md quotes: the scene words that
/// changed, three start writes, the polls, and a word read per four read-back bytes.
#[test]
fn mmio_bus_words_per_frame() {
    use sim_target::mmio::DONE_AFTER_POLLS;
    let regs = reference_regs();
    let mut session = Session::new(sim_target_mmio().expect("probes"));
    session.handshake().expect("handshake");
    let mut renderer = Renderer::new();
    let mut frame = |session: &mut Session<BuiltIn<ModelMmioBus>>, regs| {
        let before = session.transport().bus().accesses();
        let (_, words) = renderer
            .frame(
                session,
                regs,
                Numeric::Q16_16,
                Packing::Rgb888,
                Aovs::default(),
            )
            .expect("renders");
        let after = session.transport().bus().accesses();
        (
            words as u64,
            after.writes - before.writes,
            after.reads - before.reads,
        )
    };
    let (words, writes, reads) = frame(&mut session, &regs);
    let rgb_words = (32 * 18 * 3) / 4;
    // Scene words, NUMERIC + AOVS + AP_CTRL, and the read-back request's four registers
    // and its page.
    assert_eq!(writes, words + 3 + 4 + 1, "first frame");
    // The start's check and the polls up to ap_done, the two 64-bit results, READ_LEN,
    // the window, and the counters the renderer's statistics ask for.
    let polls = u64::from(DONE_AFTER_POLLS) + 1;
    let counters = 2 * protocol::axi_lite::COUNTERS.len() as u64;
    let frame_reads = polls + 4 + 1 + rgb_words + counters;
    assert_eq!(reads, frame_reads, "first frame");
    let mut scene = reference_scene();
    scene.objects[1].translate[1] += 0.25;
    let moved = jobs::scene::to_regs(&scene).expect("fits");
    let (words, writes, reads) = frame(&mut session, &moved);
    assert_eq!(
        (words, writes),
        (1, 1 + 3),
        "a later frame: its changes and the start"
    );
    assert_eq!(reads, frame_reads);
}
