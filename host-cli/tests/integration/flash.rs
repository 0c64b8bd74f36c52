//! Flashing end to end over a real pseudo-terminal: `fpgfx-sim --pty --bootloader` plays an
//! STM32F405 with BOOT0 high, and both the third-party `stm32flash` (Debian's) and
//! `fpgfx flash` program it. The emulator's flash is persisted with `--flash-image`, which
//! gives the tests an independent view of what actually landed.

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};

use crate::common::{
    fails, fpgfx_command, ok, pty_pair, sim_stderr, sim_stderr_after, start_sim, tmp, Sim,
};
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
    elf32(40, 0x2000_0000, text_at, text, data_lma, data)
}

/// A minimal little-endian ELF32 executable for `machine` (40 Arm, 105 MSP430): `.text`
/// at `text_at`, `.data` loaded at `data_lma` (runs at `ram`), and a `.bss` segment
/// with no file bytes at `ram + 0x1000`.
fn elf32(machine: u16, ram: u32, text_at: u32, text: &[u8], data_lma: u32, data: &[u8]) -> Vec<u8> {
    let phnum = 3u16;
    let text_off = 52 + 32 * u32::from(phnum);
    let data_off = text_off + text.len() as u32;
    let mut f = Vec::new();
    f.extend_from_slice(b"\x7FELF\x01\x01\x01\0\0\0\0\0\0\0\0\0");
    let u16le = |f: &mut Vec<u8>, v: u16| f.extend_from_slice(&v.to_le_bytes());
    let u32le = |f: &mut Vec<u8>, v: u32| f.extend_from_slice(&v.to_le_bytes());
    u16le(&mut f, 2); // ET_EXEC
    u16le(&mut f, machine);
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
            ram,
            data_lma,
            data.len() as u32,
            data.len() as u32,
            6,
        ),
        (0, ram + 0x1000, ram + 0x1000, 0, 0x100, 6),
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
    let log = sim_stderr_after(sim, std::time::Duration::from_secs(10));
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

// The FITkit's MSP430F168 through its ROM BSL: `fpgfx-sim --bootloader msp430` plays the
// chip after its entry sequence, with the 64 KiB address space persisted by
// `--flash-image`.

/// The emulator as an MSP430F168 in its ROM BSL.
fn msp430_board(extra: &[&str]) -> Sim {
    start_sim(&[&["--bootloader", "msp430"], extra].concat())
}

/// The persisted 64 KiB address space.
fn msp430_memory(path: impl AsRef<Path>) -> Vec<u8> {
    let f = std::fs::read(path).expect("flash image");
    assert_eq!(f.len(), 0x1_0000);
    f
}

/// Firmware for the F168 as Intel HEX: `code` at 0x4000, the vector table at 0xFFE0 with
/// every vector (the reset vector too) pointing at 0x4000, `info` at 0x1000.
fn msp430_hex(name: &str, code: &[u8], info: &[u8]) -> String {
    let vectors: Vec<u8> = [0x00, 0x40].repeat(16);
    let hex = [
        to_hex(0x4000, code),
        to_hex(0xFFE0, &vectors),
        to_hex(0x1000, info),
    ]
    .concat();
    // One file: drop the inner end-of-file records.
    let mut lines: Vec<&str> = hex
        .lines()
        .filter(|l| *l != ":00000001FF" && !l.starts_with(":04000005"))
        .collect();
    lines.push(":00000001FF");
    firmware_file(name, lines.join("\n") + "\n")
}

/// The workspace's Python environment's interpreter, where `cargo xtask setup` puts
/// python-msp430-tools.
fn pyenv_python() -> std::path::PathBuf {
    let python = crate::common::workspace().join("target/pyenv/bin/python");
    let found = Command::new(&python)
        .args(["-c", "import msp430.bsl.target"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    assert!(
        found,
        "python-msp430-tools is not in {}: run `cargo xtask setup` (it pip-installs it there)",
        python.display()
    );
    python
}

/// Runs python-msp430-tools' `msp430-bsl ARGS… -p PORT --no-start` through the pty shim
/// (host-cli/tests/tools/msp430_bsl_on_pty.py: a pty has no DTR/RTS and no parity);
/// returns whether it succeeded and what it printed.
fn msp430_bsl(args: &[&str], port: &str) -> (bool, String) {
    let shim = crate::common::workspace().join("host-cli/tests/tools/msp430_bsl_on_pty.py");
    let out = Command::new(pyenv_python())
        .arg(shim)
        .args(["-p", port, "--no-start"])
        .args(args)
        .output()
        .expect("python runs");
    let text = String::from_utf8_lossy(&out.stdout).to_string()
        + String::from_utf8_lossy(&out.stderr).as_ref();
    (out.status.success(), text)
}

#[test]
fn bsl_python_msp430_tools_writes_and_reads_back_through_the_emulation() {
    let memory = erased_flash_image("bsl-python.flash");
    let sim = msp430_board(&["--flash-image", &memory]);
    let code = random_bytes(6000, 21);
    let info = random_bytes(64, 22);
    let hex = msp430_hex("bsl-python.hex", &code, &info);

    // Mass erase, the erased password, program, and msp430-bsl's own read-back compare.
    let (ok, text) = msp430_bsl(&["-e", "-P", "-V", &hex], &sim.pty);
    assert!(ok, "msp430-bsl -e -P -V: {text}");

    // A second session unlocks with the image's vectors and uploads what it wrote.
    let back = tmp("bsl-python-back.bin");
    let _ = std::fs::remove_file(&back);
    let (ok, text) = msp430_bsl(
        &[
            "--password",
            &hex,
            "-u",
            "0x4000/6000",
            "-o",
            &back,
            "-f",
            "bin",
        ],
        &sim.pty,
    );
    assert!(ok, "msp430-bsl --password -u: {text}");
    let read = std::fs::read(&back).expect("upload file");
    assert!(
        read == code,
        "msp430-bsl read back other bytes than it wrote"
    );

    // The emulator's own view agrees.
    let mem = msp430_memory(&memory);
    assert!(mem[0x4000..0x4000 + code.len()] == code[..]);
    assert_eq!(&mem[0x1000..0x1040], &info[..]);
    assert_eq!(&mem[0xFFFE..], &[0x00, 0x40]);
    drop(sim);

    // A chip whose answers carry wrong checksums must fail the same upload: the client
    // checks what the emulation sends, so this test can catch a wrong emulation.
    let sim = msp430_board(&["--flash-image", &memory, "--corrupt-answers"]);
    let (ok, text) = msp430_bsl(
        &[
            "--password",
            &hex,
            "-u",
            "0x4000/16",
            "-o",
            &back,
            "-f",
            "bin",
        ],
        &sim.pty,
    );
    assert!(!ok, "msp430-bsl accepted damaged answers: {text}");
    assert!(text.contains("checksum error in answer"), "{text}");
}

#[test]
fn fpgfx_flashes_the_msp430_from_hex_and_elf_and_jumps() {
    let memory = erased_flash_image("msp430-hex-elf.flash");
    let sim = msp430_board(&["--flash-image", &memory]);

    let code = random_bytes(10_000, 31);
    let hex = msp430_hex("msp430.hex", &code, &[0x5A; 8]);
    let err = ok(&flash(&hex, &sim.pty, &["--chip", "msp430f168", "--go"])).stderr;
    assert!(err.contains("chip 0xf169 (MSP430F168), BSL 1.61"), "{err}");
    assert!(err.contains("mass-erased; wrote 10040 bytes in"), "{err}");
    assert!(err.contains("verified"), "{err}");
    assert!(err.contains("jumped to 0x4000"), "{err}");
    let mem = msp430_memory(&memory);
    assert!(mem[0x4000..0x4000 + code.len()] == code[..]);
    assert_eq!(&mem[0x1000..0x1008], &[0x5A; 8]);

    // An MSP430 ELF (EM_MSP430): .text at 0xC000 ending in the vectors (reset: 0xC000),
    // .data loaded at 0xB000.
    let data = random_bytes(100, 33);
    let text = [
        random_bytes(0x1000, 34),
        vec![0xFF; 0x3FE0 - 0x1000],
        [0x00, 0xC0].repeat(16),
    ]
    .concat();
    let elf = firmware_file(
        "msp430.elf",
        elf32(105, 0x0200, 0xC000, &text, 0xB000, &data),
    );
    let err = ok(&flash(&elf, &sim.pty, &["--chip", "msp430f168", "--go"])).stderr;
    assert!(err.contains("jumped to 0xc000"), "{err}");
    let mem = msp430_memory(&memory);
    assert!(mem[0xC000..0x10000] == text[..]);
    assert!(mem[0xB000..0xB000 + 100] == data[..]);
    // Mass erase took the hex's code away.
    assert!(mem[0x4000..0xB000].iter().all(|&b| b == 0xFF));
    sim.wait_for_log("Go 0xc000", std::time::Duration::from_secs(10));
    let log = sim_stderr(sim);
    assert!(log.contains("Go 0x4000"), "{log}");
    assert!(log.contains("Go 0xc000"), "{log}");
}

/// A wrong `--password` is refused by name and changes nothing; the run without it
/// (mass erase) succeeds, and so does one with the right password, which keeps what the
/// new image does not touch.
#[test]
fn msp430_wrong_password_is_named_and_the_board_recovers() {
    let memory = erased_flash_image("msp430-password.flash");
    let sim = msp430_board(&["--flash-image", &memory]);
    let old = msp430_hex("old.hex", &random_bytes(2048, 41), &[]);
    ok(&flash(&old, &sim.pty, &["--chip", "msp430f168"]));
    let before = msp430_memory(&memory);

    let mut other_vectors = random_bytes(32, 42);
    other_vectors[30..].copy_from_slice(&[0x00, 0x40]);
    let wrong = firmware_file("wrong.hex", to_hex(0xFFE0, &other_vectors));
    let new = msp430_hex("new.hex", &random_bytes(100, 43), &[]);
    let args = flash(
        &new,
        &sim.pty,
        &["--chip", "msp430f168", "--password", &wrong],
    );
    let err = fails(&args);
    assert!(
        err.contains(&format!(
            "RX password: the BSL refused the password from {wrong}"
        )),
        "{err}"
    );
    assert!(
        msp430_memory(&memory) == before,
        "a refused password changed the flash"
    );

    let err = ok(&flash(
        &new,
        &sim.pty,
        &["--chip", "msp430f168", "--password", &old],
    ))
    .stderr;
    assert!(err.contains("erased segments [0x4000, 0xfe00]"), "{err}");
    let mem = msp430_memory(&memory);
    // The old image's second KiB (another segment) is kept.
    assert!(mem[0x4200..0x4800] == before[0x4200..0x4800]);

    let err = ok(&flash(&new, &sim.pty, &["--chip", "msp430f168"])).stderr;
    assert!(err.contains("mass-erased"), "{err}");
    assert!(msp430_memory(&memory)[0x4200..0x4800]
        .iter()
        .all(|&b| b == 0xFF));
}

/// Answers with wrong checksums: the error names the command and what was wrong; the
/// same command on a clean line then flashes the board.
#[test]
fn msp430_checksum_errors_are_named_and_the_board_recovers() {
    let memory = erased_flash_image("msp430-checksum.flash");
    let hex = msp430_hex("checksum.hex", &random_bytes(3000, 51), &[]);
    let sim = msp430_board(&["--flash-image", &memory, "--corrupt-answers"]);
    let args = flash(&hex, &sim.pty, &["--chip", "msp430f168"]);
    let err = fails(&args);
    assert!(
        err.contains("TX BSL version (version): the chip's answer is damaged (checksum"),
        "{err}"
    );
    drop(sim);
    // The board on a clean line (a new pty: the port path is the sim's).
    let sim = msp430_board(&["--flash-image", &memory]);
    let err = ok(&flash(&hex, &sim.pty, &["--chip", "msp430f168"])).stderr;
    assert!(err.contains("verified"), "{err}");
}

/// An image reaching past the end of flash is refused before the board is touched,
/// naming the range and the chip's map.
#[test]
fn msp430_a_write_past_flash_is_refused_before_touching_the_board() {
    let memory = erased_flash_image("msp430-past.flash");
    let sim = msp430_board(&["--flash-image", &memory]);
    let bin = firmware_file("past.bin", random_bytes(0x200, 61));
    let err = fails(&flash(
        &bin,
        &sim.pty,
        &["--chip", "msp430f168", "--address", "0xff00"],
    ));
    assert!(
        err.contains(
            "the image covers 0xff00..0x10100, outside the MSP430F168's flash \
             (information memory 0x1000..0x1100, main flash 0x4000..0x10000)"
        ),
        "{err}"
    );
    assert!(msp430_memory(&memory).iter().all(|&b| b == 0xFF));
    let err = ok(&flash(
        &bin,
        &sim.pty,
        &["--chip", "msp430f168", "--address", "0xfe00"],
    ))
    .stderr;
    assert!(err.contains("verified"), "{err}");
}

/// The board stops answering in the middle of the image (the sim exits after 10 RX data
/// blocks, a board losing power): the error names the block; powered again, the same
/// command flashes it completely.
#[test]
fn msp430_an_interrupted_flash_is_completed_by_a_second_run() {
    let memory = erased_flash_image("msp430-interrupted.flash");
    let code = random_bytes(8192, 71);
    let hex = msp430_hex("interrupted.hex", &code, &[]);
    let sim = msp430_board(&["--flash-image", &memory, "--exit-after-writes", "10"]);
    let args = flash(&hex, &sim.pty, &["--chip", "msp430f168"]);
    let err = fails(&args);
    // The 10th block's ACK may or may not cross the pty before the sim exits: the error
    // names the 10th block (its answer lost) or the 11th (no answer to its SYNC).
    assert!(
        err.contains("block at 0x00004480 failed") || err.contains("block at 0x00004500 failed"),
        "{err}"
    );
    let log = sim_stderr_after(sim, std::time::Duration::from_secs(10));
    assert!(log.contains("exiting after 10 writes"), "{log}");
    let half = msp430_memory(&memory);
    assert!(half[0x4000..0x4500] == code[..0x500]);
    assert!(half[0x4500..0xFFE0].iter().all(|&b| b == 0xFF));

    // Power back on (a new pty: the port path is the sim's).
    let sim = msp430_board(&["--flash-image", &memory]);
    let err = ok(&flash(&hex, &sim.pty, &["--chip", "msp430f168"])).stderr;
    assert!(
        err.contains("mass-erased; wrote 8224 bytes in 65 blocks, verified"),
        "{err}"
    );
    drop(sim);
    assert!(msp430_memory(&memory)[0x4000..0x6000] == code[..]);
}
