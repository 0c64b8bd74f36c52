//! Flashing end to end over a real pseudo-terminal: `fpgfx-sim --pty --bootloader` plays an
//! STM32F405 with BOOT0 high, and both the third-party `stm32flash` (Debian's) and
//! `fpgfx flash` program it. The emulator's flash is persisted with `--flash-image`, which
//! gives the tests an independent view of what actually landed.

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};

use crate::common::{fails, fpgfx_command, ok, pty_pair, sim_stderr, start_sim, tmp, Sim};
use protocol::bootloader::{FLASH_BASE, FLASH_SIZE};

/// The emulator as an STM32F405 in its ROM bootloader (BOOT0 high).
fn board(extra: &[&str]) -> Sim {
    start_sim(&[&["--bootloader"], extra].concat())
}

/// A scratch file with these bytes (the firmware to flash); returns its path.
fn firmware_file(name: &str, bytes: impl AsRef<[u8]>) -> String {
    let path = tmp(name);
    std::fs::write(&path, bytes).expect("write firmware file");
    path
}

/// A path for the emulator's `--flash-image` with nothing there yet (an erased chip).
fn erased_flash_image(name: &str) -> String {
    let path = tmp(name);
    let _ = std::fs::remove_file(&path);
    path
}

/// The arguments of `fpgfx flash FILE --port PORT EXTRA…`.
fn flash<'a>(file: &'a str, port: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    [&["flash", file, "--port", port], extra].concat()
}

/// Deterministic bytes that are not 0xFF-heavy (xorshift32).
fn random_bytes(n: usize, seed: u32) -> Vec<u8> {
    let mut x = seed.max(1);
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            (x >> 8) as u8
        })
        .collect()
}

fn flash_file(path: impl AsRef<Path>) -> Vec<u8> {
    let f = std::fs::read(path).expect("flash image");
    assert_eq!(f.len(), FLASH_SIZE as usize);
    f
}

/// Runs Debian's `stm32flash ARGS… PORT` and asserts that it succeeded; returns what it
/// printed (stdout, then stderr).
fn stm32flash(args: &[&str], port: &str) -> String {
    let found = Command::new("stm32flash")
        .arg("-h")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok();
    assert!(
        found,
        "stm32flash is not installed: run `cargo xtask setup` (it installs Debian's stm32flash)"
    );
    // 8N1, not stm32flash's default 8E1: Linux's pty driver clears PARENB on every
    // tcsetattr (a pty has no parity), and stm32flash re-reads its settings and gives up
    // ("Failed to set terminal flags") when they differ. On a pty the bytes are the same
    // either way; on a real port the chip needs 8E1.
    let out = Command::new("stm32flash")
        .args(["-m", "8n1"])
        .args(args)
        .arg(port)
        .output()
        .expect("stm32flash runs");
    let text = String::from_utf8_lossy(&out.stdout).to_string()
        + String::from_utf8_lossy(&out.stderr).as_ref();
    assert!(out.status.success(), "stm32flash {args:?} {port}: {text}");
    text
}

#[test]
fn stm32flash_identifies_writes_and_reads_back() {
    let sim = board(&[]);
    let text = stm32flash(&[], &sim.pty);
    assert!(text.contains("0x0413"), "device id not reported:\n{text}");
    assert!(
        text.contains("0x31"),
        "bootloader version not reported:\n{text}"
    );

    let image = random_bytes(40 * 1024, 0x5EED);
    let bin = firmware_file("stm32flash-in.bin", &image);
    stm32flash(&["-w", &bin, "-v", "-S", "0x08000000"], &sim.pty);

    let back = tmp("stm32flash-out.bin");
    let _ = std::fs::remove_file(&back);
    stm32flash(&["-r", &back, "-S", "0x08000000:40960"], &sim.pty);
    let read = std::fs::read(&back).expect("read-back file");
    assert_eq!(read.len(), image.len());
    assert!(
        read == image,
        "stm32flash read back other bytes than it wrote"
    );
}

/// Intel HEX with extended linear address records, 16 bytes a line.
fn to_hex(address: u32, data: &[u8]) -> String {
    let mut out = String::new();
    let mut record = |kind: u8, offset: u16, bytes: &[u8]| {
        let mut r = vec![bytes.len() as u8, (offset >> 8) as u8, offset as u8, kind];
        r.extend_from_slice(bytes);
        let sum = r.iter().fold(0u8, |a, b| a.wrapping_add(*b));
        r.push(sum.wrapping_neg());
        out.push(':');
        for b in r {
            out.push_str(&format!("{b:02X}"));
        }
        out.push('\n');
    };
    let mut upper = None;
    for (i, chunk) in data.chunks(16).enumerate() {
        let a = address + 16 * i as u32;
        if upper != Some(a >> 16) {
            upper = Some(a >> 16);
            record(0x04, 0, &((a >> 16) as u16).to_be_bytes());
        }
        record(0x00, a as u16, chunk);
    }
    record(0x05, 0, &address.to_be_bytes());
    record(0x01, 0, &[]);
    out
}

/// A minimal ARM ELF32 executable: `.text` at `text_at`, `.data` loaded at `data_lma`
/// (runs at 0x2000_0000), and a `.bss` segment with no file bytes.
fn to_elf(text_at: u32, text: &[u8], data_lma: u32, data: &[u8]) -> Vec<u8> {
    let phnum = 3u16;
    let text_off = 52 + 32 * u32::from(phnum);
    let data_off = text_off + text.len() as u32;
    let mut f = Vec::new();
    f.extend_from_slice(b"\x7FELF\x01\x01\x01\0\0\0\0\0\0\0\0\0");
    let u16le = |f: &mut Vec<u8>, v: u16| f.extend_from_slice(&v.to_le_bytes());
    let u32le = |f: &mut Vec<u8>, v: u32| f.extend_from_slice(&v.to_le_bytes());
    u16le(&mut f, 2); // ET_EXEC
    u16le(&mut f, 40); // EM_ARM
    u32le(&mut f, 1);
    u32le(&mut f, text_at | 1); // entry (Thumb)
    u32le(&mut f, 52); // phoff
    u32le(&mut f, 0); // shoff
    u32le(&mut f, 0x0500_0400); // EABI5, hard float
    u16le(&mut f, 52);
    u16le(&mut f, 32);
    u16le(&mut f, phnum);
    u16le(&mut f, 40);
    u16le(&mut f, 0);
    u16le(&mut f, 0);
    // (offset, vaddr, paddr, filesz, memsz, flags)
    let phdrs = [
        (
            text_off,
            text_at,
            text_at,
            text.len() as u32,
            text.len() as u32,
            5,
        ),
        (
            data_off,
            0x2000_0000,
            data_lma,
            data.len() as u32,
            data.len() as u32,
            6,
        ),
        (0, 0x2000_1000, 0x2000_1000, 0, 0x100, 6),
    ];
    for (off, vaddr, paddr, filesz, memsz, flags) in phdrs {
        u32le(&mut f, 1); // PT_LOAD
        u32le(&mut f, off);
        u32le(&mut f, vaddr);
        u32le(&mut f, paddr);
        u32le(&mut f, filesz);
        u32le(&mut f, memsz);
        u32le(&mut f, flags);
        u32le(&mut f, 4);
    }
    f.extend_from_slice(text);
    f.extend_from_slice(data);
    f
}

#[test]
fn fpgfx_flashes_bin_hex_and_elf_and_erases_only_what_it_needs() {
    let image_file = erased_flash_image("bin-hex-elf.flash");
    let sim = board(&["--flash-image", &image_file]);

    let bin_data = random_bytes(10 * 1024 + 6, 1);
    let bin = firmware_file("fw.bin", &bin_data);
    let err = ok(&flash(&bin, &sim.pty, &["--go"])).stderr;
    assert!(err.contains("erased sectors [0]"), "{err}");
    assert!(err.contains("verified"), "{err}");
    assert!(err.contains("jumped to 0x08000000"), "{err}");

    let hex_data = random_bytes(5000, 2);
    let hex = firmware_file("fw.hex", to_hex(0x0802_0010, &hex_data));
    let err = ok(&flash(&hex, &sim.pty, &[])).stderr;
    assert!(err.contains("erased sectors [5]"), "{err}");

    let (text, data) = (random_bytes(3000, 3), random_bytes(100, 4));
    let elf = firmware_file("fw.elf", to_elf(0x0804_0000, &text, 0x0804_1000, &data));
    let err = ok(&flash(&elf, &sim.pty, &["--go"])).stderr;
    assert!(err.contains("erased sectors [6]"), "{err}");
    assert!(err.contains("jumped to 0x08040000"), "{err}");

    let flash = flash_file(&image_file);
    let at = |a: u32| (a - FLASH_BASE) as usize;
    assert_eq!(&flash[..bin_data.len()], &bin_data[..]);
    assert_eq!(
        &flash[at(0x0802_0010)..at(0x0802_0010) + 5000],
        &hex_data[..]
    );
    assert_eq!(&flash[at(0x0804_0000)..at(0x0804_0000) + 3000], &text[..]);
    assert_eq!(&flash[at(0x0804_1000)..at(0x0804_1000) + 100], &data[..]);
    // Everything else is still erased: no stray writes, no padding beyond the word.
    let mut expected_ff = 0usize;
    for (i, b) in flash.iter().enumerate() {
        let a = FLASH_BASE + i as u32;
        let in_image = (FLASH_BASE..FLASH_BASE + bin_data.len() as u32).contains(&a)
            || (0x0802_0010..0x0802_0010 + 5000).contains(&a)
            || (0x0804_0000..0x0804_0000 + 3000).contains(&a)
            || (0x0804_1000..0x0804_1000 + 100).contains(&a);
        if !in_image {
            assert_eq!(*b, 0xFF, "flash at {a:#010x} was touched");
            expected_ff += 1;
        }
    }
    assert!(expected_ff > 1_000_000);

    // The last Go may still be on its way through the sim when fpgfx exits.
    sim.wait_for_log("Go 0x08040000", std::time::Duration::from_secs(10));
    let log = sim_stderr(sim);
    assert!(log.contains("Go 0x08000000"), "{log}");
    assert!(log.contains("Go 0x08040000"), "{log}");
}

#[test]
fn an_interrupted_flash_is_completed_by_a_second_run() {
    let image_file = erased_flash_image("interrupted.flash");
    let image = random_bytes(64 * 1024, 9);
    let bin = firmware_file("interrupted.bin", &image);

    // The board dies after the 40th block: the flash fails.
    let sim = board(&["--flash-image", &image_file, "--exit-after-writes", "40"]);
    let err = fails(&flash(&bin, &sim.pty, &[]));
    assert!(err.contains("error: flash"), "{err}");
    let log = sim_stderr(sim);
    assert!(log.contains("exiting after 40 writes"), "{log}");
    let half = flash_file(&image_file);
    assert_eq!(&half[..40 * 256], &image[..40 * 256]);
    assert!(half[40 * 256..].iter().all(|&b| b == 0xFF));

    // Power back on: the second run erases again, writes everything and verifies.
    let sim = board(&["--flash-image", &image_file]);
    let err = ok(&flash(&bin, &sim.pty, &[])).stderr;
    assert!(err.contains("erased sectors [0, 1, 2, 3]"), "{err}");
    assert!(err.contains("256 blocks, verified"), "{err}");
    let full = flash_file(&image_file);
    assert!(full[..image.len()] == image[..]);
}

/// `fpgfx flash` killed while it writes (the user pulls the plug on the host side): the
/// same running board is flashed completely by the next run.
#[test]
fn a_killed_flash_is_completed_by_a_second_run_on_the_same_board() {
    let image_file = erased_flash_image("killed.flash");
    let image = random_bytes(960 * 1024, 11);
    let bin = firmware_file("killed.bin", &image);
    let sim = board(&["--flash-image", &image_file]);

    let mut first = fpgfx_command(&flash(&bin, &sim.pty, &[]))
        .stderr(Stdio::null())
        .spawn()
        .expect("fpgfx runs");
    // Kill it once the first block has landed (the sim writes the flash through).
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(15);
    loop {
        let mut head = [0u8; 4];
        let landed = std::fs::File::open(&image_file)
            .and_then(|mut f| f.read_exact(&mut head))
            .is_ok()
            && head[..] == image[..4];
        if landed {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the first run never wrote"
        );
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    first.kill().expect("kill fpgfx");
    let status = first.wait().expect("fpgfx ends");
    assert!(
        !status.success(),
        "the first run finished before it could be killed: the test proves nothing"
    );
    let partial = flash_file(&image_file);
    assert!(partial[..4] == image[..4]);

    let err = ok(&flash(&bin, &sim.pty, &[])).stderr;
    assert!(err.contains("verified"), "{err}");
    let full = flash_file(&image_file);
    assert!(full[..image.len()] == image[..]);
}

#[test]
fn a_missing_port_is_a_clear_error() {
    let bin = firmware_file("missing-port.bin", [0u8; 16]);
    let err = fails(&flash(&bin, "/dev/fpgfx-no-such-port", &[]));
    assert!(
        err.contains("serial port /dev/fpgfx-no-such-port does not exist"),
        "{err}"
    );
}

#[test]
fn a_port_nobody_answers_on_says_what_was_sent() {
    let (master, path) = pty_pair();
    let bin = firmware_file("deaf.bin", [0u8; 16]);
    let err = fails(&flash(&bin, &path, &[]));
    drop(master);
    assert!(
        err.contains(
            "no answer from the bootloader: sent 0x7F 4 times (and one burst of 258 to end a \
             half-received command) at 115200 baud 8E1, got nothing"
        ),
        "{err}"
    );
}

#[test]
fn a_busy_port_is_a_clear_error() {
    let sim = board(&[]);
    let _holder = serialport::new(&sim.pty, 115_200)
        .open_native()
        .expect("the test opens the pty first");
    let bin = firmware_file("busy.bin", [0u8; 16]);
    let err = fails(&flash(&bin, &sim.pty, &[]));
    assert!(
        err.contains(&format!("serial port {} is busy", sim.pty)),
        "{err}"
    );
}

#[test]
fn the_emulator_refuses_to_program_unerased_flash() {
    use host_cli::flash::{BootPort, Client, FlashError};
    let sim = board(&[]);
    let mut c = Client::new(BootPort::open(&sim.pty, 115_200).expect("open"), 115_200);
    c.sync(4).expect("sync");
    c.erase(&[0]).expect("erase sector 0");
    c.write_block(FLASH_BASE, &[1, 2, 3, 4])
        .expect("first write");
    let e = c
        .write_block(FLASH_BASE, &[5, 6, 7, 8])
        .expect_err("second write over the same word");
    assert!(matches!(e, FlashError::Nack { .. }), "{e}");
    assert_eq!(
        e.to_string(),
        "Write Memory: the chip answered NACK to the 4 bytes for 0x08000000"
    );
    assert_eq!(c.read_block(FLASH_BASE, 4).expect("read"), [1, 2, 3, 4]);
}
