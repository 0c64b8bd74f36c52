//! `fpgfx-sim`: a whole board on a serial line — the firmware's controller and the FPGA
//! model behind a pseudo-terminal, so `fpgfx --port` is exercised over a real tty.

use std::io::{Read, Write};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use clap::Parser;
use firmware::{Controller, ControllerError};
use sim_board::host_link::{HostLink, Pending};
use sim_board::in_process::SimBus;
use sim_board::paced::Paced;
use sim_board::socket::Socket;

#[derive(Parser)]
#[command(
    name = "fpgfx-sim",
    version,
    about = "The fpgfx sim board on a pseudo-terminal or TCP, or its FPGA alone"
)]
struct Cli {
    /// Create a pseudo-terminal, print its path on the first line of stdout and serve the
    /// controller + FPGA model on it until killed.
    #[arg(long)]
    pty: bool,
    /// Serve the STM32F405's ROM bootloader (AN3155) on the pty instead of the board:
    /// what the chip does with BOOT0 high. See docs/flash.md.
    #[arg(long, requires = "pty")]
    bootloader: bool,
    /// With --bootloader: keep the emulated flash in FILE (1 MiB, created erased if
    /// missing), updated after every write or erase, so a later run sees it.
    #[arg(long, value_name = "FILE", requires = "bootloader")]
    flash_image: Option<std::path::PathBuf>,
    /// With --bootloader, a test aid: exit (like a board losing power) right after the
    /// Nth successful Write Memory, to interrupt a flash at a known point.
    #[arg(long, value_name = "N", requires = "bootloader")]
    exit_after_writes: Option<u64>,
    /// Serve the controller + FPGA model on TCP (e.g. 127.0.0.1:7878; port 0 picks one),
    /// one client at a time; prints the bound address on the first line of stdout.
    #[arg(long, value_name = "ADDR", conflicts_with = "pty")]
    tcp: Option<String>,
    /// Serve only the FPGA (the serial FPGA link, `protocol::fpga`) on this serial port,
    /// e.g. the pty QEMU gives the board's USART2.
    #[arg(long, value_name = "PORT", conflicts_with_all = ["pty", "tcp"])]
    fpga_link: Option<String>,
    /// Line rate: of --fpga-link's port, and of the emulated UART with --pace.
    #[arg(long, default_value_t = 921_600)]
    baud: u32,
    /// Move bytes no faster than a UART at --baud would (8N1), both ways, so that
    /// throughput figures through a pty or TCP mean something.
    #[arg(long)]
    pace: bool,
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("fpgfx-sim: error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// EIO (read) or EPIPE (write) on a pty master: no process has the slave open.
fn host_gone(e: &std::io::Error) -> bool {
    e.kind() == std::io::ErrorKind::BrokenPipe || matches!(e.raw_os_error(), Some(5) | Some(32))
}

fn run(cli: Cli) -> Result<()> {
    if cli.bootloader {
        return serve_bootloader(&cli);
    }
    if let Some(port) = &cli.fpga_link {
        return serve_fpga_link(port, cli.baud);
    }
    if let Some(addr) = &cli.tcp {
        return serve_tcp(addr, cli.pace.then_some(cli.baud));
    }
    anyhow::ensure!(
        cli.pty,
        "nothing to serve: give --pty, --tcp ADDR or --fpga-link PORT"
    );
    let (master, slave) =
        serialport::TTYPort::pair().context("cannot create a pseudo-terminal pair")?;
    let path = serialport::SerialPort::name(&slave).context("the pseudo-terminal has no path")?;
    // The host opens the slave by path and takes the exclusive lock a serial port gets;
    // our handle would hold it. The node lives as long as the master is open.
    drop(slave);
    announce(&path)?;
    match cli.pace {
        true => serve(Paced::new(master, cli.baud), |_| false),
        false => serve(master, |_| false),
    }
}

/// Prints where we listen on stdout's first line (tests and scripts read it).
fn announce(what: &str) -> Result<()> {
    let mut stdout = std::io::stdout();
    writeln!(stdout, "{what}")?;
    stdout.flush()?;
    Ok(())
}

/// A board: the controller and the FPGA model on `link`. `between` runs once per turn
/// with the link (to plug in a new TCP client) and returns whether it did anything.
fn serve<S: Read + Write + Pending>(
    link: S,
    mut between: impl FnMut(&mut S) -> bool,
) -> Result<()> {
    let layout = &protocol::bus::WIDE;
    let device = sim_target::device::Device::new(layout);
    let caps = device.caps();
    let mut controller = Controller::new(HostLink(link), SimBus(device), caps, layout, "fpgfx-sim");
    let epoch = Instant::now();
    loop {
        between(&mut controller.host().0);
        let now = epoch.elapsed().as_millis() as u64;
        match controller.poll(now) {
            Ok(()) => {}
            // EIO (read) or EPIPE (write) on the master while no one has the slave open:
            // the host went away; wait for the next one (it will reset the link).
            Err(ControllerError::Host(e)) if host_gone(&e) => {
                std::thread::sleep(Duration::from_millis(20));
            }
            Err(ControllerError::Host(e)) => return Err(e).context("host link"),
            // The host was answered with a Device error; like a board, keep serving.
            Err(ControllerError::Fpga(e)) => eprintln!("fpgfx-sim: FPGA model fault: {e}"),
        }
        // Sleep only when the line is quiet: a UART (with its FIFO or DMA) keeps
        // receiving while the MCU works, and a sleep per turn would cap the rate.
        if !matches!(controller.host().0.pending(), Ok(n) if n > 0) {
            std::thread::sleep(Duration::from_micros(100));
        }
    }
}

/// The board on TCP, one client at a time; a new client replaces a gone one (and resets
/// the link itself in its handshake).
fn serve_tcp(addr: &str, pace: Option<u32>) -> Result<()> {
    let listener =
        std::net::TcpListener::bind(addr).with_context(|| format!("cannot listen on {addr}"))?;
    listener.set_nonblocking(true)?;
    announce(&listener.local_addr()?.to_string())?;
    let accept = move |socket: &mut Socket<std::net::TcpStream>| match listener.accept() {
        Ok((stream, _)) => {
            let ok = stream.set_nodelay(true).is_ok() && stream.set_nonblocking(false).is_ok();
            socket.0 = ok.then_some(stream);
            true
        }
        Err(_) => false,
    };
    match pace {
        Some(baud) => serve(Paced::new(Socket(None), baud), move |p| accept(p.get_mut())),
        None => serve(Socket(None), accept),
    }
}

/// The FPGA alone behind a serial port: a board's controller (QEMU's USART2) talks to it.
fn serve_fpga_link(path: &str, baud: u32) -> Result<()> {
    let mut port = serialport::new(path, baud)
        .timeout(Duration::from_millis(1))
        .open_native()
        .with_context(|| format!("cannot open FPGA-link port {path}"))?;
    eprintln!("fpgfx-sim: FPGA link on {path}");
    let layout = &protocol::bus::WIDE;
    let mut server =
        sim_target::fpga_link::FpgaServer::new(sim_target::device::Device::new(layout));
    let epoch = Instant::now();
    let mut buf = [0u8; 4096];
    let mut out = [0u8; protocol::link::MAX_FRAME];
    let mut busy = false;
    loop {
        // While the FIFO holds work, only peek at the line; when idle, sleep in the read.
        use serialport::SerialPort;
        port.set_timeout(if busy {
            Duration::ZERO
        } else {
            Duration::from_millis(1)
        })?;
        let n = match port.read(&mut buf) {
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => 0,
            Err(e) if host_gone(&e) => {
                // The board went away (QEMU exited): nothing left to serve.
                eprintln!("fpgfx-sim: FPGA-link peer closed {path}");
                return Ok(());
            }
            Err(e) => return Err(e).with_context(|| format!("reading {path}")),
        };
        let now = epoch.elapsed().as_millis() as u64;
        server.input(now, &buf[..n]);
        while let Some(m) = server.poll_transmit(now, &mut out) {
            port.write_all(&out[..m])
                .with_context(|| format!("writing {path}"))?;
        }
        if let Some(text) = server.take_fault_text() {
            eprintln!("fpgfx-sim: FPGA fault: {text}");
        }
        busy = server.work();
    }
}

/// `--bootloader`: the emulated ROM bootloader on a pty. A pty has no physical parity,
/// so the 8E1 the host asks for is accepted and changes nothing: bytes arrive as sent.
fn serve_bootloader(cli: &Cli) -> Result<()> {
    use sim_board::bootloader::Bootloader;
    use std::io::Read;

    let mut flash_file = None;
    let mut chip = match &cli.flash_image {
        Some(path) => {
            let image = match std::fs::read(path) {
                Ok(image) => image,
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                    let erased = vec![0xFF; protocol::bootloader::FLASH_SIZE as usize];
                    std::fs::write(path, &erased)
                        .with_context(|| format!("cannot create {}", path.display()))?;
                    erased
                }
                Err(e) => return Err(e).with_context(|| format!("cannot read {}", path.display())),
            };
            let chip = Bootloader::with_flash(image)
                .with_context(|| format!("flash image {}", path.display()))?;
            flash_file = Some(
                std::fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .with_context(|| format!("cannot open {}", path.display()))?,
            );
            chip
        }
        None => Bootloader::new(),
    };

    let (mut master, slave) =
        serialport::TTYPort::pair().context("cannot create a pseudo-terminal pair")?;
    let path = serialport::SerialPort::name(&slave).context("the pseudo-terminal has no path")?;
    drop(slave);
    serialport::SerialPort::set_timeout(&mut master, Duration::from_millis(5))
        .context("pty timeout")?;
    let mut stdout = std::io::stdout();
    writeln!(stdout, "{path}")?;
    stdout.flush()?;

    let mut buf = [0u8; 1024];
    let mut out = Vec::new();
    let mut host_present = false;
    loop {
        let n = match master.read(&mut buf) {
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => 0,
            Err(e) if host_gone(&e) => {
                // Nobody has the slave open. Tools expect a fresh chip per session (on a
                // board the adapter's DTR usually drives reset), so the next host starts
                // with 0x7F; flash survives.
                if host_present {
                    chip.reset();
                    host_present = false;
                }
                std::thread::sleep(Duration::from_millis(2));
                continue;
            }
            Err(e) => return Err(e).context("pty read"),
        };
        if n == 0 {
            continue;
        }
        host_present = true;
        out.clear();
        chip.feed(&buf[..n], &mut out);
        let dirty = chip.take_dirty();
        if let Some(file) = flash_file.as_mut() {
            persist(file, chip.flash(), &dirty)?;
        }
        if !out.is_empty() {
            match master.write_all(&out).and_then(|()| master.flush()) {
                Ok(()) => {}
                Err(e) if host_gone(&e) => continue,
                Err(e) => return Err(e).context("pty write"),
            }
        }
        if let Some(address) = chip.go_address() {
            // The chip would now run user code. We report the jump and behave as if the
            // board were reset into the bootloader again, so the sim keeps serving.
            eprintln!("fpgfx-sim: Go {address:#010x}");
            chip.reset();
        }
        if cli
            .exit_after_writes
            .is_some_and(|n| chip.stats().writes >= n)
        {
            eprintln!(
                "fpgfx-sim: exiting after {} writes (--exit-after-writes)",
                chip.stats().writes
            );
            return Ok(());
        }
    }
}

/// Writes the changed flash ranges through to the image file.
fn persist(file: &mut std::fs::File, flash: &[u8], dirty: &[std::ops::Range<u32>]) -> Result<()> {
    use std::io::{Seek, SeekFrom};
    for r in dirty {
        file.seek(SeekFrom::Start(u64::from(r.start)))?;
        file.write_all(&flash[r.start as usize..r.end as usize])?;
    }
    if !dirty.is_empty() {
        file.flush().context("flash image")?;
    }
    Ok(())
}
