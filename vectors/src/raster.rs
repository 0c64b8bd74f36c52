//! `fpgfx vectors raster`: a raster job as test vectors for the raster block.
//!
//! Three sources, each the one that owns its fact:
//!
//! * the SPI stream comes from the controller's own FITkit driver
//!   ([`firmware::FitkitSpi`]) run against a recording SPI device, fed the packets the
//!   controller packs ([`jobs::raster::pack_job`]), so the bytes are the board's;
//! * the FIFO records are what the block's address decoder cuts from that stream (on
//!   the FITkit) or the packets themselves (layouts without SPI framing);
//! * the fragment stream and the framebuffer come from the golden model
//!   ([`sim_target::Device`] on the layout, decoding those records), its framebuffer
//!   writes recorded in order ([`sim_target::raster::FbWrite`]); on the FITkit the
//!   model walks the bounding box as the RTL does, so its cycle counters are the RTL's.

use compare::memh::{self, FrameHeader, PixelFormat};
use embedded_hal::delay::DelayNs;
use embedded_hal::spi::{ErrorKind, ErrorType, Operation, SpiDevice};
use firmware::{FitkitSpi, FitkitSpiError, FpgaBus};
use protocol::axi_lite;
use protocol::bus::LayoutId;
use protocol::bus::{rgb332_encode, BusLayout};
use protocol::fitkit_spi::{Status, ADDR_STATUS, FIFO_RECORDS, FLAG_FIFO_EMPTY, RECORD_BITS};
use protocol::raster::{RasterSetup, Rgb, Traversal};
use serde::Serialize;
use sim_target::raster::{FbWrite, Stats};

use super::{fill, job_hash, FileEntry, VectorFile, VectorSet, VectorsError};
use jobs::raster::{Packet, RasterJob};

/// The testbench template: sizes and expected counters are `@NAME@` placeholders.
const TESTBENCH: &str = include_str!("../../hw/fitkit-raster/vectors/tb_fpgfx.v");
/// The Icarus run script.
const RUN_IVERILOG: &str = include_str!("../../hw/fitkit-raster/vectors/run-iverilog.sh");
/// The SPI master tasks tb_fpgfx.v includes: the block's own testbenches use the same file.
const SPI_TASKS: &str = include_str!("../../hw/fitkit-raster/tb/spi_tasks.vh");
/// The SPI map tb_fpgfx.v includes, generated from `protocol::fitkit_spi::MAP`.
const FITKIT_MAP: &str = include_str!("../../hw/fitkit-raster/rtl/fitkit_map.vh");
/// The Verilator run script.
const RUN_VERILATOR: &str = include_str!("../../hw/fitkit-raster/vectors/run-verilator.sh");

/// Bits of a fragment word's x and y fields: 12, for frames up to 4096 pixels a side
/// (`protocol::MAX_FRAME_SIDE`), so each is three hex digits a reader can see.
const COORD_BITS: u32 = 12;

/// Writes `job_text` (the raster job `file`, as `fpgfx raster` reads it) as test
/// vectors for a raster block taking `layout`'s records. The FITkit set includes the
/// SPI stream, the Verilog testbench and its run scripts; the other layouts have no
/// SPI framing and no RTL here, so their sets stop at records, fragments and frame.
pub fn raster(job_text: &str, file: &str, layout: LayoutId) -> Result<VectorSet, VectorsError> {
    let Trace {
        job,
        spi: transactions,
        records,
        writes,
        frame,
        stats,
    } = trace(job_text, file, layout)?;
    let fitkit = layout == LayoutId::Fitkit;
    let bus = layout.layout();
    let model = ModelRun {
        writes,
        frame,
        stats,
    };
    let format = if fitkit {
        PixelFormat::Rgb332
    } else {
        PixelFormat::Rgb888
    };
    let (width, height) = (u32::from(job.setup.width), u32::from(job.setup.height));
    let word = |c: Rgb| -> Result<u64, VectorsError> {
        match format {
            PixelFormat::Rgb332 => {
                rgb332_encode(c)
                    .map(u64::from)
                    .ok_or_else(|| VectorsError::Model {
                        file: file.into(),
                        message: format!("colour {c:?} is not an RGB332 colour on the FITkit"),
                    })
            }
            _ => Ok(u64::from(c.r) << 16 | u64::from(c.g) << 8 | u64::from(c.b)),
        }
    };
    let hash = job_hash(job_text.as_bytes());
    let origin = format!("fpgfx {} vectors raster of {file} ({hash})", version());

    let mut files = vec![setup_file(&job.setup, layout, &origin)];
    if let Some(t) = &transactions {
        files.extend(spi_files(t, &origin));
    }
    files.push(fifo_file(&records, bus, &origin));

    let color_bits = 4 * format.digits() as u32;
    let mut frags = Vec::new();
    for w in &model.writes {
        let entry = |kind: u64, x: u32, y: u32, c: u64| {
            kind << (2 * COORD_BITS + color_bits)
                | u64::from(y) << (COORD_BITS + color_bits)
                | u64::from(x) << color_bits
                | c
        };
        match *w {
            FbWrite::Clear(c) => {
                let c = word(c)?;
                for y in 0..height {
                    frags.extend((0..width).map(|x| entry(0, x, y, c)));
                }
            }
            FbWrite::Pixel { x, y, color } => frags.push(entry(1, x, y, word(color)?)),
        }
    }
    let frag_digits = 1 + 2 * COORD_BITS as usize / 4 + format.digits();
    let frag_entry = FileEntry {
        name: FRAGMENTS,
        words: frags.len(),
        word_bits: 4 * frag_digits as u32,
        content: "one framebuffer write each, in the order the block's memory port issues \
                  them: kind (1 fragment, 0 clear), y, x, colour",
    };
    files.push(data_file(
        memh::format(
            &[
                &origin,
                &format!(
                    "{FRAGMENTS}: {} writes, one per line: K YYY XXX {}, K = 1 a drawing \
                     fragment, 0 a clear's write (docs/vectors.md)",
                    frags.len(),
                    "C".repeat(format.digits())
                ),
            ],
            frags,
            frag_digits,
        ),
        frag_entry,
    ));

    let header = FrameHeader {
        width,
        height,
        format,
    };
    let pixels = model
        .frame
        .iter()
        .map(|&c| word(c))
        .collect::<Result<Vec<_>, _>>()?;
    files.push(data_file(
        memh::format_frame(&header, pixels.iter().copied()),
        FileEntry {
            name: FRAMEBUFFER,
            words: pixels.len(),
            word_bits: 4 * format.digits() as u32,
            content: "the final frame, row-major (compare::memh, header `fpgfx framebuffer`)",
        },
    ));
    files.push(VectorFile {
        name: JOB,
        bytes: job_text.as_bytes().to_vec(),
        executable: false,
        entry: None,
    });

    let expected = fitkit.then(|| ExpectedStatus::of(&model.stats));
    if let (Some(t), Some(e)) = (&transactions, &expected) {
        let spi_bytes: usize = t.iter().map(Vec::len).sum();
        let values = [
            ("VERSION", version().to_string()),
            ("JOB", file.to_string()),
            ("JOB_HASH", hash.clone()),
            ("WIDTH", width.to_string()),
            ("HEIGHT", height.to_string()),
            ("SPI_BYTES", spi_bytes.to_string()),
            ("SPI_FRAMES", t.len().to_string()),
            ("FRAGMENTS", files_words(&files, FRAGMENTS).to_string()),
            ("EXP_PACKETS", e.packets.to_string()),
            ("EXP_FRAGMENTS", e.fragments.to_string()),
            ("EXP_LINE_CYCLES", e.line_cycles.to_string()),
            ("EXP_TRI_CYCLES", e.triangle_cycles.to_string()),
            ("EXP_CLEAR_CYCLES", e.clear_cycles.to_string()),
            (
                "CYCLE_LIMIT",
                cycle_limit(spi_bytes, t.len(), &model.stats, width, height).to_string(),
            ),
        ];
        for (name, template, executable) in [
            (TESTBENCH_FILE, TESTBENCH, false),
            (RUN_IVERILOG_FILE, RUN_IVERILOG, true),
            (RUN_VERILATOR_FILE, RUN_VERILATOR, true),
            (SPI_TASKS_FILE, SPI_TASKS, false),
            (FITKIT_MAP_FILE, FITKIT_MAP, false),
        ] {
            files.push(VectorFile {
                name,
                bytes: fill(template, &values).into_bytes(),
                executable,
                entry: None,
            });
        }
    }

    let manifest = Manifest {
        generator: "fpgfx vectors raster",
        fpgfx_version: version(),
        layout: bus.name,
        job: JOB,
        job_source: file,
        job_hash: hash,
        width,
        height,
        pixel_format: format.name(),
        testbench: if fitkit {
            "tb_fpgfx.v: fitkit_raster's ports (docs/rtl.md); sh run-iverilog.sh RTL_DIR or sh run-verilator.sh RTL_DIR"
        } else {
            "none: the Verilog testbench targets the FITkit top level (fitkit_raster); this layout has no SPI framing or RTL here"
        },
        file: files.iter().filter_map(|f| f.entry.clone()).collect(),
        expected_status: expected,
    };
    let text = toml::to_string(&manifest).map_err(|e| VectorsError::Model {
        file: file.into(),
        message: format!("the manifest does not serialise: {e}"),
    })?;
    files.push(VectorFile {
        name: MANIFEST,
        bytes: format!("# {origin}\n# Every file and its format: docs/vectors.md.\n{text}")
            .into_bytes(),
        executable: false,
        entry: None,
    });
    Ok(VectorSet { files })
}

/// A raster job run through the golden model on one bus layout: everything a vector set
/// is written from, in memory, for a front end that wants the data rather than the files
/// (the Python package's scoreboard hands it to a cocotb testbench).
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Trace {
    /// The job as run: on the FITkit with the bounding-box traversal its RTL walks, so
    /// that the counters are the RTL's; on the other layouts as the file says.
    pub job: RasterJob,
    /// The SPI write transactions of the controller's FITkit driver, the set-up's first,
    /// each one CS_n-low period (address byte and payload); `None` off the FITkit, whose
    /// other layouts have no SPI framing.
    pub spi: Option<Vec<Vec<u8>>>,
    /// The input FIFO's records, one entry per packet: the FIFO tag (the FITkit's SPI
    /// channel, else 0) and the packet's records, in the order they are pushed.
    pub records: Vec<(u8, Vec<u64>)>,
    /// Every framebuffer write in the order the block's memory port issues them, the
    /// set-up's clear first.
    pub writes: Vec<FbWrite>,
    /// The final frame, row-major.
    pub frame: Vec<Rgb>,
    /// The block's counters after the job (the set-up's clear counted).
    pub stats: Stats,
}

/// Runs `job_text` (the raster job `file`, as `fpgfx raster` reads it) through the golden
/// model on `layout`, as [`raster`] does before it writes the files: the packets the
/// controller packs, on the FITkit the SPI stream its driver makes of them and the records
/// the block's decoder cuts from it, and the model's framebuffer writes, frame and counters.
pub fn trace(job_text: &str, file: &str, layout: LayoutId) -> Result<Trace, VectorsError> {
    let Packing { job, packets, spi } = pack(job_text, file, layout)?;
    let model = run_model(&job.setup, &packets, layout.layout(), file)?;
    let records = match &spi {
        Some(t) => t.iter().map(|t| decoder_records(t)).collect(),
        None => packets.iter().map(|(_, r)| (0, r.to_vec())).collect(),
    };
    Ok(Trace {
        job,
        spi,
        records,
        writes: model.writes,
        frame: model.frame,
        stats: model.stats,
    })
}

/// A raster job packed as the controller sends it, without running the model: what a
/// testbench that drives the block itself needs ([`pack`]).
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Packing {
    /// The job as packed: on the FITkit with the bounding-box traversal, as in [`Trace`].
    pub job: RasterJob,
    /// One packet per command, in file order: the controller's channel (on the FITkit the
    /// SPI address) and the FIFO records.
    pub packets: Vec<Packet>,
    /// On the FITkit, the SPI write transactions of the controller's driver: the set-up's
    /// first, then one per packet, each one CS_n-low period (address byte and payload).
    pub spi: Option<Vec<Vec<u8>>>,
}

/// Parses `job_text` (the raster job `file`) and packs it for `layout` as the controller
/// does, refusing what the controller or the layout would refuse, naming the command;
/// on the FITkit also the SPI transactions its driver makes of the packets.
pub fn pack(job_text: &str, file: &str, layout: LayoutId) -> Result<Packing, VectorsError> {
    let mut job = jobs::raster::parse(job_text, file)?;
    let fitkit = layout == LayoutId::Fitkit;
    if fitkit {
        // Coverage is the same for every traversal; the counters are the RTL's only for
        // the one its triangle unit walks.
        job.setup.traversal = Traversal::BoundingBox;
    }
    let packets = jobs::raster::pack_job(&job, file, layout.layout())?;
    // The controller's refusals first: they name what the user can change.
    let spi = fitkit
        .then(|| spi_transactions(&job.setup, &packets, file))
        .transpose()?;
    Ok(Packing { job, packets, spi })
}

/// `raster_setup.hex`: the frame-wide set-up the model ran, for a testbench whose DUT
/// takes it as parameters rather than over SPI (a C model, an HLS block).
pub const SETUP: &str = "raster_setup.hex";
/// `spi_bytes.hex`: the MOSI bytes.
pub const SPI_BYTES: &str = "spi_bytes.hex";
/// `spi_frames.hex`: where each CS_n-low transaction starts and how long it is.
pub const SPI_FRAMES: &str = "spi_frames.hex";
/// `fifo_records.hex`: the input FIFO's records with tag and packet end.
pub const FIFO_RECORDS_FILE: &str = "fifo_records.hex";
/// `expected_fragments.hex`: every framebuffer write in order.
pub const FRAGMENTS: &str = "expected_fragments.hex";
/// `expected_framebuffer.hex`: the final frame.
pub const FRAMEBUFFER: &str = "expected_framebuffer.hex";
/// `job.toml`: the job file, byte for byte.
pub const JOB: &str = "job.toml";
/// `manifest.toml`: layout, sizes, counts, version, the job's hash.
pub const MANIFEST: &str = "manifest.toml";
/// `tb_fpgfx.v`: the self-checking testbench (FITkit only).
pub const TESTBENCH_FILE: &str = "tb_fpgfx.v";
/// `run-iverilog.sh`: builds and runs the testbench with Icarus (FITkit only).
pub const RUN_IVERILOG_FILE: &str = "run-iverilog.sh";
/// `run-verilator.sh`: builds and runs the testbench with Verilator (FITkit only).
pub const RUN_VERILATOR_FILE: &str = "run-verilator.sh";
/// `spi_tasks.vh`: the SPI master tasks the testbench includes (FITkit only).
pub const SPI_TASKS_FILE: &str = "spi_tasks.vh";
/// `fitkit_map.vh`: the SPI map the testbench includes (FITkit only).
pub const FITKIT_MAP_FILE: &str = "fitkit_map.vh";

fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

fn files_words(files: &[VectorFile], name: &str) -> usize {
    files
        .iter()
        .find(|f| f.name == name)
        .and_then(|f| f.entry.as_ref())
        .map_or(0, |e| e.words)
}

/// `raster_setup.hex`: one word per field, in the order of the C library's
/// `fpgfx_raster_setup` after the layout; each enum is its index in protocol's `ALL`
/// table (the AXI4-Lite raster registers' codes, `protocol::axi_lite`), which is how
/// `FPGFX_LAYOUT_*`, `FPGFX_AA_*`, `FPGFX_CULL_*` and `FPGFX_TRAVERSAL_*` are numbered.
fn setup_file(setup: &RasterSetup, layout: LayoutId, origin: &str) -> VectorFile {
    let bg = setup.background;
    let words = [
        // Every layout is in the table (its `of` looks it up there).
        LayoutId::ALL.iter().position(|&l| l == layout).unwrap_or(0) as u64,
        u64::from(setup.width),
        u64::from(setup.height),
        u64::from(setup.subpixel_bits),
        u64::from(bg.r),
        u64::from(bg.g),
        u64::from(bg.b),
        u64::from(axi_lite::aa_pattern_code(setup.aa.pattern)),
        u64::from(setup.aa.samples),
        u64::from(axi_lite::cull_code(setup.cull)),
        u64::from(axi_lite::traversal_code(setup.traversal)),
    ];
    data_file(
        memh::format(
            &[
                origin,
                &format!(
                    "{SETUP}: layout width height subpixel_bits bg_r bg_g bg_b aa_pattern \
                     aa_samples cull traversal, one per line (docs/vectors.md)"
                ),
            ],
            words,
            8,
        ),
        FileEntry {
            name: SETUP,
            words: words.len(),
            word_bits: 32,
            content: "the set-up the model ran: layout, width, height, subpixel_bits, \
                      background r g b, aa pattern, aa samples, cull, traversal \
                      (the C library's codes)",
        },
    )
}

fn data_file(text: String, entry: FileEntry) -> VectorFile {
    VectorFile {
        name: entry.name,
        bytes: text.into_bytes(),
        executable: false,
        entry: Some(entry),
    }
}

/// What the golden model did with the job.
struct ModelRun {
    /// Every framebuffer write in order, the set-up's clear first.
    writes: Vec<FbWrite>,
    /// The final frame, row-major.
    frame: Vec<Rgb>,
    stats: Stats,
}

/// Runs the packets through the golden model's device, as the controller would push
/// them, with the block's framebuffer writes recorded from the set-up on.
fn run_model(
    setup: &RasterSetup,
    packets: &[Packet],
    layout: &'static BusLayout,
    file: &str,
) -> Result<ModelRun, VectorsError> {
    let refused = |message: String| VectorsError::Model {
        file: file.into(),
        message,
    };
    let mut dev = sim_target::Device::new(layout);
    dev.raster_setup(setup)
        .map_err(|e| refused(e.to_string()))?;
    let no_block = || refused("no raster block after the set-up".into());
    dev.raster_mut()
        .ok_or_else(no_block)?
        .framebuffer_mut()
        .record_writes(true);
    for (channel, records) in packets {
        while dev.fifo_free() < records.len() {
            dev.wait().map_err(|e| refused(e.to_string()))?;
        }
        dev.push_packet(*channel, records)
            .map_err(|e| refused(e.to_string()))?;
    }
    dev.drain().map_err(|e| refused(e.to_string()))?;
    let raster = dev.raster_mut().ok_or_else(no_block)?;
    // The set-up clears the frame before recording could start: it is the first write
    // stream the block issues.
    let mut writes = vec![FbWrite::Clear(setup.background)];
    writes.extend(raster.framebuffer_mut().take_writes());
    let fb = raster.framebuffer();
    let frame = (0..fb.height())
        .flat_map(|y| (0..fb.width()).map(move |x| (x, y)))
        .map(|(x, y)| fb.pixel(x, y).unwrap_or_default())
        .collect();
    Ok(ModelRun {
        writes,
        frame,
        stats: *raster.stats(),
    })
}

/// The SPI device the controller's FITkit driver writes to here: it keeps every write
/// transaction and answers the driver's status polls with an idle block and an empty
/// FIFO (the testbench replaces those polls with the FIFO_FREE pin, so they are not part
/// of the stream).
#[derive(Default)]
struct Recorder {
    transactions: Vec<Vec<u8>>,
}

/// A transaction the recorder cannot answer: the driver read something other than the
/// status block.
#[derive(Debug)]
struct NotRecordable;

impl embedded_hal::spi::Error for NotRecordable {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Other
    }
}

impl ErrorType for Recorder {
    type Error = NotRecordable;
}

impl SpiDevice for Recorder {
    fn transaction(&mut self, ops: &mut [Operation<'_, u8>]) -> Result<(), NotRecordable> {
        match ops {
            [Operation::Write([ADDR_STATUS]), Operation::Read(buf)] => {
                let idle = Status {
                    free: FIFO_RECORDS,
                    flags: FLAG_FIFO_EMPTY,
                    ..Status::default()
                }
                .encode();
                let n = buf.len().min(idle.len());
                buf[..n].copy_from_slice(&idle[..n]);
                Ok(())
            }
            [Operation::Write(bytes)] => {
                self.transactions.push(bytes.to_vec());
                Ok(())
            }
            _ => Err(NotRecordable),
        }
    }
}

/// No time passes: the recorder's FIFO is never full.
struct NoDelay;

impl DelayNs for NoDelay {
    fn delay_ns(&mut self, _ns: u32) {}
}

/// The write transactions the controller's FITkit driver makes for the set-up and the
/// packets, in order, each one CS_n-low period.
fn spi_transactions(
    setup: &RasterSetup,
    packets: &[Packet],
    file: &str,
) -> Result<Vec<Vec<u8>>, VectorsError> {
    let refused = |e: FitkitSpiError<NotRecordable>| VectorsError::Controller {
        file: file.into(),
        message: e.to_string(),
    };
    let mut driver = FitkitSpi::new(Recorder::default(), NoDelay);
    driver.raster_setup(setup).map_err(refused)?;
    for (channel, records) in packets {
        // The engine's back-pressure loop; the recorder always has room.
        while driver.fifo_free().map_err(refused)? < records.len() {
            driver.wait().map_err(refused)?;
        }
        driver.push_packet(*channel, records).map_err(refused)?;
    }
    Ok(driver.release().0.transactions)
}

/// What the block's address decoder makes of one write transaction: the channel (its
/// address byte, the FIFO tag) and the payload cut into 36-bit records, MSB first, the
/// padding bits dropped.
pub fn decoder_records(transaction: &[u8]) -> (u8, Vec<u64>) {
    let (&address, payload) = transaction.split_first().unwrap_or((&0, &[]));
    let bits = 8 * payload.len();
    let value = payload.iter().fold(0u128, |v, &b| v << 8 | u128::from(b));
    let n = bits / RECORD_BITS as usize;
    let mask = (1u128 << RECORD_BITS) - 1;
    let records = (0..n)
        .map(|k| ((value >> (bits - RECORD_BITS as usize * (k + 1))) & mask) as u64)
        .collect();
    (address, records)
}

/// `spi_bytes.hex` and `spi_frames.hex`.
fn spi_files(transactions: &[Vec<u8>], origin: &str) -> [VectorFile; 2] {
    let bytes: Vec<u64> = transactions
        .iter()
        .flatten()
        .map(|&b| u64::from(b))
        .collect();
    let mut start = 0u64;
    let frames: Vec<u64> = transactions
        .iter()
        .map(|t| {
            let w = start << 8 | t.len() as u64;
            start += t.len() as u64;
            w
        })
        .collect();
    [
        data_file(
            memh::format(
                &[
                    origin,
                    &format!(
                        "{SPI_BYTES}: {} bytes MOSI sends, MSB first, in order; {SPI_FRAMES} \
                         cuts them into CS_n-low transactions",
                        bytes.len()
                    ),
                ],
                bytes.iter().copied(),
                2,
            ),
            FileEntry {
                name: SPI_BYTES,
                words: bytes.len(),
                word_bits: 8,
                content: "one MOSI byte each, every transaction's address byte and payload",
            },
        ),
        data_file(
            memh::format(
                &[
                    origin,
                    &format!(
                        "{SPI_FRAMES}: {} transactions, one per line: SSSSSS LL = index of \
                         the first byte in {SPI_BYTES}, byte count (address byte included)",
                        frames.len()
                    ),
                ],
                frames.iter().copied(),
                8,
            ),
            FileEntry {
                name: SPI_FRAMES,
                words: frames.len(),
                word_bits: 32,
                content:
                    "one CS_n-low transaction each: first byte's index (24 bits), length (8 bits)",
            },
        ),
    ]
}

/// `fifo_records.hex`: per record a flag digit (4 = the packet's last record, plus the
/// 2-bit FIFO tag) above the record's digits. Written here rather than with
/// [`memh::format`] because a wide record and its flags exceed 64 bits.
fn fifo_file(packets: &[(u8, Vec<u64>)], layout: &BusLayout, origin: &str) -> VectorFile {
    let digits = usize::from(layout.record_bits).div_ceil(4);
    let mut text = memh::format(
        &[
            origin,
            &format!(
                "{FIFO_RECORDS_FILE}: input FIFO records of the {} layout ({}-bit), one per \
                 line: F {}; F = 4 · last record of its packet + FIFO tag (the FITkit's SPI \
                 channel, else 0)",
                layout.name,
                layout.record_bits,
                "R".repeat(digits)
            ),
        ],
        [],
        0,
    );
    let mut words = 0;
    for (tag, records) in packets {
        for (k, &r) in records.iter().enumerate() {
            let flags = u8::from(k + 1 == records.len()) << 2 | (tag & 3);
            text.push_str(&format!("{flags:x}{r:0digits$x}\n"));
            words += 1;
        }
    }
    data_file(
        text,
        FileEntry {
            name: FIFO_RECORDS_FILE,
            words,
            word_bits: 4 * (digits as u32 + 1),
            content:
                "one input FIFO record each: flags (bit 2 last of packet, bits 1:0 tag), record",
        },
    )
}

/// The status block's counters after the job, as the model counts them (docs/rtl.md:
/// counters zeroed by the set-up, the set-up's clear counted).
#[derive(Debug, Clone, Serialize)]
struct ExpectedStatus {
    /// Line, triangle and clear packets executed.
    packets: u32,
    /// Drawing fragments written (clear writes excluded).
    fragments: u32,
    /// Line unit busy cycles.
    line_cycles: u32,
    /// Triangle unit busy cycles.
    triangle_cycles: u32,
    /// Clear cycles (the set-up's and the clear packets').
    clear_cycles: u32,
}

impl ExpectedStatus {
    fn of(s: &Stats) -> Self {
        // The block's counters are free-running 32-bit: compare modulo 2^32 as it does.
        Self {
            packets: s.commands as u32,
            fragments: s.fragments as u32,
            line_cycles: s.cycles.line as u32,
            triangle_cycles: s.cycles.triangle as u32,
            clear_cycles: s.cycles.clear as u32,
        }
    }
}

/// The testbench's default bound in clk cycles: twice everything it can ask of the block
/// (every SPI bit at f_clk / 8 with the gaps, the model's busy cycles plus executor
/// overhead, a read-back of the whole frame and two status reads), plus a margin; the
/// testbench scales it up under `+mem_wait`.
fn cycle_limit(spi_bytes: usize, frames: usize, stats: &Stats, width: u32, height: u32) -> u64 {
    let spi = 64 * spi_bytes as u64 + 32 * frames as u64;
    let work = stats.total_cycles() + 8 * stats.commands;
    let read_back = u64::from(height) * (u64::from(width) + 5) * 64 + 2 * 33 * 64;
    2 * (spi + work + read_back) + 100_000
}

#[derive(Serialize)]
struct Manifest<'a> {
    generator: &'static str,
    fpgfx_version: &'static str,
    layout: &'static str,
    job: &'static str,
    job_source: &'a str,
    job_hash: String,
    width: u32,
    height: u32,
    pixel_format: &'static str,
    testbench: &'static str,
    file: Vec<FileEntry>,
    #[serde(skip_serializing_if = "Option::is_none")]
    expected_status: Option<ExpectedStatus>,
}

#[cfg(test)]
mod tests {
    use super::*;

    const JOB_TEXT: &str = r##"
size = [64, 48]
background = "#000055"
subpixel_bits = 0

[[cmd]]
op = "line"
from = [1.0, 2.0]
to = [60.0, 40.0]
color = "#ffffff"

[[cmd]]
op = "triangle"
v = [[5.0, 5.0], [50.0, 10.0], [20.0, 45.0]]
color = "#ffff00"

[[cmd]]
op = "clear"
color = "#ff0000"
"##;

    #[test]
    fn the_decoder_records_are_the_packers() {
        let job = jobs::raster::parse(JOB_TEXT, "t.toml").expect("job");
        let packets =
            jobs::raster::pack_job(&job, "t.toml", &protocol::bus::FITKIT).expect("fitkit");
        let t = spi_transactions(&job.setup, &packets, "t.toml").expect("spi");
        assert_eq!(t.len(), 1 + packets.len(), "a set-up, then one per command");
        assert_eq!(t[0][0], protocol::fitkit_spi::ADDR_SETUP);
        for (t, (channel, records)) in t[1..].iter().zip(&packets) {
            assert_eq!(decoder_records(t), (*channel, records.to_vec()));
        }
        // The docs/protocol.md test vector: line 0x01, records 0x8_0405_2CC8, 0x5_4800_0000.
        let bytes = [0x01, 0x80, 0x40, 0x52, 0xcc, 0x85, 0x48, 0x00, 0x00, 0x00];
        assert_eq!(
            decoder_records(&bytes),
            (1, vec![0x8_0405_2cc8, 0x5_4800_0000])
        );
    }

    #[test]
    fn fragments_start_with_the_set_up_clear_and_count_the_model() {
        let set = raster(JOB_TEXT, "t.toml", LayoutId::Fitkit).expect("vectors");
        let frags = memh::parse(set.file(FRAGMENTS).expect("fragments").text()).expect("memh");
        // Set-up clear, line, triangle, clear packet; words K YYY XXX CC.
        let word = |k: u64, x: u64, y: u64, c: u64| k << 32 | y << 20 | x << 8 | c;
        assert_eq!(
            frags.words[0],
            word(0, 0, 0, 0x01),
            "background #000055 is RGB332 0x01"
        );
        assert_eq!(
            frags.words[64 * 48],
            word(1, 1, 2, 0xff),
            "the line starts at (1, 2)"
        );
        let drawn = frags.words.iter().filter(|w| *w >> 32 == 1).count();
        assert_eq!(frags.words.len(), 2 * 64 * 48 + drawn);
        let (header, frame) =
            memh::parse_frame(set.file(FRAMEBUFFER).expect("frame").text()).expect("frame");
        assert_eq!((header.width, header.height), (64, 48));
        assert!(
            frame.iter().all(|&p| p == 0xe0),
            "the clear packet came last"
        );
        let manifest = &set.file(MANIFEST).expect("manifest").text();
        assert!(
            manifest.contains(&format!("fragments = {drawn}")),
            "{manifest}"
        );
        for name in [
            TESTBENCH_FILE,
            RUN_IVERILOG_FILE,
            RUN_VERILATOR_FILE,
            SPI_TASKS_FILE,
            FITKIT_MAP_FILE,
        ] {
            let text = &set
                .file(name)
                .expect("a FITkit set has the testbench")
                .text();
            // A placeholder is an upper-case name between two `@` (Verilog's `@(` and
            // the shell's `$@` never enclose one).
            let parts: Vec<&str> = text.split('@').collect();
            let inner = parts.get(1..parts.len().saturating_sub(1)).unwrap_or(&[]);
            let unfilled = inner
                .iter()
                .find(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_uppercase() || b == b'_'));
            assert_eq!(unfilled, None, "{name}: an unfilled placeholder");
        }
    }

    #[test]
    fn other_layouts_have_no_spi_and_no_testbench() {
        let set = raster(JOB_TEXT, "t.toml", LayoutId::Wide).expect("vectors");
        assert!(set.file(SPI_BYTES).is_none() && set.file(TESTBENCH_FILE).is_none());
        let (header, _) =
            memh::parse_frame(set.file(FRAMEBUFFER).expect("frame").text()).expect("frame");
        assert_eq!(header.format, PixelFormat::Rgb888);
        let fifo = &set.file(FIFO_RECORDS_FILE).expect("records").text();
        // 64-bit records: a flag digit and 16 record digits.
        assert!(fifo
            .lines()
            .filter(|l| !l.starts_with("//"))
            .all(|l| l.len() == 17));
    }
}
