//! The ray-trace block: a frame from its register image and texture memory, rendered
//! through the emulated device exactly as `fpgfx render --port builtin` renders it.

use protocol::axi_lite;
use protocol::frame::{Block, Numeric, PixelFormat, Plane, ReadRequest, Rect, StartFrame};
use sim_target::scene_regs::{from_regs, Regs};
use sim_target::Device;

use crate::{fpgfx_status, guard, input, output, put, Failure};

/// Words of the register image: `regs` must hold exactly this many (`n_regs`).
pub const FPGFX_SCENE_WORDS: usize = 494;
/// Texels of the texture memory: `texture` holds this many 32-bit little-endian words.
pub const FPGFX_TEXTURE_WORDS: usize = 65536;

/// AXI4-Lite byte address of the control register (`ap_start` …), as the block's
/// generated driver names it.
pub const FPGFX_AXI_AP_CTRL: u32 = 0x00;
/// AXI4-Lite byte address of the global interrupt enable.
pub const FPGFX_AXI_GIE: u32 = 0x04;
/// AXI4-Lite byte address of the interrupt enable register.
pub const FPGFX_AXI_IER: u32 = 0x08;
/// AXI4-Lite byte address of the interrupt status register.
pub const FPGFX_AXI_ISR: u32 = 0x0C;
/// AXI4-Lite byte address of the `numeric` scalar: an `FPGFX_NUMERIC_*` code.
pub const FPGFX_AXI_NUMERIC: u32 = 0x10;
/// AXI4-Lite byte address of the `aovs` scalar: 1 writes the depth and normal planes.
pub const FPGFX_AXI_AOVS: u32 = 0x18;
/// AXI4-Lite byte address of register image word 0; word `i` is at `+ 4 * i`.
pub const FPGFX_AXI_SCENE_BASE: u32 = 0x800;
/// `ap_start` in the control register.
pub const FPGFX_AXI_AP_START: u32 = 0x01;
/// `auto_restart` in the control register.
pub const FPGFX_AXI_AUTO_RESTART: u32 = 0x80;

/// Number format code: IEEE binary64.
pub const FPGFX_NUMERIC_F64: u32 = 0;
/// Number format code: IEEE binary32, ViRAY's.
pub const FPGFX_NUMERIC_F32: u32 = 1;
/// Number format code: IEEE binary16.
pub const FPGFX_NUMERIC_F16: u32 = 2;
/// Number format code: signed Q16.16, the seed's `ap_fixed<32,16>`.
pub const FPGFX_NUMERIC_Q16_16: u32 = 3;
/// Number format code: signed Q8.24.
pub const FPGFX_NUMERIC_Q8_24: u32 = 4;
/// Number format code: signed Q24.8.
pub const FPGFX_NUMERIC_Q24_8: u32 = 5;
/// Number format code: signed Q32.32.
pub const FPGFX_NUMERIC_Q32_32: u32 = 6;

// The header's numbers are copies for C; their home is protocol and sim-target, and a
// change there must fail the build here rather than ship a wrong header.
const _: () = {
    assert!(FPGFX_SCENE_WORDS == axi_lite::SCENE_WORDS);
    assert!(FPGFX_TEXTURE_WORDS == sim_target::rt::texture::TEXTURE_WORDS);
    assert!(FPGFX_AXI_AP_CTRL == axi_lite::AP_CTRL);
    assert!(FPGFX_AXI_GIE == axi_lite::GIE);
    assert!(FPGFX_AXI_IER == axi_lite::IER);
    assert!(FPGFX_AXI_ISR == axi_lite::ISR);
    assert!(FPGFX_AXI_NUMERIC == axi_lite::NUMERIC);
    assert!(FPGFX_AXI_AOVS == axi_lite::AOVS);
    assert!(FPGFX_AXI_SCENE_BASE == axi_lite::SCENE_BASE);
    assert!(FPGFX_AXI_AP_START == axi_lite::ctrl::AP_START);
    assert!(FPGFX_AXI_AUTO_RESTART == axi_lite::ctrl::AUTO_RESTART);
    assert!(FPGFX_NUMERIC_F64 == axi_lite::numeric_code(Numeric::F64));
    assert!(FPGFX_NUMERIC_F32 == axi_lite::numeric_code(Numeric::F32));
    assert!(FPGFX_NUMERIC_F16 == axi_lite::numeric_code(Numeric::F16));
    assert!(FPGFX_NUMERIC_Q16_16 == axi_lite::numeric_code(Numeric::Q16_16));
    assert!(FPGFX_NUMERIC_Q8_24 == axi_lite::numeric_code(Numeric::Q8_24));
    assert!(FPGFX_NUMERIC_Q24_8 == axi_lite::numeric_code(Numeric::Q24_8));
    assert!(FPGFX_NUMERIC_Q32_32 == axi_lite::numeric_code(Numeric::Q32_32));
};

/// The start of a frame: the scalar registers written before `ap_start`, with the values
/// the AXI writes give them.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct fpgfx_start {
    /// The `numeric` register: an `FPGFX_NUMERIC_*` code.
    pub numeric: u32,
    /// The `aovs` register: 1 makes the depth and normal planes, 0 not.
    pub aovs: u32,
}

/// The register image, checked: length, magic, version and every field.
fn image(regs: &[u32]) -> Result<Regs, Failure> {
    if regs.len() != FPGFX_SCENE_WORDS {
        return Err(Failure::size(format!(
            "n_regs is {}, the register image has {FPGFX_SCENE_WORDS} words",
            regs.len()
        )));
    }
    Regs::from_words(regs)
        .map_err(|e| Failure::new(fpgfx_status::FPGFX_BAD_REGISTERS, format!("regs: {e}")))
}

/// Width and height the image's frame has, each within what a read-back addresses.
fn frame_size(image: &Regs) -> Result<(u16, u16), Failure> {
    let r = image.render();
    let max = protocol::MAX_FRAME_SIDE;
    match (u16::try_from(r.width), u16::try_from(r.height)) {
        (Ok(w), Ok(h))
            if (1..=max).contains(&u32::from(w)) && (1..=max).contains(&u32::from(h)) =>
        {
            Ok((w, h))
        }
        _ => Err(Failure::new(
            fpgfx_status::FPGFX_BAD_REGISTERS,
            format!(
                "regs: frame size {}x{} is outside 1..={max} per side",
                r.width, r.height
            ),
        )),
    }
}

/// Refuses texture memory other than what the image's textures fill in: the model
/// generates each procedural texture from its registers (image textures are not
/// modelled), so it cannot render what a different memory would show.
fn check_texture(image: &Regs, texture: &[u8]) -> Result<(), Failure> {
    if texture.len() != FPGFX_TEXTURE_WORDS * 4 {
        return Err(Failure::size(format!(
            "tex_len is {}, the texture memory has {FPGFX_TEXTURE_WORDS} 32-bit words ({} bytes)",
            texture.len(),
            FPGFX_TEXTURE_WORDS * 4
        )));
    }
    let scene = from_regs(image)
        .map_err(|e| Failure::new(fpgfx_status::FPGFX_BAD_REGISTERS, format!("regs: {e}")))?;
    let expected = sim_target::rt::texture::memory(&scene);
    let given = texture
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    match given.zip(&expected).position(|(g, &e)| g != e) {
        None => Ok(()),
        Some(i) => Err(Failure::new(
            fpgfx_status::FPGFX_UNSUPPORTED,
            format!(
                "texture word {i} is {:#010x}, the registers' procedural textures put {:#010x} there: \
                 the model renders only the textures the registers describe",
                u32::from_le_bytes([texture[4 * i], texture[4 * i + 1], texture[4 * i + 2], texture[4 * i + 3]]),
                expected[i]
            ),
        )),
    }
}

/// The frame size a register image describes, so that a caller can size the buffers of
/// `fpgfx_render`.
///
/// # Safety
/// `regs` must address `n_regs` words; `width` and `height` must be writable.
#[no_mangle]
pub unsafe extern "C" fn fpgfx_frame_size(
    regs: *const u32,
    n_regs: usize,
    width: *mut u32,
    height: *mut u32,
) -> fpgfx_status {
    guard(|| {
        // SAFETY: forwarded caller promises.
        let (w, h) = frame_size(&image(unsafe { input(regs, n_regs, "regs") }?)?)?;
        unsafe {
            put(width, u32::from(w), "width")?;
            put(height, u32::from(h), "height")
        }
    })
}

/// Renders one frame of the ray-trace block, as `fpgfx render --port builtin` does, from
/// what its AXI writes carry: the register image `regs` (`n_regs` =
/// `FPGFX_SCENE_WORDS` words, scene memory order) and the scalars in `start`.
///
/// `texture` is the block's texture memory (`tex_len` = 4 · `FPGFX_TEXTURE_WORDS`
/// bytes, little-endian words) or NULL with `tex_len` 0 for the memory the registers'
/// procedural textures fill (the `texture.bin` of `fpgfx vectors render`); other contents
/// are `FPGFX_UNSUPPORTED`, since the model generates its textures from the registers.
///
/// Writes the frame as RGB888, row-major, to `rgb888_out` (`out_len` = width · height · 3,
/// see `fpgfx_frame_size`). `depth_out` (width · height floats, +inf where no ray hit) and
/// `normal_out` (x, y, z per pixel) are optional: NULL with length 0 skips them; either
/// needs `start->aovs` = 1, as on the block.
///
/// # Safety
/// Each non-null pointer must address as many elements as its length says; the output
/// buffers must not overlap each other or the inputs.
#[no_mangle]
pub unsafe extern "C" fn fpgfx_render(
    regs: *const u32,
    n_regs: usize,
    texture: *const u8,
    tex_len: usize,
    start: *const fpgfx_start,
    rgb888_out: *mut u8,
    out_len: usize,
    depth_out: *mut f32,
    depth_len: usize,
    normal_out: *mut f32,
    normal_len: usize,
) -> fpgfx_status {
    guard(|| {
        // SAFETY (every block below): the caller's promises on pointers and lengths.
        let image = image(unsafe { input(regs, n_regs, "regs") }?)?;
        let start = unsafe { input(start, 1, "start") }?[0];
        let numeric = axi_lite::numeric_from_code(start.numeric).ok_or_else(|| {
            Failure::argument(format!(
                "start->numeric is {}, not an FPGFX_NUMERIC_* code (0..={})",
                start.numeric,
                Numeric::ALL.len() - 1
            ))
        })?;
        let aovs = match start.aovs {
            0 => false,
            1 => true,
            n => return Err(Failure::argument(format!("start->aovs is {n}, not 0 or 1"))),
        };
        if !(texture.is_null() && tex_len == 0) {
            check_texture(&image, unsafe { input(texture, tex_len, "texture") }?)?;
        }
        let (w, h) = frame_size(&image)?;
        let pixels = usize::from(w) * usize::from(h);
        let planes = |ptr_null: bool, len: usize, name: &str, per_pixel: usize| {
            if ptr_null && len == 0 {
                return Ok(false);
            }
            if !aovs {
                return Err(Failure::argument(format!(
                    "{name} is given but start->aovs is 0: the block writes no such plane"
                )));
            }
            if len != pixels * per_pixel {
                return Err(Failure::size(format!(
                    "{name} holds {len} floats, the {w}x{h} frame has {}",
                    pixels * per_pixel
                )));
            }
            Ok(true)
        };
        let want_depth = planes(depth_out.is_null(), depth_len, "depth_out", 1)?;
        let want_normal = planes(normal_out.is_null(), normal_len, "normal_out", 3)?;
        if out_len != pixels * 3 {
            return Err(Failure::size(format!(
                "out_len is {out_len}, the {w}x{h} frame needs {} bytes of RGB888",
                pixels * 3
            )));
        }
        let rgb = unsafe { output(rgb888_out, out_len, "rgb888_out") }?;
        let mut device = Device::new(&protocol::bus::WIDE);
        let words: Vec<u32> = image.words().collect();
        device.write_regs(0, &words).map_err(device_error)?;
        device
            .start(&StartFrame {
                frame_id: 1,
                block: Block::RayTrace,
                numeric,
                auto_restart: false,
                aovs,
            })
            .map_err(device_error)?;
        let mut read = |plane, format, out: &mut [u8]| {
            let req = ReadRequest {
                plane,
                rect: Rect { x: 0, y: 0, w, h },
                format,
            };
            // The frame was just rendered with these planes: a refusal is a bug here.
            match device.read_len(&req) {
                Some(n) if n as usize == out.len() => {
                    device.read(&req, 0, out);
                    Ok(())
                }
                n => Err(Failure::new(
                    fpgfx_status::FPGFX_INTERNAL_ERROR,
                    format!(
                        "internal error: the device offers {n:?} bytes of {plane:?}, {} expected",
                        out.len()
                    ),
                )),
            }
        };
        read(Plane::Color, PixelFormat::Rgb888, rgb)?;
        let mut floats = |plane, format, out: &mut [f32]| {
            let mut bytes = vec![0u8; out.len() * 4];
            read(plane, format, &mut bytes)?;
            for (o, b) in out.iter_mut().zip(bytes.chunks_exact(4)) {
                *o = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            }
            Ok::<(), Failure>(())
        };
        if want_depth {
            floats(Plane::Depth, PixelFormat::DepthF32, unsafe {
                output(depth_out, depth_len, "depth_out")
            }?)?;
        }
        if want_normal {
            floats(Plane::Normal, PixelFormat::NormalF32, unsafe {
                output(normal_out, normal_len, "normal_out")
            }?)?;
        }
        Ok(())
    })
}

fn device_error(e: sim_target::DeviceError) -> Failure {
    Failure::new(fpgfx_status::FPGFX_DEVICE_ERROR, e.to_string())
}
