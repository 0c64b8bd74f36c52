//! The MSP430F2617 board binary under mspdebug's simulator: built with the pinned
//! nightly (`firmware/msp430-toolchain`), run with a small raster job, its SPI writes
//! held to those of the same controller built for this host, its RAM held to the part's
//! 8 KiB. `cargo xtask setup` installs the toolchain and mspdebug; without them this
//! fails saying so, it never skips.

#[allow(dead_code)]
#[path = "../examples/msp430_sim.rs"]
mod harness;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use protocol::bus::LayoutId;
use protocol::fitkit_spi::{ADDR_READ, ADDR_STATUS};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}

/// The pinned nightly's name, as xtask installs it.
fn toolchain() -> String {
    let file = workspace().join("firmware/msp430-toolchain");
    std::fs::read_to_string(&file)
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
        .trim()
        .to_string()
}

/// Builds the board binary for `part` and returns its path; `checked` builds it with
/// overflow checks (into a target folder of its own, so that neither build undoes the
/// other's).
fn build(part: &str, checked: bool) -> PathBuf {
    let toolchain = toolchain();
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace().join("target"));
    let target_dir = if checked {
        target.join("msp430-overflow-checked")
    } else {
        target.clone()
    };
    let status = Command::new("cargo")
        .current_dir(workspace())
        .env("FPGFX_MSP430_PART", part)
        .env("CARGO_TARGET_DIR", &target_dir)
        .env(
            "CARGO_PROFILE_FIRMWARE_OVERFLOW_CHECKS",
            if checked { "true" } else { "false" },
        )
        // The outer cargo's toolchain must not leak into the nested build.
        .env_remove("RUSTUP_TOOLCHAIN")
        .env_remove("RUSTC")
        .arg(format!("+{toolchain}"))
        .args([
            "build",
            "-q",
            "-Zbuild-std=core",
            "--target",
            "msp430-none-elf",
        ])
        .args([
            "-p",
            "firmware",
            "--features",
            "board-msp430",
            "--profile",
            "firmware",
        ])
        .status()
        .expect("cargo runs");
    assert!(
        status.success(),
        "building the MSP430 binary with {toolchain} failed (run `cargo xtask setup` to \
         install the toolchain and its rust-src)"
    );
    let elf = target_dir.join("msp430-none-elf/firmware/fpgfx-firmware-msp430");
    // Another part's build would overwrite it: keep this one's apart.
    let suffix = if checked { "-checked" } else { "" };
    let copy = target.join(format!(
        "msp430-sim/fpgfx-firmware-msp430-{part}{suffix}.elf"
    ));
    std::fs::create_dir_all(copy.parent().unwrap_or(&target)).expect("target dir");
    std::fs::copy(&elf, &copy).expect("the ELF exists after the build");
    copy
}

/// The F2617 binary, built once for the tests of this file.
fn f2617() -> &'static Path {
    static ELF: OnceLock<PathBuf> = OnceLock::new();
    ELF.get_or_init(|| {
        mspdebug_installed();
        build("f2617", false)
    })
}

fn mspdebug_installed() {
    assert!(
        Command::new("mspdebug").arg("--version").output().is_ok(),
        "mspdebug is not installed: run `cargo xtask setup`"
    );
}

#[test]
fn msp430_f2617_under_mspdebug_shifts_the_host_builds_spi_bytes() {
    let elf = f2617();
    let out = elf.with_extension("out");
    let report = harness::run(&elf.to_string_lossy(), &out).expect("the simulator run");
    println!("{}", report.summary.join("\n"));
    assert_eq!(report.part, 2617, "the binary drives the F2617's registers");
    assert!(
        report.same,
        "SPI writes differ from the host build's: {:?}",
        report.summary
    );
    stack_has_room(&report);
}

/// The stack must stay clear of .bss, with room to spare for paths the job does not
/// take: at least 512 B untouched (docs/firmware.md gives the figures).
fn stack_has_room(report: &harness::Report) {
    assert!(
        report.stack + 512 <= report.stack_room,
        "stack {} B of {} B between .bss and the top of RAM",
        report.stack,
        report.stack_room
    );
}

/// The SPI write transactions `fpgfx vectors` gives for `text` on the FITkit (the stream
/// the built-in target's model is fed and the STM32 board's driver sends), or `None`
/// when the FITkit layout refuses the job.
fn vectors_stream(text: &str, file: &str) -> Option<Vec<Vec<u8>>> {
    let set = vectors::raster::raster(text, file, LayoutId::Fitkit).ok()?;
    let words = |name: &str| -> Vec<u64> {
        let f = set
            .file(name)
            .unwrap_or_else(|| panic!("{file}: no {name}"));
        compare::memh::parse(&String::from_utf8_lossy(&f.bytes))
            .unwrap_or_else(|e| panic!("{file}: {name}: {e}"))
            .words
    };
    let bytes: Vec<u8> = words(vectors::raster::SPI_BYTES)
        .iter()
        .map(|&b| b as u8)
        .collect();
    Some(
        words(vectors::raster::SPI_FRAMES)
            .iter()
            .map(|&w| {
                let (start, len) = ((w >> 8) as usize, (w & 0xFF) as usize);
                bytes[start..start + len].to_vec()
            })
            .collect(),
    )
}

/// Every gallery job the FITkit carries, as `fpgfx raster` sends it over the host link,
/// through the MSP430 under the simulator: its SPI writes (status reads and the
/// read-back aside) are byte for byte the stream `fpgfx vectors` derives for the same
/// job, and the host build's.
#[test]
fn msp430_f2617_sends_the_fitkit_gallery_as_the_built_in_target() {
    gallery(f2617(), "gallery");
}

/// The protocol and the controller with a 16-bit `usize`: the binary built with overflow
/// checks (on mspdebug's flat memory, `FPGFX_MSP430_PART=sim`, the F168's registers:
/// the checks' code does not fit the F2617's flash), so an arithmetic overflow anywhere
/// on the paths the jobs take panics, and the panic's exit ends the run with an error.
/// It runs this file's first job and the gallery.
#[test]
fn msp430_overflow_checked_build_runs_the_jobs_without_a_16_bit_overflow() {
    mspdebug_installed();
    let elf = build("sim", true);
    let out = elf.with_extension("out");
    let report = harness::run(&elf.to_string_lossy(), &out)
        .unwrap_or_else(|e| panic!("the overflow-checked build's run: {e}"));
    assert_eq!(report.part, 168, "the sim map plays the F168's registers");
    assert!(report.same, "{:?}", report.summary);
    gallery(&elf, "gallery-checked");
}

/// Runs every gallery job the FITkit carries through `elf` (outputs in `PREFIX-STEM.out`
/// beside it) and holds its SPI writes to `fpgfx vectors`' stream and the host build's.
fn gallery(elf: &Path, prefix: &str) {
    let dir = workspace().join("examples/raster");
    let mut jobs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("examples/raster")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    jobs.sort();
    let mut carried = Vec::new();
    for path in &jobs {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).expect("a gallery file");
        let Some(expected) = vectors_stream(&text, &file) else {
            continue;
        };
        let job = jobs::raster::parse(&text, &file).expect("a gallery job parses");
        let frames = harness::job_frames(job.setup, &job.cmds).expect("the job's frames");
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("job");
        let out = elf.with_file_name(format!("{prefix}-{stem}.out"));
        let report = harness::run_job(&elf.to_string_lossy(), &out, &frames, &[])
            .unwrap_or_else(|e| panic!("{file}: the simulator run: {e}"));
        let writes: Vec<Vec<u8>> = report
            .spi
            .into_iter()
            .filter(|t| !matches!(t.first(), Some(&ADDR_STATUS) | Some(&ADDR_READ)))
            .collect();
        assert_eq!(
            writes,
            expected,
            "{file}: the MSP430's SPI writes differ from fpgfx vectors' stream ({})",
            out.display()
        );
        assert!(report.same, "{file}: {:?}", report.summary);
        carried.push(stem.to_string());
    }
    assert!(
        carried.iter().any(|s| s == "fitkit"),
        "fitkit.toml must be among the jobs the FITkit carries: {carried:?}"
    );
}

/// A frame longer than any buffer of the board's link (here 3 000 bytes without a
/// delimiter, past `MAX_FRAME`) before the job: the link discards it and counts an
/// overflow, nothing overruns a buffer, and the job after it runs as without it.
#[test]
fn msp430_f2617_discards_an_over_long_frame_and_runs_the_job_after_it() {
    let elf = f2617();
    let noise = vec![0x55u8; 3_000];
    assert!(noise.len() > protocol::link::MAX_FRAME);
    let out = elf.with_file_name("over-long.out");
    let report = harness::run_job(&elf.to_string_lossy(), &out, &harness::job(), &noise)
        .unwrap_or_else(|e| panic!("the simulator run: {e}"));
    assert!(report.same, "{:?}", report.summary);
    let stats = report
        .answers
        .iter()
        .find_map(|a| match a {
            protocol::frame::DeviceFrame::Stats(s) => Some(*s),
            _ => None,
        })
        .expect("the job's statistics");
    assert!(
        stats.link.overflows >= 1,
        "the board's link counted no overflow: {:?}",
        stats.link
    );
    stack_has_room(&report);
}
