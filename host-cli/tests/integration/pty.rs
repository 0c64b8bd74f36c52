//! End to end over a real pseudo-terminal: `fpgfx-sim --pty` serves the controller and the
//! FPGA model, `fpgfx --port` drives it. The images must equal built-in mode's, and a
//! second host session on the same running board must work (the link resynchronises).

use crate::common::{example, fails, ok, pty_pair, rgb, start_sim, start_tcp_sim, tmp};

#[test]
fn pty_board_draws_what_built_in_draws() {
    let sim = start_sim(&[]);
    let golden = rgb(&example("raster/golden/gallery.png"));

    // Two host sessions against the same running board.
    for run in 0..2 {
        let out = tmp(&format!("gallery{run}.png"));
        ok(&["--port", &sim.pty, "raster", &gallery(), "-o", &out]);
        assert!(
            rgb(&out) == golden,
            "raster over the pty (run {run}) differs from the golden"
        );
    }

    let scene = example("rt/shapes.toml");
    let (over_pty, built_in) = (tmp("shapes-pty.png"), tmp("shapes-builtin.png"));
    let render = |port: &str, out: &str| {
        ok(&[
            "--port", port, "render", &scene, "--size", "96x54", "-o", out,
        ]);
    };
    render(&sim.pty, &over_pty);
    render("builtin", &built_in);
    assert!(
        rgb(&over_pty) == rgb(&built_in),
        "render over the pty differs from built-in"
    );
}

#[test]
fn a_port_that_does_not_exist_is_a_clear_error() {
    let err = fails(&["--port", "/dev/fpgfx-no-such-port", "raster", &gallery()]);
    assert!(
        err.contains("serial port /dev/fpgfx-no-such-port does not exist"),
        "{err}"
    );
}

fn gallery() -> String {
    example("raster/gallery.toml")
}

/// A port another program holds (serial ports are opened exclusively).
#[test]
fn a_busy_port_is_named_busy() {
    let sim = start_sim(&[]);
    let _holder = serialport::new(&sim.pty, 115_200)
        .open_native()
        .expect("first open succeeds");
    let err = fails(&["--port", &sim.pty, "raster", &gallery()]);
    assert!(
        err.contains(&format!("serial port {} is busy", sim.pty)),
        "{err}"
    );
}

/// A line where nobody answers: the error says what was sent and that nothing came back.
#[test]
fn a_silent_port_says_what_was_sent_and_received() {
    let (_master, path) = pty_pair();
    let err = fails(&["--port", &path, "--timeout", "1", "raster", &gallery()]);
    assert!(err.contains("no answer to the handshake"), "{err}");
    assert!(err.contains("link reset + hello"), "{err}");
    assert!(err.contains("received 0 bytes"), "{err}");
}

/// Something that is not an fpgfx controller answers: the first bytes are shown.
#[test]
fn a_foreign_device_is_shown_in_hex() {
    use std::io::Write;
    let (mut master, path) = pty_pair();
    let talker = std::thread::spawn(move || {
        for _ in 0..40 {
            let _ = master.write_all(b"AT\r\nOK\r\n");
            std::thread::sleep(std::time::Duration::from_millis(25));
        }
    });
    let err = fails(&["--port", &path, "--timeout", "1", "raster", &gallery()]);
    let _ = talker.join();
    assert!(err.contains("starting 41 54 0d 0a 4f 4b"), "{err}");
}

/// The board over TCP: same images as built-in, for two clients one after the other.
#[test]
fn tcp_board_draws_what_built_in_draws() {
    let sim = start_tcp_sim();
    let golden = rgb(&example("raster/golden/gallery.png"));
    for run in 0..2 {
        let out = tmp(&format!("tcp{run}.png"));
        ok(&["--port", &sim.pty, "raster", &gallery(), "-o", &out]);
        assert!(rgb(&out) == golden, "raster over TCP (run {run}) differs");
    }
}

/// `--pace` holds the line to its baud rate: a 9 216-byte read-back at 115 200 baud (8N1)
/// cannot arrive faster than the line carries it, less the 1 KiB the model lets run ahead
/// (a UART's DMA buffers). A lower bound only: a loaded machine may take longer.
#[test]
fn pace_holds_the_line_rate() {
    let sim = start_sim(&["--pace", "--baud", "115200"]);
    let file = tmp("pace.toml");
    std::fs::write(&file, "size = [64, 48]\n").expect("temp file");
    let stats = ok(&[
        "--port",
        &sim.pty,
        "--baud",
        "115200",
        "raster",
        &file,
        "-o",
        &tmp("pace.png"),
        "--stats",
    ])
    .stdout;
    let line = stats
        .lines()
        .find(|l| l.starts_with("read-back"))
        .expect("read-back line");
    let ms: f64 = line
        .split(" payload in ")
        .nth(1)
        .and_then(|r| r.split(" ms").next())
        .and_then(|v| v.trim().parse().ok())
        .expect("a time in ms");
    let floor = (9216.0 - 1024.0) * 10.0 / 115_200.0 * 1e3;
    assert!(
        ms >= floor,
        "read-back took {ms} ms, the line needs at least {floor:.0} ms"
    );
}

/// A controller built from another message set: the handshake error names both schema
/// hashes (and the peer), instead of exchanging garbage.
#[test]
fn a_schema_mismatch_names_both_sides() {
    use protocol::frame::{decode, encode, Caps, DeviceFrame, Hello, HostFrame};
    use protocol::link::{Event, Link, MAX_FRAME};
    use std::io::{Read, Write};
    let (mut master, path) = pty_pair();
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let stop_peer = stop.clone();
    let peer = std::thread::spawn(move || {
        let mut link: Link = Link::new(Default::default());
        let epoch = std::time::Instant::now();
        let mut buf = [0u8; 512];
        let mut out = [0u8; MAX_FRAME];
        while !stop_peer.load(std::sync::atomic::Ordering::Relaxed) {
            let now = epoch.elapsed().as_millis() as u64;
            let n = master.read(&mut buf).unwrap_or(0);
            let mut input = &buf[..n];
            let mut reply = None;
            loop {
                let (used, event) = link.handle_input(now, input);
                input = &input[used..];
                match event {
                    Some(Event::Data(p)) => {
                        if let Ok(HostFrame::Hello(_)) = decode::<HostFrame>(p) {
                            let mut hello = Hello::new(Caps::default(), "old firmware 0.0.9");
                            hello.schema_hash ^= 0xdead_beef;
                            reply = Some(DeviceFrame::Hello(hello));
                        }
                    }
                    None if input.is_empty() => break,
                    _ => {}
                }
            }
            if let Some(r) = reply {
                let mut b = [0u8; 256];
                let bytes = encode(&r, &mut b).expect("fits").to_vec();
                let _ = link.send(now, &bytes);
            }
            link.handle_timeout(now);
            while let Some(m) = link.poll_transmit(now, &mut out) {
                let _ = master.write_all(&out[..m]);
            }
        }
    });
    let err = fails(&["--port", &path, "--timeout", "5", "raster", &gallery()]);
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    let _ = peer.join();
    assert!(err.contains("old firmware 0.0.9"), "{err}");
    assert!(err.contains("message schema mismatch"), "{err}");
    let ours = format!("{:#018x}", protocol::frame::SCHEMA_HASH);
    let theirs = format!("{:#018x}", protocol::frame::SCHEMA_HASH ^ 0xdead_beef);
    assert!(err.contains(&ours) && err.contains(&theirs), "{err}");
}
