//! The controller on the host, byte for byte: a scripted host drives its own
//! `protocol::link` end against the controller's, and a recording FPGA bus logs every
//! operation. Back-pressure, refusals, resynchronisation, FPGA faults and ViRAY's
//! auto-restart with an animation step are checked against exact expectations.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::convert::Infallible;
use std::rc::Rc;

use firmware::{Controller, ControllerError, FpgaBus};
use heapless::Vec as HVec;
use protocol::bus::{pack, PackOptions, WIDE};
use protocol::frame::{
    decode, encode, Animation, Block, Caps, DeviceCounters, DeviceFrame, ErrorCode, FrameDone,
    Hello, HostFrame, NumericSet, Orbit, Ramp, ReadRequest, RegWrite, StartFrame,
};
use protocol::link::{Event, Link, MAX_FRAME};
use protocol::raster::{
    Aa, AaPattern, Cull, Point, RasterCmd, RasterSetup, Rgb, Shade, Traversal, Triangle,
};
use protocol::MAX_PAYLOAD;

type Queue = Rc<RefCell<VecDeque<u8>>>;

/// The controller's UART.
struct Port {
    rx: Queue,
    tx: Queue,
}

impl embedded_io::ErrorType for Port {
    type Error = Infallible;
}
impl embedded_io::Read for Port {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let mut rx = self.rx.borrow_mut();
        let n = buf.len().min(rx.len());
        for (d, s) in buf.iter_mut().zip(rx.drain(..n)) {
            *d = s;
        }
        Ok(n)
    }
}
impl embedded_io::ReadReady for Port {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(!self.rx.borrow().is_empty())
    }
}
impl embedded_io::Write for Port {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        self.tx.borrow_mut().extend(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Op {
    Push(u8, Vec<u64>),
    Setup,
    Regs(u16, Vec<u32>),
    Start(StartFrame),
    Stop,
    Reset,
}

/// The FPGA's failure, for the fault test.
#[derive(Debug, PartialEq)]
struct Fault;

/// A recording FPGA: a FIFO of `capacity` records draining `drain` per `wait`; frames
/// finish as soon as they start.
struct Bus {
    ops: Vec<Op>,
    capacity: usize,
    queued: usize,
    drain: usize,
    overruns: usize,
    done: VecDeque<FrameDone>,
    fail_pushes: bool,
}

impl Bus {
    fn new(capacity: usize, drain: usize) -> Self {
        Self {
            ops: Vec::new(),
            capacity,
            queued: 0,
            drain,
            overruns: 0,
            done: VecDeque::new(),
            fail_pushes: false,
        }
    }
}

impl FpgaBus for Bus {
    type Error = Fault;
    fn fifo_free(&mut self) -> Result<usize, Fault> {
        Ok(self.capacity - self.queued)
    }
    fn push_packet(&mut self, channel: u8, records: &[u64]) -> Result<(), Fault> {
        if self.fail_pushes {
            return Err(Fault);
        }
        if self.queued + records.len() > self.capacity {
            self.overruns += 1;
        }
        self.queued += records.len();
        self.ops.push(Op::Push(channel, records.to_vec()));
        Ok(())
    }
    fn wait(&mut self) -> Result<(), Fault> {
        self.queued = self.queued.saturating_sub(self.drain);
        Ok(())
    }
    fn idle(&mut self) -> Result<bool, Fault> {
        Ok(self.queued == 0)
    }
    fn raster_setup(&mut self, _: &RasterSetup) -> Result<(), Fault> {
        self.ops.push(Op::Setup);
        Ok(())
    }
    fn write_regs(&mut self, offset: u16, words: &[u32]) -> Result<(), Fault> {
        self.ops.push(Op::Regs(offset, words.to_vec()));
        Ok(())
    }
    fn write_texels(&mut self, _: u32, _: &[u8]) -> Result<(), Fault> {
        Ok(())
    }
    fn start(&mut self, s: &StartFrame) -> Result<(), Fault> {
        self.ops.push(Op::Start(*s));
        self.done.push_back(FrameDone {
            frame_id: s.frame_id,
            cycles: 100,
            work: 10,
        });
        Ok(())
    }
    fn stop(&mut self) -> Result<(), Fault> {
        self.ops.push(Op::Stop);
        Ok(())
    }
    fn poll_done(&mut self) -> Result<Option<FrameDone>, Fault> {
        Ok(self.done.pop_front())
    }
    fn read_len(&mut self, _: &ReadRequest) -> Result<Option<u32>, Fault> {
        Ok(None)
    }
    fn read(&mut self, _: &ReadRequest, _: u32, _: &mut [u8]) -> Result<(), Fault> {
        Ok(())
    }
    fn counters(&mut self) -> Result<DeviceCounters, Fault> {
        Ok(DeviceCounters::default())
    }
    fn reset(&mut self) -> Result<(), Fault> {
        self.ops.push(Op::Reset);
        self.queued = 0;
        Ok(())
    }
}

fn caps() -> Caps {
    Caps {
        raster: true,
        ray_trace: true,
        numeric: NumericSet(u16::MAX),
        pixel_formats: 0xff,
        max_width: 640,
        max_height: 480,
        max_subpixel_bits: 8,
        queue_depth: firmware::INBOX as u16,
        fifo_depth: 512,
        max_objects: 8,
        max_lights: 2,
        texture_words: 4096,
        raster_layout: None,
        float_regs: NumericSet::default(),
        rt_build: protocol::frame::RtBuild::FULL,
        link_payload: 0,
    }
}

/// A scripted host and the controller under test, joined by two byte queues.
struct Rig {
    host: Link,
    controller: Controller<Port, Bus>,
    to_ctrl: Queue,
    from_ctrl: Queue,
    now: u64,
    answers: Vec<DeviceFrame>,
    fpga_errors: usize,
}

impl Rig {
    fn new(bus: Bus, caps: Caps) -> Self {
        let (to_ctrl, from_ctrl) = (Queue::default(), Queue::default());
        let port = Port {
            rx: to_ctrl.clone(),
            tx: from_ctrl.clone(),
        };
        let mut rig = Rig {
            host: Link::new(Default::default()),
            controller: Controller::new(port, bus, caps, &WIDE, "test board"),
            to_ctrl,
            from_ctrl,
            now: 0,
            answers: Vec::new(),
            fpga_errors: 0,
        };
        rig.host.reset(0, 7);
        rig.pump(20);
        rig
    }

    fn bus(&mut self) -> &mut Bus {
        self.controller.engine().bus()
    }

    /// One round: host → bytes → controller → bytes → host.
    fn step(&mut self) {
        let mut out = [0u8; MAX_FRAME];
        while let Some(n) = self.host.poll_transmit(self.now, &mut out) {
            self.to_ctrl.borrow_mut().extend(&out[..n]);
        }
        match self.controller.poll(self.now) {
            Ok(()) => {}
            Err(ControllerError::Fpga(Fault)) => self.fpga_errors += 1,
            Err(ControllerError::Host(never)) => match never {},
        }
        let bytes: Vec<u8> = self.from_ctrl.borrow_mut().drain(..).collect();
        let mut input = &bytes[..];
        loop {
            let (used, event) = self.host.handle_input(self.now, input);
            input = &input[used..];
            match event {
                Some(Event::Data(p)) => self.answers.push(decode(p).expect("answer decodes")),
                None if input.is_empty() => break,
                _ => {}
            }
        }
        self.host.handle_timeout(self.now);
        self.now += 1;
    }

    fn pump(&mut self, rounds: usize) {
        for _ in 0..rounds {
            self.step();
        }
    }

    /// Sends a payload as the host would: when the link refuses (no credit), keep the
    /// line running until it accepts.
    fn send_bytes(&mut self, payload: &[u8]) {
        for _ in 0..10_000 {
            if self.host.send(self.now, payload).is_ok() {
                self.step();
                return;
            }
            self.step();
        }
        panic!("the controller never gave credit");
    }

    fn send(&mut self, frame: &HostFrame) {
        let mut buf = [0u8; MAX_PAYLOAD];
        let bytes = encode(frame, &mut buf).expect("fits").to_vec();
        self.send_bytes(&bytes);
    }

    fn hello(&mut self) {
        self.send(&HostFrame::Hello(Hello::new(Caps::default(), "test host")));
        self.pump(5);
        // The controller names the layout it packs in (the rig's is WIDE), whatever caps
        // it was given, since it is the one packing.
        assert!(
            matches!(self.answers.last(), Some(DeviceFrame::Hello(h))
                if h.caps.raster_layout == Some(protocol::bus::LayoutId::Wide)),
            "{:?}",
            self.answers
        );
        self.answers.clear();
    }

    fn errors(&self) -> Vec<(ErrorCode, u16, u32)> {
        self.answers
            .iter()
            .filter_map(|a| match a {
                DeviceFrame::Error(e) => Some((e.code, e.seq, e.index)),
                _ => None,
            })
            .collect()
    }
}

fn setup(width: u16, height: u16) -> RasterSetup {
    RasterSetup {
        width,
        height,
        subpixel_bits: 4,
        background: Rgb::new(0, 0, 0),
        aa: Aa {
            pattern: AaPattern::None,
            samples: 1,
        },
        cull: Cull::None,
        traversal: Traversal::BoundingBox,
    }
}

fn triangle(i: i32) -> RasterCmd {
    let p = |x: i32, y: i32| Point {
        x: x << 4,
        y: y << 4,
    };
    RasterCmd::Triangle(Triangle {
        v: [p(i % 300, 1), p(i % 300 + 20, 5), p(i % 300 + 3, 40)],
        shade: Shade::Flat(Rgb::new(i as u8, 0, 0)),
        z: None,
        w: None,
        tex: None,
    })
}

/// A FIFO of 4 records that drains one record per wait: the controller stalls on every
/// command, yet all 200 arrive, in order, packed exactly, and the FIFO never overflows.
#[test]
fn slow_bus_back_pressure_loses_nothing() {
    let mut rig = Rig::new(Bus::new(4, 1), caps());
    rig.hello();
    rig.send(&HostFrame::RasterSetup(setup(320, 240)));
    let cmds: Vec<RasterCmd> = (0..200).map(triangle).collect();
    for batch in cmds.chunks(protocol::frame::RASTER_BATCH) {
        rig.send(&HostFrame::Raster(HVec::from_slice(batch).expect("batch")));
    }
    rig.pump(50);
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());
    let pushed: Vec<Vec<u64>> = rig
        .bus()
        .ops
        .iter()
        .filter_map(|o| match o {
            Op::Push(_, r) => Some(r.clone()),
            _ => None,
        })
        .collect();
    let opts = PackOptions {
        subpixel_bits: 4,
        clear: false,
    };
    let want: Vec<Vec<u64>> = cmds
        .iter()
        .map(|c| pack(&WIDE, c, opts).expect("packs").to_vec())
        .collect();
    assert_eq!(pushed, want, "FIFO contents differ from the commands sent");
    assert_eq!(rig.bus().overruns, 0, "the FIFO overflowed");
    let link = rig.host.counters();
    assert_eq!(link.resent, 0);
    assert_eq!(rig.fpga_errors, 0);
}

#[test]
fn requests_before_the_handshake_are_refused() {
    let mut rig = Rig::new(Bus::new(64, 64), caps());
    rig.send(&HostFrame::RasterSetup(setup(16, 16)));
    rig.pump(5);
    assert_eq!(rig.errors(), vec![(ErrorCode::Handshake, 0, 0)]);
    assert!(rig.bus().ops.is_empty(), "nothing may reach the FPGA");
}

/// An undecodable payload and values out of range each get an error frame naming the
/// request (and the command inside a batch); the session goes on.
#[test]
fn malformed_and_out_of_range_requests_are_answered() {
    let mut rig = Rig::new(Bus::new(64, 64), caps());
    rig.hello(); // seq 0
    rig.send_bytes(&[0xff, 0xff, 0xff, 0xff]); // seq 1
    rig.send(&HostFrame::RasterSetup(setup(641, 16))); // seq 2: wider than max_width
    rig.send(&HostFrame::RasterSetup(setup(32, 32))); // seq 3: fine
    let fill = RasterCmd::Fill(protocol::raster::SeedFill {
        seed: protocol::raster::Pixel { x: 5, y: 32 },
        color: Rgb::new(1, 2, 3),
        connectivity: protocol::raster::Connectivity::Four,
    });
    rig.send(&HostFrame::Raster(
        HVec::from_slice(&[triangle(1), fill]).expect("batch"),
    )); // seq 4: the fill (index 1) is outside the frame
    rig.send(&HostFrame::Regs(RegWrite {
        offset: 493,
        words: HVec::from_slice(&[0, 0]).expect("words"),
    })); // seq 5: past the 494-word map
    rig.pump(10);
    assert_eq!(
        rig.errors(),
        vec![
            (ErrorCode::Malformed, 1, 0),
            (ErrorCode::OutOfRange, 2, 0),
            (ErrorCode::OutOfRange, 4, 1),
            (ErrorCode::OutOfRange, 5, 493),
        ]
    );
    // The triangle before the bad fill was drawn; the setup that fitted was applied.
    let ops = &rig.bus().ops;
    assert_eq!(ops.iter().filter(|o| **o == Op::Setup).count(), 1);
    assert_eq!(ops.iter().filter(|o| matches!(o, Op::Push(..))).count(), 1);
}

#[test]
fn missing_capabilities_are_refused() {
    let mut raster_only = caps();
    raster_only.ray_trace = false;
    let mut rig = Rig::new(Bus::new(64, 64), raster_only);
    rig.hello();
    rig.send(&HostFrame::Regs(RegWrite {
        offset: 0,
        words: HVec::from_slice(&[1]).expect("words"),
    }));
    rig.send(&HostFrame::Start(StartFrame {
        frame_id: 1,
        block: Block::RayTrace,
        numeric: protocol::frame::Numeric::F32,
        auto_restart: false,
        aovs: false,
    }));
    rig.pump(10);
    assert_eq!(
        rig.errors(),
        vec![
            (ErrorCode::Unsupported, 1, 0),
            (ErrorCode::Unsupported, 2, 0)
        ]
    );
    assert!(rig.bus().ops.is_empty());
}

/// A host that restarts its link (a new `fpgfx` run) gets a clean controller: the old
/// session's handshake no longer counts, and a new hello brings it back.
#[test]
fn a_link_reset_starts_a_new_session() {
    let mut rig = Rig::new(Bus::new(64, 64), caps());
    rig.hello();
    rig.host.reset(rig.now, 99);
    rig.pump(20);
    rig.send(&HostFrame::RasterSetup(setup(16, 16)));
    rig.pump(5);
    assert_eq!(rig.errors(), vec![(ErrorCode::Handshake, 0, 0)]);
    rig.answers.clear();
    rig.hello();
    rig.send(&HostFrame::RasterSetup(setup(16, 16)));
    rig.pump(5);
    assert!(rig.errors().is_empty());
    assert_eq!(rig.bus().ops, vec![Op::Setup]);
}

/// When the FPGA transport fails, the caller hears of it and the host still gets an
/// answer (Device) for its request instead of waiting forever.
#[test]
fn an_fpga_fault_is_answered() {
    let mut rig = Rig::new(Bus::new(64, 64), caps());
    rig.hello();
    rig.send(&HostFrame::RasterSetup(setup(64, 64)));
    rig.bus().fail_pushes = true;
    rig.send(&HostFrame::Raster(
        HVec::from_slice(&[triangle(3)]).expect("batch"),
    ));
    rig.pump(10);
    assert_eq!(rig.fpga_errors, 1);
    assert_eq!(rig.errors(), vec![(ErrorCode::Device, 2, 0)]);
}

/// ViRAY's driver loop: with auto-restart the controller starts the next frame as soon as
/// one is done, stepping the animation in between (a ramp and an orbit), until Stop.
#[test]
fn auto_restart_steps_the_animation_until_stopped() {
    use protocol::scene::light;
    let mut rig = Rig::new(Bus::new(64, 64), caps());
    rig.hello();
    let pos = light::OFFSET + light::WORDS + light::POSITION; // light 1's x, y, z
    let q16 = |v: f64| (v * 65536.0).round() as i32 as u32;
    rig.send(&HostFrame::Regs(RegWrite {
        offset: pos as u16,
        words: HVec::from_slice(&[q16(3.0), q16(4.0), q16(0.0)]).expect("words"),
    }));
    let angle = 10f64.to_radians();
    let orbit = Orbit {
        x_reg: pos as u16,
        z_reg: pos as u16 + 2,
        center: [0, 0],
        cos: (angle.cos() * Orbit::ONE as f64).round() as i32,
        sin: (angle.sin() * Orbit::ONE as f64).round() as i32,
    };
    let ramp = Ramp {
        reg: pos as u16 + 1,
        step: -65536 / 4,
    };
    rig.send(&HostFrame::Animate(Animation {
        ramps: HVec::from_slice(&[ramp]).expect("ramps"),
        orbits: HVec::from_slice(&[orbit]).expect("orbits"),
    }));
    rig.send(&HostFrame::Start(StartFrame {
        frame_id: 10,
        block: Block::RayTrace,
        numeric: protocol::frame::Numeric::F32,
        auto_restart: true,
        aovs: false,
    }));
    rig.pump(6);
    rig.send(&HostFrame::Stop);
    rig.pump(10);
    assert!(rig.errors().is_empty(), "{:?}", rig.errors());

    let done: Vec<u32> = rig
        .answers
        .iter()
        .filter_map(|a| match a {
            DeviceFrame::Done(d) => Some(d.frame_id),
            _ => None,
        })
        .collect();
    assert!(done.len() >= 3, "only {done:?}");
    assert_eq!(done, (10..10 + done.len() as u32).collect::<Vec<_>>());
    let starts = rig
        .bus()
        .ops
        .iter()
        .filter(|o| matches!(o, Op::Start(_)))
        .count();
    assert_eq!(
        starts,
        done.len(),
        "a frame started after Stop, or one was lost"
    );

    // Between consecutive starts: y ramps down by ¼, (x, z) turns by 10°.
    let (mut x, mut y, mut z) = (q16(3.0), q16(4.0), q16(0.0));
    let mut steps = 0;
    let ops = rig.bus().ops.clone();
    for w in ops.windows(4) {
        if let [Op::Regs(a, ya), Op::Regs(b, xb), Op::Regs(c, zc), Op::Start(_)] = w {
            y = ramp.apply(y);
            (x, z) = orbit.apply(x, z);
            assert_eq!((*a as usize, ya[..].to_vec()), (pos + 1, vec![y]));
            assert_eq!((*b as usize, xb[..].to_vec()), (pos, vec![x]));
            assert_eq!((*c as usize, zc[..].to_vec()), (pos + 2, vec![z]));
            steps += 1;
        }
    }
    assert_eq!(steps, done.len() - 1, "one animation step per restart");
    let r = (x as i32 as f64).hypot(z as i32 as f64) / 65536.0;
    assert!((r - 3.0).abs() < 1e-3, "orbit radius drifted to {r}");
    assert!(ops.contains(&Op::Stop));
}

/// The animation steps are Q16.16 arithmetic: on a binary32 image (a float datapath's)
/// the controller refuses them, naming the value-format word, instead of writing garbage.
#[test]
fn animation_on_a_binary32_image_is_refused() {
    use protocol::scene::{hdr, ValueFormat};
    let mut rig = Rig::new(Bus::new(64, 64), caps());
    rig.hello();
    let animation = || {
        HostFrame::Animate(Animation {
            ramps: HVec::from_slice(&[Ramp { reg: 40, step: 1 }]).expect("ramps"),
            orbits: HVec::new(),
        })
    };
    rig.send(&animation());
    rig.pump(2);
    assert!(
        rig.errors().is_empty(),
        "a Q16.16 image animates: {:?}",
        rig.errors()
    );
    rig.send(&HostFrame::Regs(RegWrite {
        offset: hdr::VALUE_FORMAT as u16,
        words: HVec::from_slice(&[ValueFormat::Binary32.code()]).expect("words"),
    }));
    rig.send(&animation());
    rig.pump(2);
    let errors = rig.errors();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(
        (errors[0].0, errors[0].2),
        (ErrorCode::Unsupported, hdr::VALUE_FORMAT as u32)
    );
    // An empty animation (stop animating) is always allowed.
    rig.send(&HostFrame::Animate(Animation::default()));
    rig.pump(2);
    assert_eq!(rig.errors().len(), 1);
}
