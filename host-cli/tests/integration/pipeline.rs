//! The host → link → controller → bus path, with a recording FPGA bus: what reaches the
//! FPGA is exactly what the file said, errors name the command, and a slow bus stalls the
//! pipeline instead of losing anything.

use std::convert::Infallible;

use firmware::FpgaBus;
use host_cli::session::{Session, SessionError};
use protocol::bus::{unpack, BusLayout, WIDE};
use protocol::frame::{
    Caps, DeviceCounters, ErrorCode, FrameDone, NumericSet, ReadRequest, StartFrame,
};
use protocol::raster::{RasterCmd, RasterSetup};
use sim_board::in_process::BuiltIn;

use crate::common;

/// An FPGA that records packets and drains its FIFO `drain` records per `wait()`.
struct Recorder {
    layout: &'static BusLayout,
    capacity: usize,
    queued: usize,
    drain: usize,
    packets: Vec<(u8, Vec<u64>)>,
    setup: Option<RasterSetup>,
    waits: usize,
}

impl Recorder {
    fn new(capacity: usize, drain: usize) -> Self {
        Self {
            layout: &WIDE,
            capacity,
            queued: 0,
            drain,
            packets: Vec::new(),
            setup: None,
            waits: 0,
        }
    }

    fn decoded(&self) -> Vec<RasterCmd> {
        let sub = self.setup.map_or(8, |s| s.subpixel_bits);
        self.packets
            .iter()
            .map(|(ch, r)| {
                unpack(self.layout, *ch, r, sub)
                    .expect("packet decodes")
                    .cmd
            })
            .collect()
    }
}

impl FpgaBus for Recorder {
    type Error = Infallible;
    fn fifo_free(&mut self) -> Result<usize, Infallible> {
        Ok(self.capacity - self.queued)
    }
    fn push_packet(&mut self, channel: u8, records: &[u64]) -> Result<(), Infallible> {
        assert!(records.len() <= self.capacity - self.queued, "FIFO overrun");
        self.queued += records.len();
        self.packets.push((channel, records.to_vec()));
        Ok(())
    }
    fn wait(&mut self) -> Result<(), Infallible> {
        self.waits += 1;
        self.queued = self.queued.saturating_sub(self.drain);
        Ok(())
    }
    fn idle(&mut self) -> Result<bool, Infallible> {
        Ok(self.queued == 0)
    }
    fn raster_setup(&mut self, setup: &RasterSetup) -> Result<(), Infallible> {
        self.setup = Some(*setup);
        Ok(())
    }
    fn write_regs(&mut self, _: u16, _: &[u32]) -> Result<(), Infallible> {
        Ok(())
    }
    fn write_texels(&mut self, _: u32, _: &[u8]) -> Result<(), Infallible> {
        Ok(())
    }
    fn start(&mut self, _: &StartFrame) -> Result<(), Infallible> {
        Ok(())
    }
    fn stop(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
    fn poll_done(&mut self) -> Result<Option<FrameDone>, Infallible> {
        Ok(None)
    }
    fn read_len(&mut self, req: &ReadRequest) -> Result<Option<u32>, Infallible> {
        Ok(Some(req.rect.area() * req.format.bytes_per_pixel() as u32))
    }
    fn read(&mut self, _: &ReadRequest, offset: u32, out: &mut [u8]) -> Result<(), Infallible> {
        for (i, b) in out.iter_mut().enumerate() {
            *b = ((offset as usize + i) * 7 % 251) as u8;
        }
        Ok(())
    }
    fn counters(&mut self) -> Result<DeviceCounters, Infallible> {
        Ok(DeviceCounters::default())
    }
    fn reset(&mut self) -> Result<(), Infallible> {
        self.queued = 0;
        Ok(())
    }
}

fn caps() -> Caps {
    Caps {
        raster: true,
        ray_trace: false,
        numeric: NumericSet::default(),
        pixel_formats: 1,
        max_width: 4096,
        max_height: 4096,
        max_subpixel_bits: 8,
        queue_depth: 4,
        fifo_depth: 512,
        max_objects: 8,
        max_lights: 2,
        texture_words: 65536,
        raster_layout: None,
        float_regs: NumericSet::default(),
        rt_build: protocol::frame::RtBuild::FULL,
        link_payload: 0,
    }
}

fn many_triangles(n: usize) -> String {
    let mut s = String::from("size = [320, 240]\n");
    for i in 0..n {
        let x = (i % 300) as f64 + 0.25;
        s += &format!(
            "[[cmd]]\nop = \"triangle\"\nv = [[{x}, 1.5], [{}, 100.0], [10.0, 200.75]]\ncolor = \"#{:02x}8000\"\n",
            x + 13.0,
            i % 256
        );
    }
    s
}

#[test]
fn every_command_reaches_the_fifo_in_order_under_back_pressure() {
    let text = many_triangles(200);
    let job = jobs::raster::parse(&text, "tri.toml").expect("valid");
    // A FIFO of 4 records draining 1 per wait: the controller must stall, never overrun.
    let mut session = Session::new(BuiltIn::new(Recorder::new(4, 1), caps(), &WIDE));
    session.handshake().expect("handshake");
    let out = host_cli::run::raster::run(&mut session, &job, "tri.toml").expect("runs");
    let bus = session.transport().bus();
    assert_eq!(
        bus.decoded(),
        job.cmds,
        "the FPGA saw exactly the file's commands"
    );
    assert!(bus.waits > 200, "a slow FIFO must stall the controller");
    assert_eq!(out.stats.device.commands, 200);
    assert!(out.stats.device.fifo_stalls > 0);
    // Read-back crossed the link intact (the recorder's pattern, CRC checked).
    let raw = out.image.into_raw();
    assert_eq!(raw.len(), 320 * 240 * 3);
    assert!(raw
        .iter()
        .enumerate()
        .all(|(i, &b)| b == (i * 7 % 251) as u8));
}

#[test]
fn refusals_name_the_command() {
    // The FITkit layout has no circle command. The controller names its layout in its
    // hello, so the host refuses the circle by its place in the file before sending
    // anything (the controller would refuse it too, by index, but only after drawing the
    // commands before it).
    let text = "size = [64, 64]\n[[cmd]]\nop = \"clear\"\ncolor = \"#000000\"\n[[cmd]]\nop = \"circle\"\ncenter = [5.0, 5.0]\nradius = 3.0\ncolor = \"#ffffff\"\n";
    let job = jobs::raster::parse(text, "c.toml").expect("valid");
    let mut session = Session::new(BuiltIn::new(
        Recorder::new(512, 512),
        caps(),
        &protocol::bus::FITKIT,
    ));
    session.handshake().expect("handshake");
    let err = host_cli::run::raster::run(&mut session, &job, "c.toml")
        .expect_err("FITkit has no circles");
    match &err {
        SessionError::Unsupported(what) => {
            assert!(
                what.contains("c.toml: cmd[1] (circle)") && what.contains("fitkit layout"),
                "{err}"
            );
        }
        other => panic!("expected the host's refusal, got {other}"),
    }
    assert!(
        session.transport().bus().setup.is_none(),
        "nothing may reach the FPGA"
    );
}

#[test]
fn capability_refusal_before_anything_is_sent() {
    let job = jobs::raster::parse("size = [4000, 10]", "big.toml").expect("valid");
    let mut small = caps();
    small.max_width = 1024;
    let mut session = Session::new(BuiltIn::new(Recorder::new(512, 512), small, &WIDE));
    session.handshake().expect("handshake");
    let err = host_cli::run::raster::run(&mut session, &job, "big.toml").expect_err("too wide");
    assert!(err.to_string().contains("4000×10 exceeds"), "{err}");
    assert!(session.transport().bus().setup.is_none());
}

/// The whole built-in path (link, controller, WIDE packing, FIFO, device) must draw
/// exactly what the raster block draws when called directly with the same commands.
#[test]
fn built_in_target_matches_the_raster_block_exactly() {
    let text = common::every_primitive(192, 128, "");
    let job = jobs::raster::parse(&text, "g.toml").expect("valid");
    let mut session = Session::new(sim_board::in_process::sim_target());
    session.handshake().expect("handshake");
    let out = host_cli::run::raster::run(&mut session, &job, "g.toml").expect("runs");

    let (width, height) = (job.setup.width.into(), job.setup.height.into());
    let mut direct = sim_target::raster::Raster::new(width, height, &job.setup).expect("setup");
    for cmd in &job.cmds {
        direct.draw(cmd).expect("draws");
    }
    let want = direct.framebuffer().rgb();
    let got = out.image.as_raw();
    let diff = want.iter().zip(got).filter(|(a, b)| a != b).count();
    assert_eq!(diff, 0, "{diff} bytes differ between built-in and direct");
    assert_eq!(out.stats.device.fragments, direct.stats().fragments);
}

fn small_reference() -> sim_target::rt::Scene {
    let text = std::fs::read_to_string(common::example("reference.toml")).expect("reference scene");
    let mut scene = jobs::scene::parse(&text, "reference.toml").expect("reference parses");
    scene.width = 96;
    scene.height = 54;
    scene
}

/// Registers over the link, render on the device, read-back: identical to rendering the
/// register image's scene directly; a second frame sends only what changed.
#[test]
fn built_in_render_matches_direct_and_sends_only_changes() {
    use host_cli::run::render::{Aovs, Packing, Renderer};
    use jobs::scene::to_regs;
    use sim_target::scene_regs::from_regs;
    let mut scene = small_reference();
    let regs = to_regs(&scene).expect("fits");
    let mut session = Session::new(sim_board::in_process::sim_target());
    session.handshake().expect("handshake");
    let mut renderer = Renderer::new();
    let aovs = Aovs {
        depth: true,
        normal: true,
    };
    let numeric = protocol::frame::Numeric::Q16_16;
    let (out, words) = renderer
        .frame(&mut session, &regs, numeric, Packing::Rgb888, aovs)
        .expect("renders");
    let direct = sim_target::rt::render(
        &from_regs(&regs).expect("decodes"),
        &sim_target::rt::RenderOptions {
            numeric,
            aovs: true,
            ..Default::default()
        },
    )
    .expect("renders");
    assert_eq!(
        out.image.as_raw(),
        &direct.rgb8,
        "colour differs from direct render"
    );
    assert_eq!(out.depth.as_ref(), direct.depth.as_ref());
    assert_eq!(out.normal.as_ref(), direct.normal.as_ref());
    assert_eq!(out.rays, direct.stats.rays());
    assert!(
        words > 200,
        "first frame writes the whole scene ({words} words)"
    );

    // Move one object along x: one register word crosses the link.
    scene.objects[2].translate[0] += 0.5;
    let moved = to_regs(&scene).expect("fits");
    let words = common::words_for_next_frame(&mut renderer, &mut session, &moved, numeric);
    assert_eq!(words, 1, "only translate.x changed");
}

/// A frame started without AOVs (`StartFrame::aovs`) has no depth or normal plane: the
/// device skips them, and reading them back is refused with an error that names the
/// read-back instead of returning zeros; the colour is the same either way.
#[test]
fn a_frame_without_aovs_refuses_their_read_back() {
    use host_cli::run::render::{Aovs, Packing, Renderer};
    use protocol::frame::{PixelFormat, Plane, ReadRequest, Rect};
    let regs = jobs::scene::to_regs(&small_reference()).expect("fits");
    let numeric = protocol::frame::Numeric::F32;
    let mut session = Session::new(sim_board::in_process::sim_target());
    session.handshake().expect("handshake");
    let mut renderer = Renderer::new();
    let (plain, _) = renderer
        .frame(
            &mut session,
            &regs,
            numeric,
            Packing::Rgb888,
            Aovs::default(),
        )
        .expect("renders");
    assert!(plain.depth.is_none() && plain.normal.is_none());
    assert_eq!(plain.read_back.payload_bytes, 96 * 54 * 3, "colour only");
    let rect = Rect {
        x: 0,
        y: 0,
        w: 96,
        h: 54,
    };
    for (plane, format) in [
        (Plane::Depth, PixelFormat::DepthF32),
        (Plane::Normal, PixelFormat::NormalF32),
    ] {
        let err = session
            .read_back(ReadRequest {
                plane,
                rect,
                format,
            })
            .expect_err("no such plane");
        let text = format!("{err:#}");
        assert!(
            text.contains("read-back") && text.contains(&format!("{plane:?}")),
            "{plane:?}: {text}"
        );
    }
    let aovs = Aovs {
        depth: true,
        normal: true,
    };
    let (with, _) = renderer
        .frame(&mut session, &regs, numeric, Packing::Rgb888, aovs)
        .expect("renders");
    assert_eq!(with.image, plain.image, "AOVs change no colour");
    assert_eq!(with.depth.map(|d| d.len()), Some(96 * 54));
    assert_eq!(with.normal.map(|n| n.len()), Some(96 * 54 * 3));
    assert_eq!(with.read_back.payload_bytes, 96 * 54 * (3 + 4 + 12));
}

/// A seed outside the framebuffer (which the file parser also refuses) is refused by the
/// controller itself, so a foreign host cannot make the FPGA fault.
#[test]
fn controller_refuses_a_seed_outside_the_frame() {
    use protocol::frame::HostFrame;
    use protocol::raster::{Connectivity, Pixel, Rgb, SeedFill};
    let job = jobs::raster::parse("size = [16, 16]", "s.toml").expect("valid");
    let mut session = Session::new(sim_board::in_process::sim_target());
    session.handshake().expect("handshake");
    session
        .send(
            &HostFrame::RasterSetup(job.setup),
            Box::new(|_| "setup".into()),
        )
        .expect("sent");
    let mut cmds = heapless::Vec::new();
    let fill = RasterCmd::Fill(SeedFill {
        seed: Pixel { x: 16, y: 0 },
        color: Rgb::new(1, 2, 3),
        connectivity: Connectivity::Four,
    });
    cmds.push(fill).expect("capacity");
    session
        .send(
            &HostFrame::Raster(cmds),
            Box::new(|i| format!("batch entry {i}")),
        )
        .expect("sent");
    let err = session.sync().expect_err("refused");
    match err {
        SessionError::Refused { what, code, .. } => {
            assert_eq!(code, ErrorCode::OutOfRange);
            assert_eq!(what, "batch entry 0");
        }
        other => panic!("expected a refusal, got {other}"),
    }
    // The board is still alive.
    session.sync().expect("still answering");
}
