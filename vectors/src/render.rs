//! `fpgfx vectors render`: test vectors for the ray-trace block. A scene becomes what a
//! DUT is given (the AXI4-Lite writes, the register image, the texture memory) and what it
//! must produce (the frame in RGB888 and in the KCU116 packing, the depth and normal
//! planes), each as a `$readmemh` file ([`compare::memh`]) and as raw little-endian bytes.
//!
//! The frame is rendered exactly as `fpgfx render --port builtin` renders it: the scene is
//! written into the register image, the image into an emulated device
//! ([`sim_target::Device`]), and the planes are read back from it. Rendering from the
//! parsed scene instead would skip the image's Q16.16 quantisation and give vectors a
//! board never matches. docs/vectors.md describes every file.

use compare::memh::{self, FrameHeader, PixelFormat as MemhFormat};
use protocol::axi_lite::{self, SCENE_WORDS};
use protocol::frame::{Block, Numeric, PixelFormat, Plane, ReadRequest, Rect, StartFrame};
use protocol::names::Named;
use protocol::scene::ValueFormat;
use sim_target::rt::Scene;
use sim_target::scene_regs::{self, SceneRegsError};
use sim_target::Device;

use super::{VectorFile, VectorSet, VectorsError};

/// What to render besides the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Options {
    /// Number format of the frame (the `NUMERIC` register).
    pub numeric: Numeric,
    /// Frame size overriding the scene's (the camera keeps its field of view).
    pub size: Option<(u32, u32)>,
}

/// One scene's vectors, in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderVectors {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// The start the frame was rendered with (`aovs` set: the planes are vectors too).
    pub start: StartFrame,
    /// The register image, word by word, as the DUT's scene memory holds it.
    pub regs: [u32; SCENE_WORDS],
    /// The texture memory the block samples, one `0x00RRGGBB` word per texel.
    pub texture: Vec<u32>,
    /// The frame, RGB888 row-major.
    pub rgb888: Vec<u8>,
    /// The frame in ViRAY's KCU116 16-bit packing ([`sim_target::rt::pack_kcu116`]).
    pub kcu116: Vec<u16>,
    /// Distance to the first hit per pixel, +∞ where the primary ray missed.
    pub depth: Vec<f32>,
    /// World-space normal per pixel, x, y, z interleaved (0 where the ray missed).
    pub normal: Vec<f32>,
    /// What the frame cost, as `fpgfx render --stats` reports it.
    pub counters: RenderCounters,
}

/// A frame's counters: the device's `FrameDone` and saturation count, the seed's ray
/// count, and the clock count the ray-casting core's RTL reports for the same image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderCounters {
    /// Rays the model traced (`RT_WORK`): primary, shadow and reflected rays that ran.
    pub rays_traced: u64,
    /// Rays as the seed counts them (pixels × spp × depth × (1 + lights)), traced or not:
    /// the numerator of its Mrays/s.
    pub rays_nominal: u64,
    /// The HLS block's cycles at its II (`sim_target::rt::BOARD_CLOCK_HZ`), the model's
    /// `RT_CYCLES`.
    pub cycles: u64,
    /// Clock edges from `ap_start` to `ap_done` of the ray-casting core in RTL
    /// (`hw/rt-core/`, one pixel slot per clock group): its `RT_CYCLES` for this image
    /// (`sim_target::rt::core`).
    pub core_cycles: u64,
    /// Results a fixed-point datapath clipped to its format's range (0 in float formats).
    pub saturations: u64,
}

/// The bus layout of the emulated device: the built-in target's. A ray-traced frame
/// never touches the raster FIFO, so any layout renders the same image.
const LAYOUT: &protocol::bus::BusLayout = &protocol::bus::WIDE;

/// What a DUT is given for one frame, without rendering it ([`registers`]).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Registers {
    /// The scene as the register image carries it, at the frame size asked for: what the
    /// device renders (materials expanded per object, numbers quantised to the image).
    pub scene: Scene,
    /// The register image, word by word, as the DUT's scene memory holds it.
    pub regs: [u32; SCENE_WORDS],
    /// The start the frame is rendered with (`aovs` set).
    pub start: StartFrame,
}

impl Registers {
    /// The AXI4-Lite writes of the frame, in bus order ([`axi_lite::write_sequence`]).
    pub fn writes(&self) -> Vec<(u32, u32)> {
        axi_lite::write_sequence(&self.regs, &self.start).collect()
    }
}

/// The scene's register image and start in the value format the built-in target's caps
/// ask for, as `fpgfx render --port builtin` sends them: what [`render`] renders from, for
/// a testbench that writes the registers itself.
pub fn registers(scene: &Scene, opts: &Options) -> Result<Registers, VectorsError> {
    let mut scene = scene.clone();
    if let Some((w, h)) = opts.size {
        scene.width = w;
        scene.height = h;
    }
    let format = ValueFormat::for_caps(&Device::new(LAYOUT).caps(), opts.numeric);
    let image = jobs::scene::to_regs_as(&scene, format)?;
    let mut regs = [0u32; SCENE_WORDS];
    image.to_words(&mut regs).map_err(SceneRegsError::from)?;
    Ok(Registers {
        scene: scene_regs::from_regs(&image)?,
        regs,
        start: frame_start(opts.numeric),
    })
}

/// The start of every frame here: the AOV planes written, so that they are vectors too.
fn frame_start(numeric: Numeric) -> StartFrame {
    StartFrame {
        frame_id: 1,
        block: Block::RayTrace,
        numeric,
        auto_restart: false,
        aovs: true,
    }
}

/// A register image as the device decodes it (`regs` as the DUT's scene memory holds
/// them), to be rendered in `numeric`: the path for a caller that has an image rather
/// than a scene file, refused as the device refuses it.
pub fn decode(regs: &[u32; SCENE_WORDS], numeric: Numeric) -> Result<Registers, VectorsError> {
    let image = scene_regs::Regs::from_words(regs).map_err(SceneRegsError::from)?;
    Ok(Registers {
        scene: scene_regs::from_regs(&image)?,
        regs: *regs,
        start: frame_start(numeric),
    })
}

/// Renders `scene` as the built-in target does and collects the vectors.
pub fn render(scene: &Scene, opts: &Options) -> Result<RenderVectors, VectorsError> {
    render_registers(&registers(scene, opts)?)
}

/// Renders a register image ([`registers`], [`decode`]) as the built-in target does and
/// collects the vectors.
pub fn render_registers(r: &Registers) -> Result<RenderVectors, VectorsError> {
    let Registers {
        scene: device_scene,
        regs,
        start,
    } = r.clone();
    let mut device = Device::new(LAYOUT);
    // The device renders the scene the registers describe (materials expanded per object),
    // so its texture memory is that scene's, not the file's.
    let texture = sim_target::rt::texture::memory(&device_scene);
    let (width, height) = (device_scene.width, device_scene.height);
    device.write_regs(0, &regs)?;
    device.start(&start)?;
    let rect = Rect {
        x: 0,
        y: 0,
        w: u16::try_from(width).map_err(|_| VectorsError::Size(width, height))?,
        h: u16::try_from(height).map_err(|_| VectorsError::Size(width, height))?,
    };
    let mut read = |plane, format, what| {
        let req = ReadRequest {
            plane,
            rect,
            format,
        };
        let len = device.read_len(&req).ok_or(VectorsError::Plane(what))?;
        let mut bytes = vec![0u8; len as usize];
        device.read(&req, 0, &mut bytes);
        Ok::<_, VectorsError>(bytes)
    };
    let rgb888 = read(Plane::Color, PixelFormat::Rgb888, "RGB888 colour")?;
    let kcu116 = read(Plane::Color, PixelFormat::Kcu116, "KCU116 colour")?
        .chunks_exact(2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]))
        .collect();
    let floats = |bytes: Vec<u8>| -> Vec<f32> {
        bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    };
    let depth = floats(read(Plane::Depth, PixelFormat::DepthF32, "depth")?);
    let normal = floats(read(Plane::Normal, PixelFormat::NormalF32, "normal")?);
    let done = device.poll_done().ok_or(VectorsError::NoFrameDone)?;
    let counters = RenderCounters {
        rays_traced: done.work,
        rays_nominal: sim_target::rt::nominal_rays(&device_scene, width, height, device_scene.spp),
        cycles: done.cycles,
        core_cycles: sim_target::rt::core::CoreFrame::of(&device_scene).cycles(),
        saturations: device.counters().saturations,
    };
    Ok(RenderVectors {
        width,
        height,
        start,
        regs,
        texture,
        rgb888,
        kcu116,
        depth,
        normal,
        counters,
    })
}

/// The manifest: what a reader needs to check it has the vectors it expects.
#[derive(serde::Serialize)]
struct Manifest<'a> {
    fpgfx_version: &'static str,
    scene: &'a str,
    scene_hash: String,
    width: u32,
    height: u32,
    numeric: &'static str,
    numeric_code: u32,
    aovs: bool,
    counts: Counts,
}

#[derive(serde::Serialize)]
struct Counts {
    axi_writes: usize,
    scene_words: usize,
    texture_words: usize,
    pixels: usize,
    normal_words: usize,
}

/// CRC-32 (ISO-HDLC, the link's) of the register image as little-endian words: the
/// image fixes the frame together with the number format, whatever file it came from.
fn scene_hash(regs: &[u32]) -> String {
    let mut digest = protocol::link::CRC32.digest();
    for w in regs {
        digest.update(&w.to_le_bytes());
    }
    format!("crc32:{:08x}", digest.finalize())
}

fn le_bytes<const N: usize, T: Copy>(words: &[T], to: impl Fn(T) -> [u8; N]) -> Vec<u8> {
    words.iter().flat_map(|&w| to(w)).collect()
}

impl RenderVectors {
    /// The AXI4-Lite writes of the frame, in bus order ([`axi_lite::write_sequence`]).
    pub fn writes(&self) -> Vec<(u32, u32)> {
        axi_lite::write_sequence(&self.regs, &self.start).collect()
    }

    /// Every file of the vectors, in the order they are written; `scene` is how the
    /// manifest names the scene (its path as given).
    pub fn set(&self, scene: &str) -> Result<VectorSet, VectorsError> {
        let (w, h) = (self.width, self.height);
        let writes = self.writes();
        let order = format!(
            "scene image at {:#x} + 4*i, then numeric ({:#x}), aovs ({:#x}), ap_ctrl ({:#x})",
            axi_lite::SCENE_BASE,
            axi_lite::NUMERIC,
            axi_lite::AOVS,
            axi_lite::AP_CTRL
        );
        let axi = memh::format(
            &[
                "fpgfx axi4-lite writes: (address << 32) | data, one per line, in bus order",
                &order,
            ],
            writes
                .iter()
                .map(|&(addr, data)| u64::from(addr) << 32 | u64::from(data)),
            16,
        );
        let regs = memh::format(
            &["fpgfx ray-tracer register image: word i at scene offset i (protocol::scene)"],
            self.regs.iter().map(|&w| u64::from(w)),
            8,
        );
        let texture = memh::format(
            &["fpgfx ray-tracer texture memory: one 0x00RRGGBB texel per word"],
            self.texture.iter().map(|&w| u64::from(w)),
            8,
        );
        let header = FrameHeader {
            width: w,
            height: h,
            format: MemhFormat::Rgb888,
        };
        let rgb = memh::format_frame(
            &header,
            self.rgb888
                .chunks_exact(3)
                .map(|p| u64::from(p[0]) << 16 | u64::from(p[1]) << 8 | u64::from(p[2])),
        );
        let kcu_comment =
            format!("fpgfx kcu116 {w}x{h}: G << 8 | B at even x, R at odd x, row-major");
        let kcu = memh::format(
            &[&kcu_comment],
            self.kcu116.iter().map(|&w| u64::from(w)),
            4,
        );
        let depth_comment = format!(
            "fpgfx depth {w}x{h}: f32 bits, distance to the first hit, 7f800000 (+inf) where none"
        );
        let depth = memh::format(
            &[&depth_comment],
            self.depth.iter().map(|v| u64::from(v.to_bits())),
            8,
        );
        let normal_comment = format!(
            "fpgfx normal {w}x{h}: f32 bits, x y z per pixel (word 3*i + axis), 0 where no hit"
        );
        let normal = memh::format(
            &[&normal_comment],
            self.normal.iter().map(|v| u64::from(v.to_bits())),
            8,
        );
        let manifest = Manifest {
            fpgfx_version: env!("CARGO_PKG_VERSION"),
            scene,
            scene_hash: scene_hash(&self.regs),
            width: w,
            height: h,
            numeric: self.start.numeric.name(),
            numeric_code: axi_lite::numeric_code(self.start.numeric),
            aovs: self.start.aovs,
            counts: Counts {
                axi_writes: writes.len(),
                scene_words: self.regs.len(),
                texture_words: self.texture.len(),
                pixels: self.rgb888.len() / 3,
                normal_words: self.normal.len(),
            },
        };
        let manifest = format!(
            "# fpgfx vectors render (docs/vectors.md)\n{}",
            toml::to_string(&manifest)?
        );
        let files = [
            ("axi_writes.hex", axi.into_bytes()),
            ("scene_regs.hex", regs.into_bytes()),
            ("texture.hex", texture.into_bytes()),
            ("texture.bin", le_bytes(&self.texture, u32::to_le_bytes)),
            ("expected_rgb888.hex", rgb.into_bytes()),
            ("expected_rgb888.bin", self.rgb888.clone()),
            ("expected_kcu116.hex", kcu.into_bytes()),
            (
                "expected_kcu116.bin",
                le_bytes(&self.kcu116, u16::to_le_bytes),
            ),
            ("expected_depth.hex", depth.into_bytes()),
            (
                "expected_depth.bin",
                le_bytes(&self.depth, f32::to_le_bytes),
            ),
            ("expected_normal.hex", normal.into_bytes()),
            (
                "expected_normal.bin",
                le_bytes(&self.normal, f32::to_le_bytes),
            ),
            ("manifest.toml", manifest.into_bytes()),
        ];
        Ok(VectorSet {
            files: files
                .into_iter()
                .map(|(name, bytes)| VectorFile {
                    name,
                    bytes,
                    executable: false,
                    entry: None,
                })
                .collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        let text = include_str!("../../examples/rt/textures.toml");
        jobs::scene::parse(text, "textures.toml").unwrap()
    }

    #[test]
    fn the_writes_carry_the_image_and_the_start() {
        let opts = Options {
            numeric: Numeric::Q16_16,
            size: Some((8, 4)),
        };
        let v = render(&scene(), &opts).unwrap();
        assert_eq!((v.width, v.height), (8, 4));
        assert_eq!(v.regs[protocol::scene::hdr::WIDTH], 8);
        let writes = v.writes();
        assert_eq!(writes.len(), SCENE_WORDS + 3);
        assert_eq!(writes[protocol::scene::hdr::WIDTH], (0x810, 8));
        assert_eq!(&writes[SCENE_WORDS..], &[(0x10, 3), (0x18, 1), (0x00, 1)]);
        assert_eq!(v.rgb888.len(), 8 * 4 * 3);
        assert_eq!(v.kcu116.len(), 8 * 4);
        assert_eq!(v.depth.len(), 8 * 4);
        assert_eq!(v.normal.len(), 8 * 4 * 3);
        assert!(v.texture.iter().any(|&t| t != 0), "the scene has textures");
    }

    #[test]
    fn the_manifest_names_what_is_there() {
        let opts = Options {
            numeric: Numeric::F32,
            size: Some((4, 2)),
        };
        let v = render(&scene(), &opts).unwrap();
        let set = v.set("textures.toml").unwrap();
        let m: toml::Value = toml::from_str(set.file("manifest.toml").unwrap().text()).unwrap();
        assert_eq!(m["width"].as_integer(), Some(4));
        assert_eq!(m["numeric"].as_str(), Some("f32"));
        assert_eq!(m["counts"]["axi_writes"].as_integer(), Some(497));
        assert_eq!(m["counts"]["texture_words"].as_integer(), Some(65536));
        assert!(m["scene_hash"].as_str().unwrap().starts_with("crc32:"));
    }
}
