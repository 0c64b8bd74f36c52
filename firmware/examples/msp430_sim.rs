//! Runs the MSP430 board binary (`fpgfx-firmware-msp430`) under mspdebug's simulator
//! with a small raster job, and checks the SPI bytes it shifts out against the same
//! controller code built for the host.
//!
//! `cargo run -p firmware --example msp430_sim -- ELF [OUT_DIR]` (docs/firmware.md,
//! "MSP430"). The part comes from the ELF's `FPGFX_PART` (168 or 2617), so the run
//! drives the registers the binary was built for. mspdebug's `sim` models the CPU and
//! flat memory but no USART or USCI, so:
//!
//! * two `gpio` devices with an interrupt number set (which makes them eight plain byte
//!   registers) stand in for the host UART (F168: USART0 at 0x70–0x77; F2617: USCI_A0 at
//!   0x60–0x67) and the SPI (F168: USART1 at 0x78–0x7F; F2617: USCI_B1 at 0xD8–0xDF),
//!   so that the receive buffers hold what the harness writes there;
//! * a `tracer` prints every peripheral write: the bytes written to the UART's transmit
//!   buffer are the host link's output, those to the SPI's its MOSI, and P5OUT (0x31)
//!   bit 0 is the FPGA's chip select;
//! * the firmware calls `fpgfx_host_rx_idle` when the host link has no byte and
//!   `fpgfx_spi_rx_wait` while an SPI byte is shifted: the harness breaks on both, writes
//!   the next host byte into the UART's receive buffer and sets its receive flag, or the
//!   MISO byte into the SPI's and sets its flag (the transmit flags are set and stay
//!   set). MISO answers a status read with the block idle and its FIFO empty (the canned
//!   status of `vectors`' recorder), every other byte with 0.
//!
//! The host end of the link is `protocol::link::Link`, as in `fpgfx`. Written to
//! OUT_DIR (default `target/msp430-sim`): `spi.txt` (one CS-low transaction per line, MOSI
//! hex), `host-in.hex`/`host-out.hex` (the link's bytes each way), `summary.txt`.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::convert::Infallible;
use std::io::{Read as _, Write as _};
use std::path::PathBuf;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::rc::Rc;
use std::sync::mpsc::{self, Receiver};
use std::time::Duration;

use embedded_hal::delay::DelayNs;
use embedded_hal::spi::{ErrorType, Operation, SpiDevice};
use firmware::{Controller, FitkitSpi};
use protocol::bus::FITKIT;
use protocol::fitkit_spi::{Status, ADDR_STATUS, FIFO_RECORDS, FLAG_FIFO_EMPTY, STATUS_BYTES};
use protocol::frame::{
    decode, encode, Block, Caps, DeviceFrame, Hello, HostFrame, Numeric, PixelFormat, Plane,
    RasterBatcher, ReadRequest, Rect, StartFrame,
};
use protocol::link::{Config, Event, Link, MAX_FRAME};
pub use protocol::raster::{
    Aa, AaPattern, Cull, Line, LineAlgo, Point, RasterCmd, RasterSetup, Rgb, Shade, Traversal,
    Triangle,
};
use protocol::MAX_PAYLOAD;

type Error = Box<dyn std::error::Error>;

const SYNC_TOKEN: u32 = 7;
/// The board's core clock, to turn simulated cycles into the host link's milliseconds.
const CORE_KHZ: u64 = 7_373;

/// The job: handshake, a 64 × 48 frame, a clear, a line and a triangle, start, a
/// read-back, statistics, sync.
pub fn job() -> Vec<HostFrame> {
    let p = |x, y| Point { x, y };
    let cmds = [
        RasterCmd::Clear(Rgb::new(0, 0, 255)),
        RasterCmd::Line(Line {
            from: p(2, 3),
            to: p(60, 40),
            color: Rgb::new(255, 255, 255),
            color_to: None,
            width: 1,
            aa: false,
            algo: LineAlgo::Bresenham,
        }),
        RasterCmd::Triangle(Triangle {
            v: [p(10, 5), p(50, 12), p(20, 44)],
            shade: Shade::Flat(Rgb::new(255, 0, 0)),
            z: None,
            w: None,
            tex: None,
        }),
    ];
    vec![
        HostFrame::Hello(Hello::new(Caps::default(), "fpgfx msp430-sim host")),
        HostFrame::RasterSetup(RasterSetup {
            width: 64,
            height: 48,
            subpixel_bits: 0,
            background: Rgb::new(0, 0, 0),
            aa: Aa {
                pattern: AaPattern::None,
                samples: 1,
            },
            cull: Cull::None,
            traversal: Traversal::BoundingBox,
        }),
        HostFrame::Raster(heapless::Vec::from_slice(&cmds).expect("3 ≤ RASTER_BATCH")),
    ]
    .into_iter()
    // A read-back of four rows as RGB888 (768 B: four chunks) and the statistics, so
    // that the stack's high-water mark covers the answers' paths too, not only the
    // requests'.
    .chain(tail(64, 4))
    .collect()
}

/// What every job ends with: start, a read-back of the first `rows` rows of a frame
/// `width` wide as RGB888, the statistics and the sync the harness waits for.
fn tail(width: u16, rows: u16) -> [HostFrame; 4] {
    [
        HostFrame::Start(StartFrame {
            frame_id: 1,
            block: Block::Raster,
            numeric: Numeric::Q16_16,
            auto_restart: false,
            aovs: false,
        }),
        HostFrame::Read(ReadRequest {
            plane: Plane::Color,
            rect: Rect {
                x: 0,
                y: 0,
                w: width,
                h: rows,
            },
            format: PixelFormat::Rgb888,
        }),
        HostFrame::GetStats,
        HostFrame::Sync(SYNC_TOKEN),
    ]
}

/// A raster job's frames as `fpgfx raster` sends them: handshake, the set-up, the
/// commands in batches as [`RasterBatcher`] cuts them, then [`tail`] with one row read
/// back.
pub fn job_frames(setup: RasterSetup, cmds: &[RasterCmd]) -> Result<Vec<HostFrame>, Error> {
    let mut frames = vec![
        HostFrame::Hello(Hello::new(Caps::default(), "fpgfx msp430-sim host")),
        HostFrame::RasterSetup(setup),
    ];
    let mut batcher = RasterBatcher::new();
    for cmd in cmds {
        if let Some(batch) = batcher.push(cmd).map_err(|e| format!("{e:?}"))? {
            frames.push(batch.to_frame()?);
        }
    }
    if let Some(batch) = batcher.finish() {
        frames.push(batch.to_frame()?);
    }
    frames.extend(tail(setup.width, 1));
    Ok(frames)
}

fn idle_status() -> [u8; STATUS_BYTES] {
    Status {
        free: FIFO_RECORDS,
        flags: FLAG_FIFO_EMPTY,
        ..Status::default()
    }
    .encode()
}

/// Where a part keeps what the harness plays: a serial port's register block (the
/// simulated gpio's base), its receive and transmit buffers, and its flag register with
/// the receive and transmit bits.
struct Port {
    base: u16,
    rxbuf: u16,
    txbuf: u16,
    flags: u16,
    rx: u8,
    tx: u8,
}

/// The host UART and the FPGA's SPI of one part.
struct PartMap {
    name: &'static str,
    host: Port,
    spi: Port,
}

/// The two parts' serial ports (msp430mcu's msp430f168.h and msp430x26x.h), by the
/// `FPGFX_PART` code the binary carries.
fn part_map(code: u16) -> Option<PartMap> {
    match code {
        168 => Some(PartMap {
            name: "MSP430F168 (USART0 UART, USART1 SPI)",
            host: Port {
                base: 0x70,
                rxbuf: 0x76,
                txbuf: 0x77,
                flags: 0x02,
                rx: 0x40,
                tx: 0x80,
            },
            spi: Port {
                base: 0x78,
                rxbuf: 0x7E,
                txbuf: 0x7F,
                flags: 0x03,
                rx: 0x10,
                tx: 0x20,
            },
        }),
        2617 => Some(PartMap {
            name: "MSP430F2617 (USCI_A0 UART, USCI_B1 SPI)",
            host: Port {
                base: 0x60,
                rxbuf: 0x66,
                txbuf: 0x67,
                flags: 0x03,
                rx: 0x01,
                tx: 0x02,
            },
            spi: Port {
                base: 0xD8,
                rxbuf: 0xDE,
                txbuf: 0xDF,
                flags: 0x07,
                rx: 0x04,
                tx: 0x08,
            },
        }),
        _ => None,
    }
}

/// mspdebug reading commands from a pipe: each command's output ends at the next
/// prompt. (Its `--embedded` mode, made for this, lost a command now and then here.)
struct Mspdebug {
    child: Child,
    stdin: ChildStdin,
    chunks: Receiver<Vec<u8>>,
    pending: String,
}

const PROMPT: &str = "(mspdebug) ";

impl Mspdebug {
    fn start() -> Result<Self, Error> {
        let mut child = Command::new("mspdebug")
            .args(["-n", "sim"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("cannot run mspdebug (apt-get install mspdebug): {e}"))?;
        let stdin = child.stdin.take().ok_or("no stdin")?;
        let mut stdout = child.stdout.take().ok_or("no stdout")?;
        let (tx, chunks) = mpsc::channel();
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            while let Ok(n) = stdout.read(&mut buf) {
                if n == 0 || tx.send(buf[..n].to_vec()).is_err() {
                    break;
                }
            }
        });
        let mut m = Self {
            child,
            stdin,
            chunks,
            pending: String::new(),
        };
        m.wait_ready()?;
        Ok(m)
    }

    fn wait_ready(&mut self) -> Result<Vec<String>, Error> {
        loop {
            if let Some(i) = self.pending.find(PROMPT) {
                let out: Vec<String> = self.pending[..i].lines().map(str::to_string).collect();
                self.pending.drain(..i + PROMPT.len());
                if std::env::var_os("MSP430_SIM_DEBUG").is_some() {
                    eprintln!("{}", out.join("\n"));
                }
                return Ok(out);
            }
            let chunk = self
                .chunks
                .recv_timeout(Duration::from_secs(60))
                .map_err(|_| "mspdebug stopped answering")?;
            self.pending.push_str(&String::from_utf8_lossy(&chunk));
        }
    }

    fn cmd(&mut self, c: &str) -> Result<Vec<String>, Error> {
        writeln!(self.stdin, "{c}")?;
        self.stdin.flush()?;
        self.wait_ready()
    }

    /// Reads `len` bytes at `addr` (an address or a symbol).
    fn read(&mut self, addr: &str, len: usize) -> Result<(u32, Vec<u8>), Error> {
        let mut first = None;
        let mut bytes = Vec::new();
        for line in self.cmd(&format!("md {addr} {len}"))? {
            let body = line.trim_start_matches(':').trim();
            let Some((a, rest)) = body.split_once(':') else {
                continue;
            };
            let Ok(a) = u32::from_str_radix(a.trim(), 16) else {
                continue;
            };
            first.get_or_insert(a);
            let hex = rest.split('|').next().unwrap_or("");
            bytes.extend(
                hex.split_whitespace()
                    .filter_map(|h| u8::from_str_radix(h, 16).ok()),
            );
        }
        Ok((first.ok_or("md printed no address")?, bytes))
    }
}

impl Drop for Mspdebug {
    fn drop(&mut self) {
        let _ = writeln!(self.stdin, "exit");
        let _ = self.child.wait();
    }
}

/// What a `run` printed that the harness needs.
#[derive(Default)]
struct Trace {
    host_out: Vec<u8>,
    /// (chip select low?, MOSI byte) events in order.
    spi: Vec<SpiEvent>,
    cycles: u64,
}

enum SpiEvent {
    Select(bool),
    Byte(u8),
}

fn parse_trace(lines: &[String], map: &PartMap, trace: &mut Trace) -> Option<String> {
    let host_tx = format!("0x{:04x}", map.host.txbuf);
    let spi_tx = format!("0x{:04x}", map.spi.txbuf);
    let mut stop = None;
    let mut after_regs = false;
    for line in lines {
        let l = line.trim_start_matches(':');
        if let Some((when, what)) = l.split_once(": write.b => ") {
            if let Ok(c) = when.trim().parse() {
                trace.cycles = c;
            }
            let mut it = what.split_whitespace();
            let (Some(addr), Some(value)) = (it.next(), it.next()) else {
                continue;
            };
            let value = u8::from_str_radix(value.trim_start_matches("0x"), 16).unwrap_or(0);
            if addr == host_tx {
                trace.host_out.push(value);
            } else if addr == spi_tx {
                trace.spi.push(SpiEvent::Byte(value));
            } else if addr == "0x0031" {
                trace.spi.push(SpiEvent::Select(value & 1 == 0));
            }
        } else if l.contains("( PC:") {
            after_regs = true;
        } else if after_regs && stop.is_none() {
            let t = l.trim();
            if let Some(name) = t.strip_suffix(':') {
                if !name.contains(' ') {
                    stop = Some(name.to_string());
                }
            }
        }
    }
    stop
}

/// The MOSI transactions (one per CS-low period) in `events`.
fn transactions(events: &[SpiEvent]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut cur: Option<Vec<u8>> = None;
    for e in events {
        match e {
            SpiEvent::Select(true) => cur = Some(Vec::new()),
            SpiEvent::Select(false) => out.extend(cur.take()),
            SpiEvent::Byte(b) => {
                if let Some(c) = cur.as_mut() {
                    c.push(*b);
                }
            }
        }
    }
    out
}

/// The host end: sends the job's frames in order as the link allows, collects answers.
struct Host {
    link: Link,
    todo: VecDeque<HostFrame>,
    answers: Vec<DeviceFrame>,
    wire: VecDeque<u8>,
    sent_bytes: Vec<u8>,
}

impl Host {
    fn new(frames: &[HostFrame]) -> Self {
        Self {
            link: Link::new(Config::default()),
            todo: frames.iter().cloned().collect(),
            answers: Vec::new(),
            wire: VecDeque::new(),
            sent_bytes: Vec::new(),
        }
    }

    fn input(&mut self, now: u64, mut bytes: &[u8]) -> Result<(), Error> {
        loop {
            let (used, event) = self.link.handle_input(now, bytes);
            bytes = &bytes[used..];
            match event {
                Some(Event::Data(p)) => self.answers.push(decode::<DeviceFrame>(p)?),
                Some(_) => {}
                None if bytes.is_empty() => return Ok(()),
                None => {}
            }
        }
    }

    fn output(&mut self, now: u64) -> Result<(), Error> {
        while let Some(f) = self.todo.front() {
            let mut buf = [0u8; MAX_PAYLOAD];
            let bytes = encode(f, &mut buf)?;
            if self.link.send(now, bytes).is_err() {
                break;
            }
            self.todo.pop_front();
        }
        self.link.handle_timeout(now);
        let mut out = [0u8; MAX_FRAME];
        while let Some(n) = self.link.poll_transmit(now, &mut out) {
            self.wire.extend(&out[..n]);
            self.sent_bytes.extend(&out[..n]);
        }
        Ok(())
    }

    /// Every answer the job asks for has come: the read-back's end, the statistics and
    /// the sync (which may overtake the read-back's chunks).
    fn done(&self) -> bool {
        let has = |f: fn(&DeviceFrame) -> bool| self.answers.iter().any(f);
        has(|a| matches!(a, DeviceFrame::Synced(SYNC_TOKEN)))
            && has(|a| matches!(a, DeviceFrame::ReadDone(_)))
            && has(|a| matches!(a, DeviceFrame::Stats(_)))
    }
}

/// The bottom (end of .bss) and top of the stack, from the firmware's
/// `FPGFX_STACK_AREA`.
fn stack_area(sim: &mut Mspdebug) -> Result<(u32, u32), Error> {
    let (_, area) = sim.read("FPGFX_STACK_AREA", 4)?;
    let [b0, b1, t0, t1] = area[..] else {
        return Err("FPGFX_STACK_AREA: short read".into());
    };
    Ok((
        u32::from(u16::from_le_bytes([b0, b1])),
        u32::from(u16::from_le_bytes([t0, t1])),
    ))
}

/// Bytes of stack used so far: start-up (or the harness) filled it with 0xA5.
fn stack_used(sim: &mut Mspdebug, ebss: u32, top: u32) -> Result<u32, Error> {
    let (base, ram) = sim.read(&format!("0x{ebss:04x}"), (top - ebss) as usize)?;
    let untouched = ram.iter().take_while(|&&b| b == 0xA5).count() as u32;
    Ok(top - (base + untouched))
}

/// The MSP430 run: returns the MOSI transactions, the host's answers and what else the
/// summary reports.
/// The MOSI transactions, the summary's lines, the part's code and the stack's
/// (high-water mark, room).
type Simulated = (Vec<Vec<u8>>, Vec<String>, u16, (u32, u32), Vec<DeviceFrame>);

fn simulate(
    elf: &str,
    out: &std::path::Path,
    frames: &[HostFrame],
    noise: &[u8],
) -> Result<Simulated, Error> {
    let mut sim = Mspdebug::start()?;
    let mut summary = Vec::new();
    sim.cmd(&format!("prog {elf}"))?;
    let (_, code) = sim.read("FPGFX_PART", 2)?;
    let code = match code[..] {
        [lo, hi, ..] => u16::from_le_bytes([lo, hi]),
        _ => return Err("FPGFX_PART: short read".into()),
    };
    let map = part_map(code).ok_or_else(|| format!("FPGFX_PART {code}: not a known part"))?;
    summary.push(format!("part: {}", map.name));
    for c in [
        "simio add gpio host".to_string(),
        format!("simio config host base 0x{:x}", map.host.base),
        "simio config host irq 14".into(),
        "simio add gpio spi".into(),
        format!("simio config spi base 0x{:x}", map.spi.base),
        "simio config spi irq 15".into(),
        "simio add timer timer_a 3".into(),
        "simio config timer_a base 0x160".into(),
        "simio add tracer trace".into(),
        "simio config trace verbose".into(),
        "setbreak fpgfx_host_rx_idle".into(),
        "setbreak fpgfx_spi_rx_wait".into(),
        "setbreak fpgfx_exit".into(),
    ] {
        sim.cmd(&c)?;
    }
    // Both transmitters always ready. (On the F2617 the host's flags share IFG2 with
    // nothing the harness plays; on the F168 the two ports' flags are IFG1 and IFG2.)
    sim.cmd(&format!("mw 0x{:04x} {:02x}", map.host.flags, map.host.tx))?;
    sim.cmd(&format!("mw 0x{:04x} {:02x}", map.spi.flags, map.spi.tx))?;
    let status = idle_status();
    let mut host = Host::new(frames);
    host.wire.extend(noise);
    let mut trace = Trace::default();
    let mut fed = 0usize;
    let (mut host_bytes_in, mut miso_bytes, mut runs) = (0usize, 0usize, 0usize);
    let mut stalled = 0;
    // The host's clock: the simulated cycles, plus a millisecond for every stop at which
    // neither end had anything to say. The simulator spends a few cycles per such stop
    // where a board would wait in real time, and the host's retransmission (a frame
    // lost to line noise) is due only after its timeout.
    let mut idle_ms = 0u64;
    let (ebss, top) = stack_area(&mut sim)?;
    let mut init_used = None;
    loop {
        runs += 1;
        let lines = sim.cmd("run")?;
        let Some(stop) = parse_trace(&lines, &map, &mut trace) else {
            // A simulator error (an unknown opcode after a wild jump: the stack has run
            // into .bss, say) ends `run` without a breakpoint.
            let tail = lines[lines.len().saturating_sub(3)..].join(" | ");
            return Err(format!("run stopped outside the hooks: {tail}").into());
        };
        let now = trace.cycles / CORE_KHZ + idle_ms;
        if init_used.is_none() {
            // Start-up is over (the controller waits for its first byte): what the stack
            // reached so far is start-up's; refill below the live frames to see the
            // job's own high-water mark at the end.
            init_used = Some(stack_used(&mut sim, ebss, top)?);
            let sp = lines
                .iter()
                .find_map(|l| l.split("( SP: ").nth(1))
                .and_then(|r| r.split(')').next())
                .and_then(|v| u32::from_str_radix(v.trim(), 16).ok())
                .ok_or("no SP in the stop's registers")?;
            sim.cmd(&format!("fill 0x{ebss:04x} {} a5", sp - 2 - ebss))?;
        }
        match stop.as_str() {
            "fpgfx_host_rx_idle" => {
                let new = trace.host_out[fed..].to_vec();
                fed = trace.host_out.len();
                host.input(now, &new)?;
                host.output(now)?;
                if host.done() && host.wire.is_empty() {
                    break;
                }
                match host.wire.pop_front() {
                    Some(b) => {
                        sim.cmd(&format!("mw 0x{:04x} {b:02x}", map.host.rxbuf))?;
                        let flags = map.host.rx | map.host.tx;
                        sim.cmd(&format!("mw 0x{:04x} {flags:02x}", map.host.flags))?;
                        host_bytes_in += 1;
                        stalled = 0;
                    }
                    None => {
                        stalled += 1;
                        idle_ms += 1;
                        if stalled > 5000 {
                            return Err("the host link stalled: nothing to send, no answer".into());
                        }
                    }
                }
            }
            "fpgfx_spi_rx_wait" => {
                // The open transaction is the last Select(true) onwards.
                let open: Vec<u8> = {
                    let start = trace
                        .spi
                        .iter()
                        .rposition(|e| matches!(e, SpiEvent::Select(true)))
                        .ok_or("an SPI byte outside chip select")?;
                    trace.spi[start..]
                        .iter()
                        .filter_map(|e| match e {
                            SpiEvent::Byte(b) => Some(*b),
                            SpiEvent::Select(_) => None,
                        })
                        .collect()
                };
                let i = open.len();
                let miso = match open.first() {
                    Some(&ADDR_STATUS) if i >= 2 => status.get(i - 2).copied().unwrap_or(0),
                    _ => 0,
                };
                sim.cmd(&format!("mw 0x{:04x} {miso:02x}", map.spi.rxbuf))?;
                let flags = map.spi.rx | map.spi.tx;
                sim.cmd(&format!("mw 0x{:04x} {flags:02x}", map.spi.flags))?;
                miso_bytes += 1;
            }
            "fpgfx_exit" => {
                // The stop is at the function's entry, before it records its argument:
                // the code is still in R12, the EABI's first argument register.
                let code = lines
                    .iter()
                    .find_map(|l| l.split("R12: ").nth(1))
                    .and_then(|r| r.split_whitespace().next())
                    .and_then(|v| u16::from_str_radix(v.trim_end_matches(')'), 16).ok())
                    .ok_or("no R12 in the stop's registers")?;
                let why = match code {
                    1 => "a panic: an overflow, an index out of bounds or an unwrap",
                    3 => "a float operation",
                    _ => "an unknown cause",
                };
                return Err(format!(
                    "the firmware stopped with exit code {code} ({why}) at cycle {}",
                    trace.cycles
                )
                .into());
            }
            other => return Err(format!("run stopped in {other}").into()),
        }
    }
    let job_used = stack_used(&mut sim, ebss, top)?;
    let (_, errors) = sim.read("FPGFX_FPGA_ERRORS", 2)?;
    summary.push(format!(
        "stack high-water: start-up {} bytes, the job {} bytes, of {} between .bss and \
         the top of RAM (0x{ebss:04x}..0x{top:04x})",
        init_used.unwrap_or(0),
        job_used,
        top - ebss,
    ));
    summary.push(format!(
        "host bytes in {host_bytes_in}, out {}; MISO bytes {miso_bytes}; runs {runs}; \
         simulated cycles {}; FPGA errors {:?}",
        trace.host_out.len(),
        trace.cycles,
        errors
    ));
    let answers: Vec<String> = host
        .answers
        .iter()
        .map(|a| match a {
            DeviceFrame::Chunk(c) => format!("Chunk(offset {}, {} B)", c.offset, c.data.len()),
            other => format!("{other:?}"),
        })
        .collect();
    summary.push(format!("answers: {}", answers.join(", ")));
    let hex = |b: &[u8]| b.iter().map(|x| format!("{x:02x}")).collect::<Vec<_>>();
    std::fs::write(
        out.join("host-in.hex"),
        hex(&host.sent_bytes).join("\n") + "\n",
    )?;
    std::fs::write(
        out.join("host-out.hex"),
        hex(&trace.host_out).join("\n") + "\n",
    )?;
    Ok((
        transactions(&trace.spi),
        summary,
        code,
        (job_used, top - ebss),
        host.answers,
    ))
}

/// The same job through the same controller built for this host, on an SPI device that
/// records MOSI and answers status reads as the harness does.
fn reference(frames: &[HostFrame], noise: &[u8]) -> Result<Vec<Vec<u8>>, Error> {
    struct Recorder(Rc<RefCell<Vec<Vec<u8>>>>);
    impl ErrorType for Recorder {
        type Error = Infallible;
    }
    impl SpiDevice for Recorder {
        fn transaction(&mut self, ops: &mut [Operation<'_, u8>]) -> Result<(), Infallible> {
            let mut t = Vec::new();
            for op in ops {
                match op {
                    Operation::Write(b) => t.extend_from_slice(b),
                    Operation::Read(buf) => {
                        let status = idle_status();
                        for (i, b) in buf.iter_mut().enumerate() {
                            *b = if t.first() == Some(&ADDR_STATUS) {
                                status.get(i).copied().unwrap_or(0)
                            } else {
                                0
                            };
                        }
                        t.extend(std::iter::repeat_n(0, buf.len()));
                    }
                    _ => unreachable!("FitkitSpi only writes and reads"),
                }
            }
            self.0.borrow_mut().push(t);
            Ok(())
        }
    }
    struct NoDelay;
    impl DelayNs for NoDelay {
        fn delay_ns(&mut self, _: u32) {}
    }
    /// The controller's end of an in-memory link.
    #[derive(Default)]
    struct Pipe {
        rx: VecDeque<u8>,
        tx: Vec<u8>,
    }
    impl embedded_io::ErrorType for Pipe {
        type Error = Infallible;
    }
    impl embedded_io::Read for Pipe {
        fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
            let n = buf.len().min(self.rx.len());
            for (d, s) in buf.iter_mut().zip(self.rx.drain(..n)) {
                *d = s;
            }
            Ok(n)
        }
    }
    impl embedded_io::ReadReady for Pipe {
        fn read_ready(&mut self) -> Result<bool, Infallible> {
            Ok(!self.rx.is_empty())
        }
    }
    impl embedded_io::Write for Pipe {
        fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
            self.tx.extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> Result<(), Infallible> {
            Ok(())
        }
    }
    let caps = Caps {
        raster: true,
        pixel_formats: PixelFormat::Rgb332.bit() | PixelFormat::Rgb888.bit(),
        max_width: 512,
        max_height: 512,
        queue_depth: 1,
        fifo_depth: FIFO_RECORDS,
        ..Caps::default()
    };
    let recorded = Rc::new(RefCell::new(Vec::new()));
    let fpga = FitkitSpi::new(Recorder(recorded.clone()), NoDelay);
    let mut c: Controller<Pipe, _, 1, 4, 0> =
        Controller::sized(Pipe::default(), fpga, caps, &FITKIT, "reference");
    let mut host = Host::new(frames);
    host.wire.extend(noise);
    for now in 0..100_000 {
        host.output(now)?;
        c.host().rx.extend(host.wire.drain(..));
        c.poll(now).map_err(|e| format!("{e:?}"))?;
        let out = std::mem::take(&mut c.host().tx);
        host.input(now, &out)?;
        if host.done() {
            return Ok(recorded.take());
        }
    }
    Err("the reference run did not finish".into())
}

fn main() -> Result<(), Error> {
    let mut args = std::env::args().skip(1);
    let elf = args
        .next()
        .ok_or("usage: msp430_sim ELF [OUT_DIR] (build ELF with --features board-msp430)")?;
    let out = PathBuf::from(args.next().unwrap_or_else(|| "target/msp430-sim".into()));
    let report = run(&elf, &out)?;
    println!("{}", report.summary.join("\n"));
    if report.same {
        Ok(())
    } else {
        Err("the MSP430's SPI writes differ from the host build's".into())
    }
}

/// What a run found: the summary's lines (also in `summary.txt`), the part's code from
/// the ELF, and whether the MSP430's SPI writes equal the host build's.
pub struct Report {
    /// The lines of `summary.txt`.
    pub summary: Vec<String>,
    /// `FPGFX_PART` as the ELF holds it (168 or 2617).
    pub part: u16,
    /// The SPI writes (status reads aside) are byte-identical to the host build's.
    pub same: bool,
    /// The stack's high-water mark during the job, in bytes.
    pub stack: u32,
    /// Bytes between the end of .bss and the top of RAM.
    pub stack_room: u32,
    /// The MSP430's MOSI transactions, one per chip-select period, status reads and
    /// read-backs included.
    pub spi: Vec<Vec<u8>>,
    /// Its answers over the host link, in order.
    pub answers: Vec<DeviceFrame>,
}

/// Runs `elf` under mspdebug's simulator and the same job through the host build,
/// writing the files named in the module docs into `out`. Used by this example's `main`
/// and by `firmware/tests/msp430.rs`.
pub fn run(elf: &str, out: &std::path::Path) -> Result<Report, Error> {
    run_job(elf, out, &job(), &[])
}

/// As [`run`], with the host sending `frames` (which must end as [`tail`] does), after
/// the raw bytes `noise` (a line's garbage, an over-long frame: what the board's link
/// must discard).
pub fn run_job(
    elf: &str,
    out: &std::path::Path,
    frames: &[HostFrame],
    noise: &[u8],
) -> Result<Report, Error> {
    std::fs::create_dir_all(out)?;
    let (spi, mut summary, part, (stack, stack_room), answers) = simulate(elf, out, frames, noise)?;
    let text: Vec<String> = spi
        .iter()
        .map(|t| t.iter().map(|b| format!("{b:02x}")).collect::<String>())
        .collect();
    std::fs::write(out.join("spi.txt"), text.join("\n") + "\n")?;
    let writes = |ts: &[Vec<u8>]| -> Vec<Vec<u8>> {
        ts.iter()
            .filter(|t| t.first() != Some(&ADDR_STATUS))
            .cloned()
            .collect()
    };
    let reference = reference(frames, noise)?;
    let same = !writes(&spi).is_empty() && writes(&spi) == writes(&reference);
    summary.push(format!(
        "SPI: {} transactions ({} writes, {} status reads); the host build of the same job \
         makes {} ({} writes): writes {}",
        spi.len(),
        writes(&spi).len(),
        spi.len() - writes(&spi).len(),
        reference.len(),
        writes(&reference).len(),
        if same { "identical" } else { "DIFFER" }
    ));
    std::fs::write(out.join("summary.txt"), summary.join("\n") + "\n")?;
    Ok(Report {
        summary,
        part,
        same,
        stack,
        stack_room,
        spi,
        answers,
    })
}
