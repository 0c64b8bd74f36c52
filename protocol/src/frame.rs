//! Messages between the host (`fpgfx`) and the controller firmware.
//!
//! A message is a [`HostFrame`] (host → controller) or a [`DeviceFrame`]
//! (controller → host), serialised with postcard and carried by [`crate::link`]. Every
//! message fits in [`MAX_PAYLOAD`] bytes once encoded: the bounded vectors below are
//! sized so that even their worst-case varint encodings stay under that limit (a test
//! checks each bound).
//!
//! Geometry crosses the wire already snapped to the sub-pixel grid (`x · 2^subpixel_bits`,
//! rounded half up) so the controller and the FPGA only ever do exact integer
//! arithmetic, and so that the host, not the MCU, owns the float → fixed decision.

use crate::raster::{RasterCmd, RasterSetup};

use heapless::{String, Vec};
use postcard_schema::Schema;
use serde::{Deserialize, Serialize};

use crate::{MAX_PAYLOAD, PROTOCOL_VERSION};

/// Raster commands per [`HostFrame::Raster`] batch. Batching keeps the per-frame link
/// overhead (header, CRC, COBS, delimiter: about 10 bytes) under 10 % of a triangle
/// stream, where one triangle per frame would cost about 35 %.
pub const RASTER_BATCH: usize = 8;
/// 32-bit register words in one [`RegWrite`]; 40 × 5 bytes (worst-case varint) plus the
/// header stays within [`MAX_PAYLOAD`].
pub const REG_WRITE_WORDS: usize = 40;
/// Bytes of texel data in one [`TextureWrite`].
pub const TEXTURE_CHUNK: usize = 224;
/// Bytes of pixel data in one [`ReadChunk`] on a link of [`MAX_PAYLOAD`]-byte frames; a
/// link with larger frames carries [`read_chunk_len`] of its payload.
pub const READ_CHUNK: usize = 224;

/// The most read-back bytes a chunk carries on a link whose payloads go up to `payload`
/// bytes ([`READ_CHUNK`] on a [`MAX_PAYLOAD`] link): the rest of the payload is left for
/// the message around the bytes, as on the smallest link.
pub const fn read_chunk_len(payload: usize) -> usize {
    payload - (MAX_PAYLOAD - READ_CHUNK)
}
/// Bytes of the human-readable firmware identification in [`Hello`].
pub const IDENT_LEN: usize = 32;
/// The schema hash of this build's message set: FNV-1a over the postcard-schema of
/// [`HostFrame`] and [`DeviceFrame`] (names, field order and types). Two builds that would
/// decode each other's bytes differently get different hashes, so the handshake can
/// refuse the pair instead of letting garbage through.
pub const SCHEMA_HASH: u64 = u64::from_le_bytes(
    postcard_schema::key::Key::for_path::<(HostFrame, DeviceFrame)>("fpgfx/frame").to_bytes(),
);

/// Returns [`SCHEMA_HASH`]; a function for callers that prefer not to name constants.
pub const fn schema_hash() -> u64 {
    SCHEMA_HASH
}

/// A pixel rectangle, origin top-left.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct Rect {
    /// Left column.
    pub x: u16,
    /// Top row.
    pub y: u16,
    /// Width in pixels.
    pub w: u16,
    /// Height in pixels.
    pub h: u16,
}

impl Rect {
    /// Number of pixels covered.
    pub const fn area(&self) -> u32 {
        self.w as u32 * self.h as u32
    }
}

/// Which of the FPGA's blocks a job is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum Block {
    /// The rasterizer (seed 000/001/004).
    Raster,
    /// The ViRAY ray tracer (seed 002).
    RayTrace,
}

/// Number formats a target can compute in. The real FPGA has one; the sim-target offers
/// several so that a designer can compare them on the same scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum Numeric {
    /// IEEE binary64: the reference every other format is measured against.
    F64,
    /// IEEE binary32: ViRAY's final module.
    F32,
    /// IEEE binary16 (seed 002's `half` experiment).
    F16,
    /// Signed Q16.16, the seed's `ap_fixed<32,16>`.
    Q16_16,
    /// Signed Q8.24: more fraction, less range.
    Q8_24,
    /// Signed Q24.8: more range, less fraction.
    Q24_8,
    /// Signed Q32.32 in 64 bits.
    Q32_32,
}

impl Numeric {
    /// Every format, in the bit order of [`NumericSet`].
    pub const ALL: [Numeric; 7] = [
        Numeric::F64,
        Numeric::F32,
        Numeric::F16,
        Numeric::Q16_16,
        Numeric::Q8_24,
        Numeric::Q24_8,
        Numeric::Q32_32,
    ];

    /// This format's bit in a [`NumericSet`].
    pub const fn bit(self) -> u16 {
        1 << self as u16
    }
}

crate::named! {
    Numeric, what = "number format", ignore_case = true, values = Numeric::ALL,
    {
        F64 => ["f64"],
        F32 => ["f32"],
        F16 => ["f16"],
        Q16_16 => ["q16.16", "q16_16"],
        Q8_24 => ["q8.24", "q8_24"],
        Q24_8 => ["q24.8", "q24_8"],
        Q32_32 => ["q32.32", "q32_32"],
    }
}

/// A set of [`Numeric`] formats as a bit mask (bit i = `Numeric::ALL[i]`), so that a
/// capability list costs two bytes on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct NumericSet(pub u16);

impl NumericSet {
    /// Whether `n` is in the set.
    pub const fn contains(self, n: Numeric) -> bool {
        self.0 & n.bit() != 0
    }

    /// The set with `n` added.
    pub const fn with(self, n: Numeric) -> Self {
        Self(self.0 | n.bit())
    }
}

/// How pixels are laid out in read-back data and in the framebuffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum PixelFormat {
    /// Three bytes per pixel, R, G, B.
    Rgb888,
    /// One byte per pixel, RRRGGGBB: the FITkit's 8-bit colour.
    Rgb332,
    /// ViRAY's KCU116 16-bit mode: each pixel keeps G and, alternately, B (even pixels)
    /// or R (odd pixels); two bytes per pixel, G first.
    Kcu116,
    /// One little-endian f32 per pixel (depth AOV).
    DepthF32,
    /// Three little-endian f32 per pixel (normal AOV).
    NormalF32,
}

impl PixelFormat {
    /// Bytes per pixel in read-back data.
    pub const fn bytes_per_pixel(self) -> usize {
        match self {
            PixelFormat::Rgb888 => 3,
            PixelFormat::Rgb332 => 1,
            PixelFormat::Kcu116 => 2,
            PixelFormat::DepthF32 => 4,
            PixelFormat::NormalF32 => 12,
        }
    }

    /// This format's bit in a capability mask.
    pub const fn bit(self) -> u8 {
        1 << self as u8
    }
}

/// What a target can do, sent in its [`Hello`] so that the host refuses a job up front
/// instead of discovering half-way through a frame that the board cannot draw it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct Caps {
    /// The raster block is present.
    pub raster: bool,
    /// The ray-trace block is present.
    pub ray_trace: bool,
    /// Number formats the ray tracer can run in.
    pub numeric: NumericSet,
    /// Read-back pixel formats, as a mask of [`PixelFormat::bit`].
    pub pixel_formats: u8,
    /// Largest frame width in pixels.
    pub max_width: u16,
    /// Largest frame height in pixels.
    pub max_height: u16,
    /// Largest sub-pixel precision the raster block accepts.
    pub max_subpixel_bits: u8,
    /// Slots in the controller's command queue (the credit limit of the link).
    pub queue_depth: u16,
    /// Records in the FPGA's input FIFO.
    pub fifo_depth: u16,
    /// Objects the ray tracer holds (OBJ_NUM).
    pub max_objects: u8,
    /// Lights the ray tracer holds, the ambient one included (LIGHTS_NUM).
    pub max_lights: u8,
    /// Size of the texture memory in 32-bit texels.
    pub texture_words: u32,
    /// The bus layout the controller packs raster commands in, so the host can refuse a
    /// command the board cannot draw (a circle on the FITkit) before sending anything,
    /// naming it. `None` from a host, or a controller with a layout of its own.
    pub raster_layout: Option<crate::bus::LayoutId>,
    /// Number formats whose datapath wants the scene's reals as IEEE binary32 register
    /// words ([`crate::scene::ValueFormat::Binary32`]) rather than Q16.16, so that a float
    /// datapath gets the scene to f32 precision instead of quantised to 2⁻¹⁶; the host
    /// picks the image's format with [`crate::scene::ValueFormat::for_caps`]. Empty: the
    /// seed's Q16.16 image for every format.
    pub float_regs: NumericSet,
    /// What the ray tracer's datapath builds: a hardware core carries only the shapes
    /// and shading terms its scenes need, and the host refuses a scene that asks for more,
    /// naming the field, before anything is sent. [`RtBuild::FULL`] (the default) for the
    /// golden model and every block that implements the whole register map.
    pub rt_build: RtBuild,
    /// The largest link payload this end accepts ([`crate::link::Capacity::PAYLOAD`]); a
    /// peer never sends it more. Below [`MAX_PAYLOAD`] (0 in particular, from an end that
    /// does not say) it counts as [`MAX_PAYLOAD`], which every end accepts. A read-back's
    /// chunks are sized for the smaller of the two ends' payloads ([`read_chunk_len`]).
    pub link_payload: u32,
}

impl Caps {
    /// [`Caps::link_payload`] with its floor applied.
    pub fn link_payload(&self) -> usize {
        (self.link_payload as usize).max(MAX_PAYLOAD)
    }
}

/// The shapes, lights and shading terms a ray-tracing datapath builds ([`Caps::rt_build`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub struct RtBuild {
    /// Shapes built: bit i is shape code i ([`crate::scene::Shape::code`]).
    pub shapes: u8,
    /// Point and spot lights shaded, the ambient light not counted.
    pub lights: u8,
    /// Samples per pixel taken at most.
    pub max_spp: u16,
    /// The `RtBuild::SHADOWS` … bits of the terms built.
    pub features: u16,
}

impl RtBuild {
    /// Shadow rays (the scene's `shadows`).
    pub const SHADOWS: u16 = 1 << 0;
    /// Spot lights (a point light is always built).
    pub const SPOT_LIGHTS: u16 = 1 << 1;
    /// Textures.
    pub const TEXTURES: u16 = 1 << 2;
    /// Reflected and refracted rays (a material's reflection at depth > 1).
    pub const REFLECTION: u16 = 1 << 3;
    /// The Oren–Nayar diffuse term (Lambert is always built).
    pub const OREN_NAYAR: u16 = 1 << 4;
    /// The Torrance–Sparrow highlight (Blinn–Phong is always built).
    pub const TORRANCE_SPARROW: u16 = 1 << 5;
    /// Every shape, light count, sample count and term: the whole register map.
    pub const FULL: RtBuild = RtBuild {
        shapes: 0x7f,
        lights: u8::MAX,
        max_spp: u16::MAX,
        features: 0x3f,
    };

    /// Whether every bit of `feature` is built.
    pub const fn has(&self, feature: u16) -> bool {
        self.features & feature == feature
    }
}

/// A target that says nothing about its ray tracer builds the whole map.
impl Default for RtBuild {
    fn default() -> Self {
        Self::FULL
    }
}

/// The first message in each direction. Each side compares the other's
/// `protocol_version` and `schema_hash` with its own and refuses to continue on a
/// mismatch (see [`Hello::check`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct Hello {
    /// The sender's [`PROTOCOL_VERSION`].
    pub protocol_version: u16,
    /// The sender's [`SCHEMA_HASH`].
    pub schema_hash: u64,
    /// What the sender can do; the host sends its own needs here (all zero is fine).
    pub caps: Caps,
    /// Free-form identification ("fpgfx-firmware 0.1.0 stm32f405"), for error messages.
    pub ident: String<IDENT_LEN>,
}

/// Why a handshake was refused: the two sides' values, so the message can name both.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum HandshakeError {
    /// The protocol versions differ.
    #[error("protocol version mismatch: this side speaks v{ours}, the peer speaks v{theirs}")]
    Version {
        /// This side's version.
        ours: u16,
        /// The peer's version.
        theirs: u16,
    },
    /// The versions agree but the message schemas do not (a build from a different commit).
    #[error(
        "message schema mismatch (both speak protocol v{version}): this side's schema hash is \
         {ours:#018x}, the peer's is {theirs:#018x}; rebuild both from the same fpgfx version"
    )]
    Schema {
        /// The common protocol version.
        version: u16,
        /// This side's schema hash.
        ours: u64,
        /// The peer's schema hash.
        theirs: u64,
    },
}

impl Hello {
    /// A hello for this build, with the given capabilities and identification (cut to
    /// [`IDENT_LEN`] bytes at a character boundary if longer).
    pub fn new(caps: Caps, ident: &str) -> Self {
        let mut s = String::new();
        for ch in ident.chars() {
            if s.push(ch).is_err() {
                break;
            }
        }
        Self {
            protocol_version: PROTOCOL_VERSION,
            schema_hash: SCHEMA_HASH,
            caps,
            ident: s,
        }
    }

    /// Checks the peer's hello against this build.
    pub fn check(&self) -> Result<(), HandshakeError> {
        if self.protocol_version != PROTOCOL_VERSION {
            return Err(HandshakeError::Version {
                ours: PROTOCOL_VERSION,
                theirs: self.protocol_version,
            });
        }
        if self.schema_hash != SCHEMA_HASH {
            return Err(HandshakeError::Schema {
                version: PROTOCOL_VERSION,
                ours: SCHEMA_HASH,
                theirs: self.schema_hash,
            });
        }
        Ok(())
    }
}
/// Texel data for the shared texture memory (ViRAY's TEXT_PAGE and the raster block's
/// texture RAM are one memory in the model).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct TextureWrite {
    /// Index of the first texel written.
    pub offset: u32,
    /// Texels as little-endian 32-bit words 0x00RRGGBB; the length must be a multiple
    /// of four.
    pub data: Vec<u8, TEXTURE_CHUNK>,
}

/// A run of consecutive 32-bit ray-tracer registers ([`crate::scene`] defines the map).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct RegWrite {
    /// Word offset of the first register.
    pub offset: u16,
    /// Values for `offset`, `offset + 1`, ….
    pub words: Vec<u32, REG_WRITE_WORDS>,
}

/// Register ramps in one [`Animation`].
pub const MAX_RAMPS: usize = 8;
/// Orbits in one [`Animation`].
pub const MAX_ORBITS: usize = 2;

/// A register that changes by a fixed step after every auto-restarted frame: a texture
/// scrolling across the floor, an object growing (ViRAY's driver loop, seed 002 §3.6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct Ramp {
    /// The register ([`crate::scene`] map).
    pub reg: u16,
    /// Added per frame, in the register's own units (Q16.16 for positions), wrapping.
    pub step: i32,
}

impl Ramp {
    /// The register's next value.
    pub const fn apply(&self, value: u32) -> u32 {
        (value as i32).wrapping_add(self.step) as u32
    }
}

/// A point (two Q16.16 registers, e.g. a light's x and z) turning about a centre by a
/// fixed angle after every auto-restarted frame: ViRAY's orbiting light.
///
/// The host supplies the angle as its cosine and sine in Q2.30 so that the controller
/// needs no trigonometry (the MCU has no libm) and every implementation gets the same bits:
/// integer multiply, round half up, shift.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct Orbit {
    /// Register of the first coordinate (x).
    pub x_reg: u16,
    /// Register of the second coordinate (z).
    pub z_reg: u16,
    /// Centre of the circle, Q16.16, in the same two coordinates.
    pub center: [i32; 2],
    /// cos(angle per frame), Q2.30.
    pub cos: i32,
    /// sin(angle per frame), Q2.30.
    pub sin: i32,
}

impl Orbit {
    /// 1.0 in the Q2.30 format of [`Orbit::cos`] and [`Orbit::sin`].
    pub const ONE: i64 = 1 << 30;

    /// The point after one step. Rounding (not truncation) keeps the radius from
    /// shrinking frame after frame; what drift remains is below 2⁻¹⁶ per frame.
    pub const fn apply(&self, x: u32, z: u32) -> (u32, u32) {
        let dx = (x as i32 as i64) - self.center[0] as i64;
        let dz = (z as i32 as i64) - self.center[1] as i64;
        let (c, s) = (self.cos as i64, self.sin as i64);
        let half = 1i64 << 29;
        let rx = (dx * c - dz * s + half) >> 30;
        let rz = (dx * s + dz * c + half) >> 30;
        (
            (self.center[0] as i64 + rx) as i32 as u32,
            (self.center[1] as i64 + rz) as i32 as u32,
        )
    }
}

/// What an auto-restarting ray tracer changes between frames, applied by the controller
/// after each frame is done and before the next starts, so the host need not send
/// anything while an animation runs (ViRAY's demo: light orbiting, floor texture
/// scrolling). Replaces the previous animation; an empty one stops changing the scene.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct Animation {
    /// Per-frame register steps.
    pub ramps: Vec<Ramp, MAX_RAMPS>,
    /// Per-frame rotations.
    pub orbits: Vec<Orbit, MAX_ORBITS>,
}

/// Start a job on a block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct StartFrame {
    /// Chosen by the host; echoed in [`FrameDone`].
    pub frame_id: u32,
    /// Which block renders.
    pub block: Block,
    /// Number format for the ray tracer (ignored by the raster block).
    pub numeric: Numeric,
    /// Render again as soon as a frame is done (ViRAY's driver auto-restart), until the
    /// next `StartFrame` or [`HostFrame::Stop`].
    pub auto_restart: bool,
    /// Also write the ray tracer's depth and normal planes. A frame started without them
    /// refuses their read-back; they cost the block memory bandwidth (in the golden model
    /// 33 MB per 1080p frame, a fifth of the render time), so a host asks only when it
    /// will read them.
    pub aovs: bool,
}

/// Which buffer a read-back comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub enum Plane {
    /// The colour framebuffer.
    Color,
    /// The depth AOV (ray tracer) or z-buffer (raster).
    Depth,
    /// The normal AOV (ray tracer).
    Normal,
}

/// Ask for a rectangle of a buffer. The device answers with [`ReadChunk`]s in offset
/// order and a closing [`ReadDone`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct ReadRequest {
    /// Which buffer to read.
    pub plane: Plane,
    /// Pixels, row-major.
    pub rect: Rect,
    /// Layout of the returned bytes.
    pub format: PixelFormat,
}

/// Messages from the host to the controller.
///
/// `R` is how a [`HostFrame::Raster`] batch is held once decoded: by default the commands
/// themselves, which is what the host builds and tests compare; a controller decodes a
/// [`Request`] instead (`R` = [`CheckedBatch`]), whose batch stays in the payload, so
/// that a decoded request never holds eight commands at once. Every other variant, and
/// the encoding, is the same type either way, so the two cannot drift apart.
// No alloc means no boxing: the largest variant (a full raster batch, ~1.3 KiB) sets the
// size of the decoded message; a controller avoids it with `Request`.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub enum HostFrame<R = Vec<RasterCmd, RASTER_BATCH>> {
    /// Must come first: the controller refuses every other request with
    /// [`ErrorCode::Handshake`] until a hello's version and schema hash agree with its own.
    Hello(Hello),
    /// Frame-wide raster state.
    RasterSetup(RasterSetup),
    /// A batch of raster commands, executed in order.
    Raster(R),
    /// Texel data for the shared texture memory.
    Texture(TextureWrite),
    /// Ray-tracer register writes.
    Regs(RegWrite),
    /// Start a frame; answered by [`DeviceFrame::Done`] when it finishes.
    Start(StartFrame),
    /// Stop auto-restart after the current frame.
    Stop,
    /// Wait until every queued command has reached the framebuffer, then answer
    /// [`DeviceFrame::Synced`] with the same token.
    Sync(u32),
    /// Read back part of a buffer.
    Read(ReadRequest),
    /// Ask for [`Stats`].
    GetStats,
    /// Drop queued work, clear counters and return to the state after the handshake.
    Reset,
    /// Set what changes between auto-restarted frames.
    Animate(Animation),
}

/// A [`HostFrame`] as a controller decodes it: a raster batch is checked (every command
/// decodes, at most [`RASTER_BATCH`] of them, nothing trails) but left in the payload,
/// to be walked one command at a time with [`raster_commands`]. A decoded `HostFrame`
/// is the size of its largest variant, the batch (1 076 B on a 16-bit MCU); a `Request`
/// is that of the next largest (a texture chunk), and decoding it builds one command at
/// a time instead of the whole batch. On the MSP430, whose RAM is 8 KiB, that is the
/// difference between fitting and not (docs/firmware.md, "MSP430").
pub type Request = HostFrame<CheckedBatch>;

/// The raster batch of a decoded [`Request`]: its command count, the commands checked
/// and left in the payload ([`raster_commands`] walks them). Decoding fails exactly where
/// decoding the commands themselves would: a malformed command, or more than
/// [`RASTER_BATCH`] of them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CheckedBatch {
    /// Commands in the batch.
    pub count: u8,
}

impl<'de> Deserialize<'de> for CheckedBatch {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        /// Walks the sequence, one command on the stack at a time.
        struct Walk;
        impl<'de> serde::de::Visitor<'de> for Walk {
            type Value = CheckedBatch;
            fn expecting(&self, f: &mut core::fmt::Formatter) -> core::fmt::Result {
                f.write_str("a raster batch")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<CheckedBatch, A::Error> {
                let mut count = 0usize;
                while seq.next_element::<RasterCmd>()?.is_some() {
                    count += 1;
                    // As heapless's Vec<_, RASTER_BATCH> refuses a longer sequence.
                    if count > RASTER_BATCH {
                        return Err(serde::de::Error::invalid_length(count, &self));
                    }
                }
                Ok(CheckedBatch { count: count as u8 })
            }
        }
        d.deserialize_seq(Walk)
    }
}

/// Counters kept by each end of a [`crate::link`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct LinkCounters {
    /// Data frames sent for the first time.
    pub sent: u32,
    /// Data frames sent again (after a NAK or a timeout).
    pub resent: u32,
    /// Data frames delivered to the application.
    pub delivered: u32,
    /// Frames dropped because the CRC did not match.
    pub crc_errors: u32,
    /// Frames dropped because COBS decoding or the header failed.
    pub framing_errors: u32,
    /// Data frames received again and acknowledged without being delivered twice.
    pub duplicates: u32,
    /// Data frames refused because the receiver had no free slot, or bytes lost because
    /// a frame exceeded the receive buffer.
    pub overflows: u32,
    /// NAKs sent.
    pub naks: u32,
    /// Retransmission timer expiries (each frame resent for lack of an ACK counts once).
    pub timeouts: u32,
    /// Valid frames ignored because they belong to an older reset epoch.
    pub stale: u32,
    /// Resets, started here or by the peer.
    pub resets: u32,
}

/// Counters of the controller and the FPGA model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct DeviceCounters {
    /// Raster commands executed.
    pub commands: u32,
    /// Bus words (FIFO records or register writes) pushed to the FPGA.
    pub bus_words: u32,
    /// Fragments written to the framebuffer.
    pub fragments: u64,
    /// FPGA clock cycles spent by the blocks.
    pub cycles: u64,
    /// Cycles the controller waited on a full input FIFO.
    pub fifo_stalls: u64,
    /// Frames completed.
    pub frames: u32,
    /// Free slots in the controller's command queue now.
    pub queue_free: u16,
    /// Results of the last ray-traced frame that a fixed-point datapath clipped to its
    /// format's range (the saturating arithmetic of `ap_fixed` with `AP_SAT`, division by
    /// zero included): 0 means the frame is what the format computes without clipping.
    /// Float formats count nothing here, as they do not saturate (an overflow becomes ±∞,
    /// which `fpgfx stress` counts).
    pub saturations: u64,
}

/// Both ends' view of the link plus the device counters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, Schema)]
pub struct Stats {
    /// The controller's link counters.
    pub link: LinkCounters,
    /// The controller and FPGA counters.
    pub device: DeviceCounters,
}

/// A frame finished: one per frame, auto-restarted ones included, carrying what the
/// host's statistics need.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct FrameDone {
    /// The id from [`StartFrame`].
    pub frame_id: u32,
    /// FPGA cycles the frame took.
    pub cycles: u64,
    /// Rays traced (ray tracer) or fragments written (raster).
    pub work: u64,
}

/// A piece of a read-back.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct ReadChunk {
    /// Byte offset of `data` within the whole read-back.
    pub offset: u32,
    /// Pixel bytes in the requested format.
    #[serde(with = "crate::bytes")]
    pub data: Vec<u8, READ_CHUNK>,
}

/// The end of a read-back: the host checks that it received `len` bytes whose CRC-32
/// (the link's polynomial) is `crc32`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct ReadDone {
    /// Total bytes sent.
    pub len: u32,
    /// CRC-32 of all of them.
    pub crc32: u32,
}

/// Why the controller refused or failed a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum ErrorCode {
    /// The payload did not decode as a [`HostFrame`].
    Malformed,
    /// A value is outside what the bus layout or the target can represent.
    OutOfRange,
    /// The target lacks the capability (see [`Caps`]).
    Unsupported,
    /// The request is not valid now (a raster command before [`RasterSetup`], a read of a
    /// buffer that does not exist, …).
    BadState,
    /// The hello's version or schema hash differs, or a request came before a successful
    /// hello.
    Handshake,
    /// The FPGA reported a fault.
    Device,
}

/// An error answer. `index` says where: the command's position in its batch, the
/// register offset, or the byte offset, depending on the request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct ErrorReport {
    /// The kind of failure, for the host to tell the user; `index` says where.
    pub code: ErrorCode,
    /// Link sequence number of the request that failed.
    pub seq: u16,
    /// Where within it (see the type's doc).
    pub index: u32,
}

/// Messages from the controller to the host.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub enum DeviceFrame {
    /// Answer to [`HostFrame::Hello`], sent even on a mismatch so that the host can name
    /// both sides' versions.
    Hello(Hello),
    /// A started frame finished.
    Done(FrameDone),
    /// Answer to [`HostFrame::Sync`].
    Synced(u32),
    /// Part of the read-back answering [`HostFrame::Read`], in offset order.
    Chunk(ReadChunk),
    /// Closes a read-back with its length and CRC, for the host to check.
    ReadDone(ReadDone),
    /// Answer to [`HostFrame::GetStats`].
    Stats(Stats),
    /// A request was refused or failed; the report names it by sequence number.
    Error(ErrorReport),
}

/// Errors encoding or decoding a message.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CodecError {
    /// The bytes are not a valid message of this schema.
    #[error("malformed message: {0}")]
    Decode(postcard::Error),
    /// The message does not fit in [`MAX_PAYLOAD`] bytes.
    #[error("message does not fit in {MAX_PAYLOAD} bytes")]
    TooLarge,
    /// Bytes were left over after a complete message (a sign of a schema mismatch).
    #[error("{0} trailing bytes after a complete message")]
    Trailing(usize),
}

/// Encodes a message into `buf`, returning the used prefix.
pub fn encode<'a, T: Serialize>(msg: &T, buf: &'a mut [u8]) -> Result<&'a mut [u8], CodecError> {
    let limit = buf.len().min(MAX_PAYLOAD);
    postcard::to_slice(msg, &mut buf[..limit]).map_err(|e| match e {
        postcard::Error::SerializeBufferFull => CodecError::TooLarge,
        other => CodecError::Decode(other),
    })
}

/// Decodes exactly one message from `bytes`; trailing bytes are an error, not ignored.
pub fn decode<'de, T: Deserialize<'de>>(bytes: &'de [u8]) -> Result<T, CodecError> {
    let (msg, rest) = postcard::take_from_bytes(bytes).map_err(CodecError::Decode)?;
    if rest.is_empty() {
        Ok(msg)
    } else {
        Err(CodecError::Trailing(rest.len()))
    }
}

/// The variant index serde gives [`DeviceFrame::Chunk`] (its place in the enum), which
/// postcard writes as the message's first varint. Stated here so that a controller can
/// write a chunk's message without serialising a whole [`DeviceFrame`] (on the MSP430
/// that call, no longer inlined, cost 1.7 KB of flash); a test holds it to serde's.
pub const CHUNK_TAG: u32 = 3;

/// The most bytes [`chunk_header`] writes: the tag, and the offset and the length as
/// varints of up to five bytes.
pub const CHUNK_HEADER_MAX: usize = 11;

/// The start of a [`DeviceFrame::Chunk`] message carrying `len` bytes at read-back offset
/// `offset`, and how many of the array's bytes it is: the message is these bytes, then the
/// chunk's. This is how a controller writes a chunk of any size straight into its link's
/// slot (a [`ReadChunk`] holds at most [`READ_CHUNK`]); the bytes are postcard's for the
/// same message (the tag, the offset, the length, each a varint, then the bytes), which
/// [`chunk_view`] reads back.
pub fn chunk_header(offset: u32, len: u32) -> ([u8; CHUNK_HEADER_MAX], usize) {
    // The tag is below 0x80: its varint is the byte itself.
    const _: () = assert!(CHUNK_TAG < 0x80);
    let mut head = [0u8; CHUNK_HEADER_MAX];
    head[0] = CHUNK_TAG as u8;
    let mut n = 1;
    // Varints written out (LEB128: seven bits a byte, low first) rather than serialised:
    // on the MSP430 postcard's `u32` serialiser was 216 bytes of flash for this one use.
    for mut v in [offset, len] {
        while v >= 0x80 {
            head[n] = (v as u8) | 0x80;
            v >>= 7;
            n += 1;
        }
        head[n] = v as u8;
        n += 1;
    }
    (head, n)
}

/// A read-back chunk's offset and bytes, borrowed from a received payload, if the payload
/// is a [`DeviceFrame::Chunk`] (of any length: a chunk from a link with large frames
/// does not fit a [`ReadChunk`]); `None` for any other message. A chunk whose length
/// disagrees with the payload is an error, as [`decode`] would say.
pub fn chunk_view(payload: &[u8]) -> Option<Result<(u32, &[u8]), CodecError>> {
    match postcard::take_from_bytes::<u32>(payload) {
        Ok((CHUNK_TAG, _)) => {}
        _ => return None,
    }
    Some(decode::<(u32, u32, &[u8])>(payload).map(|(_, offset, data)| (offset, data)))
}

/// Why a raster command cannot be batched.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BatchError {
    /// Even alone, the command does not fit in one frame.
    #[error("raster command does not fit in one {MAX_PAYLOAD}-byte frame")]
    TooLarge,
}

/// One closed [`HostFrame::Raster`] message, already encoded: the batcher serialises each
/// command once, straight into the payload, so a command stream costs one postcard pass
/// and no copies of the (large) `HostFrame` value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RasterBatch {
    bytes: Vec<u8, MAX_PAYLOAD>,
    count: usize,
}

impl RasterBatch {
    /// The postcard encoding of the `HostFrame::Raster` message: the link payload.
    pub fn as_bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// Commands in the batch.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The batch as a message value (decodes the bytes; for tests and tools).
    pub fn to_frame(&self) -> Result<HostFrame, CodecError> {
        decode(&self.bytes)
    }
}

/// The postcard variant index of [`HostFrame::Raster`] (its declaration order).
const RASTER_VARIANT: u8 = 2;

/// Iterates the commands of an encoded [`HostFrame::Raster`] payload without building
/// the message: the controller and the benches walk a batch in place, one command on the
/// stack at a time.
pub fn raster_commands(payload: &[u8]) -> Result<RasterCommands<'_>, CodecError> {
    match payload {
        [RASTER_VARIANT, n, rest @ ..] if usize::from(*n) <= RASTER_BATCH => Ok(RasterCommands {
            rest,
            left: usize::from(*n),
        }),
        _ => Err(CodecError::Decode(postcard::Error::DeserializeBadEnum)),
    }
}

/// Iterator returned by [`raster_commands`]; a malformed command ends it with an error,
/// and bytes left after the last command are reported as [`CodecError::Trailing`].
#[derive(Debug, Clone)]
pub struct RasterCommands<'a> {
    rest: &'a [u8],
    left: usize,
}

impl Iterator for RasterCommands<'_> {
    type Item = Result<RasterCmd, CodecError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.left == 0 {
            if self.rest.is_empty() {
                return None;
            }
            let n = self.rest.len();
            self.rest = &[];
            return Some(Err(CodecError::Trailing(n)));
        }
        self.left -= 1;
        match postcard::take_from_bytes::<RasterCmd>(self.rest) {
            Ok((cmd, rest)) => {
                self.rest = rest;
                Some(Ok(cmd))
            }
            Err(e) => {
                self.left = 0;
                self.rest = &[];
                Some(Err(CodecError::Decode(e)))
            }
        }
    }
}

/// Packs raster commands into as few [`HostFrame::Raster`] messages as possible: a batch is
/// closed when it holds [`RASTER_BATCH`] commands or the next command would push its
/// encoding past [`MAX_PAYLOAD`]. Fewer, fuller frames is what keeps the link overhead of
/// a triangle stream under 10 %.
#[derive(Debug)]
pub struct RasterBatcher {
    buf: [u8; MAX_PAYLOAD],
    len: usize,
    count: usize,
}

impl Default for RasterBatcher {
    fn default() -> Self {
        Self::new()
    }
}

impl RasterBatcher {
    /// Encoded size of a batch message besides its commands: the variant index and the
    /// length prefix (one byte each while `RASTER_BATCH` < 128).
    const HEADER: usize = 2;

    /// An empty batcher.
    pub const fn new() -> Self {
        Self {
            buf: [0; MAX_PAYLOAD],
            len: Self::HEADER,
            count: 0,
        }
    }

    fn append(&mut self, cmd: &RasterCmd) -> bool {
        match postcard::to_slice(cmd, &mut self.buf[self.len..]) {
            Ok(used) => {
                self.len += used.len();
                self.count += 1;
                true
            }
            Err(_) => false,
        }
    }

    /// Adds a command. Returns the previous batch when the command did not fit next to it
    /// (the command then starts the new batch).
    pub fn push(&mut self, cmd: &RasterCmd) -> Result<Option<RasterBatch>, BatchError> {
        if self.count < RASTER_BATCH && self.append(cmd) {
            return Ok(None);
        }
        let full = self.finish();
        if self.append(cmd) {
            Ok(full)
        } else {
            Err(BatchError::TooLarge)
        }
    }

    /// Closes the pending batch, if any.
    pub fn finish(&mut self) -> Option<RasterBatch> {
        if self.count == 0 {
            return None;
        }
        self.buf[0] = RASTER_VARIANT;
        // count ≤ RASTER_BATCH < 128: a one-byte varint.
        self.buf[1] = self.count as u8;
        let batch = RasterBatch {
            // len ≤ MAX_PAYLOAD = the capacity.
            bytes: Vec::from_slice(&self.buf[..self.len]).unwrap_or_default(),
            count: self.count,
        };
        self.len = Self::HEADER;
        self.count = 0;
        Some(batch)
    }

    /// Commands waiting in the pending batch.
    pub fn pending(&self) -> usize {
        self.count
    }
}
