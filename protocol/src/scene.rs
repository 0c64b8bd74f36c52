//! The ray tracer's register image: 32-bit AXI4-Lite words the controller writes before a
//! frame (seed 002, MicroBlaze driver, `WorldDescription`).
//!
//! The image carries everything the scene file (docs/requirements.md §4.11) can express,
//! so that the device needs no other input than these registers and the texture memory.
//! Sizes are const parameters, `OBJ` objects and `LIGHTS` lights (the seed's OBJ_NUM = 8
//! and LIGHTS_NUM = 2; light 0 is the ambient light). Between frames the controller sends
//! only what changed ([`diff`]), as [`RegWrite`] runs.
//!
//! # Number formats
//!
//! Real values are in the image's **value format**, named by header word 15
//! ([`hdr::VALUE_FORMAT`], [`ValueFormat`]) so that every reader (the device, an RTL
//! testbench, the C library) knows how to read them without being told out of band:
//!
//! - **0, Q16.16** (the seed's `ap_fixed<32,16>`, and the default): two's complement, value
//!   × 65536 rounded to nearest, ties away from zero, range −32768 … 32767.99998.
//!   [`q16_from_f64`] refuses NaN, infinities and values outside that range, naming the
//!   field, rather than saturating.
//! - **1, binary32**: the IEEE-754 bit pattern, rounded to nearest even, as an HLS `float`
//!   port on AXI4-Lite takes it. A float datapath then starts from the scene's values
//!   rounded once to f32 (relative error ≤ 2⁻²⁴) instead of quantised to 2⁻¹⁶ absolute.
//!   [`f32_from_f64`] refuses NaN, infinities and magnitudes beyond f32, naming the field.
//!
//! Any other code in word 15 is refused ([`SceneError::Code`] naming `value_format`) by
//! [`SceneRegs::from_words`] and [`SceneRegs::write`], so a held image always has a known
//! format. A Q16.16 image is word for word the image of register-map version 1 before the
//! field existed (word 15 was "reserved, 0"). A target says in
//! [`crate::frame::Caps::float_regs`] which of its number formats want binary32 registers;
//! the host picks the format with [`ValueFormat::for_caps`]. **Exception:** `MAX_DISTANCE`
//! (1e6 in the seed) cannot be held by Q16.16, so it is binary32 bits in both formats.
//! Counts, sizes, codes and seeds are plain unsigned integers in both. The controller's
//! per-frame animation steps ([`crate::frame::Ramp`], [`crate::frame::Orbit`]) add and
//! rotate Q16.16 words, so an auto-restarted animation needs a Q16.16 image: the
//! controller refuses a non-empty animation while word 15 says binary32.
//!
//! # Derived words
//!
//! Three groups of words are not the scene's own values but computed from them in f64
//! by the host: the camera basis u, v, w, the pixel pitch K, and each object's inverse
//! transform M⁻¹. A block that has no sines, tangents or f64 (ViRAY's HLS core reads u,
//! v, w; the RTL core in `hw/rt-core` reads all three) computes with these words, while
//! the golden model derives the same numbers itself from the decoded image. The host
//! (`jobs::scene::to_regs`) therefore derives them from the image's *decoded* values
//! with the model's own functions (`sim_target::rt::derive`), so the two agree bit for
//! bit; `sim_target::scene_regs::check_derived` tells whether an image's derived words
//! are the ones its other words imply, naming the first that is not (a controller-side
//! ramp of the camera position or an object's rotation makes them stale).
//!
//! # Register map (word offsets)
//!
//! | offset | field | format |
//! |---|---|---|
//! | 0 | magic `0x46505254` ("FPRT") | u32 |
//! | 1 | version (bits 0–15) \| OBJ (16–23) \| LIGHTS (24–31) | u32 |
//! | 2 | object count | u32 ≤ OBJ |
//! | 3 | light count (ambient included) | u32 ≤ LIGHTS |
//! | 4, 5 | width, height | u32, 1 … 65 535 |
//! | 6 | depth (RAYTRACING_DEPTH) | u32, 1 … 16 |
//! | 7 | bias (CORE_BIAS) | real |
//! | 8 | max_distance | **f32 bits** |
//! | 9–11 | background r, g, b | real × 3 |
//! | 12 | samples per pixel | u32 ≥ 1 |
//! | 13 | flags ([`FLAG_SHADOWS`] …) | u32 |
//! | 14 | jitter seed | u32 |
//! | 15 | value format: 0 Q16.16, 1 binary32 ([`ValueFormat`]) | u32 code |
//! | 16–18 | camera position | real × 3 |
//! | 19–21 | camera look_at | real × 3 |
//! | 22–24 | camera up | real × 3 |
//! | 25 | fov_y, degrees | real |
//! | 26–28, 29–31, 32–34 | basis u, v, w (ViRAY's form, derived by the host) | real × 9 |
//! | 35 | near_plane (image plane distance along −w) | real |
//! | 36, 37 | pixel pitch K (derived by the host), low and high word | u64, 2⁻⁴⁰ units |
//! | 38 + 12·i | light i: [`light`] offsets | |
//! | 38 + 12·LIGHTS + 54·j | object j: [`obj`] offsets | |
//!
//! Light block (12 words): kind (0 ambient, 1 point, 2 spot), position ×3, colour ×3,
//! direction ×3, cos_outer, cos_inner. Object block (54 words): shape, translate ×3,
//! scale ×3, rotate ×3 (degrees), ambient k + colour ×3, diffuse k + colour ×3 + model +
//! σ², specular k + colour ×3 + model + exponent (u32 ≤ 1023), reflection mode + η + κ,
//! texture kind, mapping, scale ×2, offset ×2, colour2 ×3, filter, seed, base texel,
//! size (`width_log2 | height_log2 << 8`), Torrance–Sparrow η + κ, constant reflectance r,
//! and the inverse linear transform M⁻¹ ×9 (derived by the host).
//! With the defaults the map is 494 words. "real" is a word in the image's value format.

use heapless::Vec;

use crate::frame::{RegWrite, REG_WRITE_WORDS};

/// First word of the image: "FPRT".
pub const MAGIC: u32 = 0x4650_5254;
/// Register-map version in word 1: bumped on any layout change, so that a device refuses
/// an image laid out for another version instead of misreading it.
pub const VERSION: u16 = 2;

/// Flag: trace shadow rays (SHADOW_ENABLE).
pub const FLAG_SHADOWS: u32 = 1 << 0;
/// Flag: flip normals facing away from the ray so both sides shade (INTERNAL_SHADING).
pub const FLAG_INTERNAL_SHADING: u32 = 1 << 1;
/// Flag: objects may shadow themselves (SELF_SHADOW_ENABLE).
pub const FLAG_SELF_SHADOW: u32 = 1 << 2;
/// Flag: sample textures (TEXTURE_ENABLE).
pub const FLAG_TEXTURES: u32 = 1 << 3;

/// Word offsets of the header. Each field's meaning and range is on the typed field it
/// carries ([`crate::scene::RenderRegs`] and the counts); these say where it sits.
pub mod hdr {
    /// Holds [`super::MAGIC`]: an image without it is refused, not rendered.
    pub const MAGIC: usize = 0;
    /// [`super::VERSION`] | OBJ << 16 | LIGHTS << 24, so an image built for other
    /// capacities is refused ([`super::SceneRegs::VERSION_WORD`]).
    pub const VERSION: usize = 1;
    /// Objects in use (≤ OBJ); the device ignores the blocks after them.
    pub const OBJECT_COUNT: usize = 2;
    /// Lights in use, the ambient one included (≤ LIGHTS).
    pub const LIGHT_COUNT: usize = 3;
    /// [`super::RenderRegs::width`].
    pub const WIDTH: usize = 4;
    /// [`super::RenderRegs::height`].
    pub const HEIGHT: usize = 5;
    /// [`super::RenderRegs::depth`].
    pub const DEPTH: usize = 6;
    /// [`super::RenderRegs::bias`], a real.
    pub const BIAS: usize = 7;
    /// [`super::RenderRegs::max_distance`], f32 bits whatever the value format (Q16.16
    /// cannot hold the seed's 1e6).
    pub const MAX_DISTANCE: usize = 8;
    /// [`super::RenderRegs::background`], 3 reals.
    pub const BACKGROUND: usize = 9;
    /// [`super::RenderRegs::spp`].
    pub const SPP: usize = 12;
    /// [`super::RenderRegs::flags`].
    pub const FLAGS: usize = 13;
    /// [`super::RenderRegs::seed`].
    pub const SEED: usize = 14;
    /// The [`super::ValueFormat`] code every real of the image is read in: a field of the
    /// image rather than a setting of the reader, so a testbench or C caller handed only
    /// the words decodes them right.
    pub const VALUE_FORMAT: usize = 15;
    /// Words in the header.
    pub const WORDS: usize = 16;
}

/// Word offsets inside the camera block, from [`crate::scene::cam::OFFSET`]; the meaning
/// of each is on the [`crate::scene::CameraRegs`] field it carries (all reals).
pub mod cam {
    /// Word offset of the camera block: right after the header.
    pub const OFFSET: usize = super::hdr::WORDS;
    /// [`super::CameraRegs::position`], × 3.
    pub const POSITION: usize = 0;
    /// [`super::CameraRegs::look_at`], × 3.
    pub const LOOK_AT: usize = 3;
    /// [`super::CameraRegs::up`], × 3.
    pub const UP: usize = 6;
    /// [`super::CameraRegs::fov_y`].
    pub const FOV_Y: usize = 9;
    /// [`super::CameraRegs::u`], × 3.
    pub const U: usize = 10;
    /// [`super::CameraRegs::v`], × 3.
    pub const V: usize = 13;
    /// [`super::CameraRegs::w`], × 3.
    pub const W: usize = 16;
    /// [`super::CameraRegs::near_plane`].
    pub const NEAR_PLANE: usize = 19;
    /// [`super::CameraRegs::pitch`]: low word, then high word (a u64 in both formats).
    pub const PITCH: usize = 20;
    /// Words in the camera block.
    pub const WORDS: usize = 22;
}

/// Word offsets inside a light block; light i starts at
/// [`crate::scene::SceneRegs::light_offset`]`(i)`. The meaning of each is on the
/// [`crate::scene::LightRegs`] field it carries.
pub mod light {
    /// Word offset of light 0's block: right after the camera block.
    pub const OFFSET: usize = super::cam::OFFSET + super::cam::WORDS;
    /// [`super::LightRegs::kind`] as a [`super::LightKind`] code.
    pub const KIND: usize = 0;
    /// [`super::LightRegs::position`], × 3.
    pub const POSITION: usize = 1;
    /// [`super::LightRegs::color`], × 3.
    pub const COLOR: usize = 4;
    /// [`super::LightRegs::direction`], × 3.
    pub const DIRECTION: usize = 7;
    /// [`super::LightRegs::cos_outer`].
    pub const COS_OUTER: usize = 10;
    /// [`super::LightRegs::cos_inner`].
    pub const COS_INNER: usize = 11;
    /// Words per light.
    pub const WORDS: usize = 12;
}

/// Word offsets inside an object block; object j starts at
/// [`crate::scene::SceneRegs::object_offset`]`(j)`. The meaning of each is on the
/// [`crate::scene::ObjectRegs`], [`crate::scene::MaterialRegs`] or
/// [`crate::scene::TextureRegs`] field it carries (codes are u32).
pub mod obj {
    /// [`super::ObjectRegs::shape`] as a [`super::Shape`] code.
    pub const SHAPE: usize = 0;
    /// [`super::ObjectRegs::translate`], × 3.
    pub const TRANSLATE: usize = 1;
    /// [`super::ObjectRegs::scale`], × 3.
    pub const SCALE: usize = 4;
    /// [`super::ObjectRegs::rotate`], × 3.
    pub const ROTATE: usize = 7;
    /// k of [`super::MaterialRegs::ambient`].
    pub const AMBIENT_K: usize = 10;
    /// Colour of [`super::MaterialRegs::ambient`], × 3.
    pub const AMBIENT_COLOR: usize = 11;
    /// k of [`super::MaterialRegs::diffuse`].
    pub const DIFFUSE_K: usize = 14;
    /// Colour of [`super::MaterialRegs::diffuse`], × 3.
    pub const DIFFUSE_COLOR: usize = 15;
    /// [`super::MaterialRegs::diffuse_model`] as a [`super::DiffuseModel`] code.
    pub const DIFFUSE_MODEL: usize = 18;
    /// [`super::MaterialRegs::sigma2`].
    pub const SIGMA2: usize = 19;
    /// k of [`super::MaterialRegs::specular`].
    pub const SPECULAR_K: usize = 20;
    /// Colour of [`super::MaterialRegs::specular`], × 3.
    pub const SPECULAR_COLOR: usize = 21;
    /// [`super::MaterialRegs::specular_model`] as a [`super::SpecularModel`] code.
    pub const SPECULAR_MODEL: usize = 24;
    /// [`super::MaterialRegs::exponent`], a plain u32.
    pub const EXPONENT: usize = 25;
    /// [`super::MaterialRegs::reflection`] as a [`super::ReflectionMode`] code.
    pub const REFLECTION_MODE: usize = 26;
    /// [`super::MaterialRegs::eta`].
    pub const ETA: usize = 27;
    /// [`super::MaterialRegs::kappa`].
    pub const KAPPA: usize = 28;
    /// [`super::TextureRegs::kind`] as a [`super::TextureKind`] code.
    pub const TEX_KIND: usize = 29;
    /// [`super::TextureRegs::mapping`] as a [`super::Mapping`] code.
    pub const TEX_MAPPING: usize = 30;
    /// [`super::TextureRegs::scale`], × 2.
    pub const TEX_SCALE: usize = 31;
    /// [`super::TextureRegs::offset`], × 2.
    pub const TEX_OFFSET: usize = 33;
    /// [`super::TextureRegs::color2`], × 3.
    pub const TEX_COLOR2: usize = 35;
    /// [`super::TextureRegs::filter`] as a [`super::TexFilter`] code.
    pub const TEX_FILTER: usize = 38;
    /// [`super::TextureRegs::seed`].
    pub const TEX_SEED: usize = 39;
    /// [`super::TextureRegs::base`].
    pub const TEX_BASE: usize = 40;
    /// `width_log2 | height_log2 << 8` of [`super::TextureRegs`]: one word for both, as
    /// neither exceeds 8.
    pub const TEX_SIZE: usize = 41;
    /// [`super::MaterialRegs::spec_eta`]: its own word, because a material may pair it
    /// with a different reflection η, so it cannot share [`ETA`].
    pub const SPEC_ETA: usize = 42;
    /// [`super::MaterialRegs::spec_kappa`].
    pub const SPEC_KAPPA: usize = 43;
    /// [`super::MaterialRegs::reflectance`]: its own word, because the scene file gives r
    /// separately from k_s.
    pub const REFLECTANCE: usize = 44;
    /// [`super::ObjectRegs::minv`], × 9, row-major.
    pub const MINV: usize = 45;
    /// Words per object.
    pub const WORDS: usize = 54;
}

/// Which block a refused value belongs to: a scene has several lights and objects with
/// the same field names, so a message must say which one it means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum At {
    /// The header or the camera: their field names are unique, so messages add nothing.
    Global,
    /// Light i; 0 is the ambient light, 1… the scene file's lights in order.
    Light(usize),
    /// Object i, numbered as the scene file lists them.
    Object(usize),
}

impl core::fmt::Display for At {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            At::Global => Ok(()),
            At::Light(i) => write!(f, "light {i}: "),
            At::Object(i) => write!(f, "object {i}: "),
        }
    }
}

/// Why a scene value cannot be put into (or read from) the registers.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// Not finite or outside the Q16.16 range.
    #[error("{at}`{field}` = {value} does not fit Q16.16 (finite, -32768 <= v < 32768)")]
    Q16 {
        /// The block, which prefixes the message.
        at: At,
        /// The field as the scene file names it (`bias`, `material.diffuse.k`), so that
        /// the user can find the line to fix.
        field: &'static str,
        /// The value as given, before conversion.
        value: f64,
    },
    /// Not a finite binary32 value.
    #[error("{at}`{field}` = {value} is not a finite f32")]
    F32 {
        /// The block, which prefixes the message.
        at: At,
        /// The field as the scene file names it (`bias`, `material.diffuse.k`), so that
        /// the user can find the line to fix.
        field: &'static str,
        /// The value as given, before conversion.
        value: f64,
    },
    /// An integer outside its range.
    #[error("{at}`{field}` = {value} is outside {min}..={max}")]
    Int {
        /// The block, which prefixes the message.
        at: At,
        /// The field as the scene file names it (`bias`, `material.diffuse.k`), so that
        /// the user can find the line to fix.
        field: &'static str,
        /// The value as given.
        value: u64,
        /// Lower bound, inclusive.
        min: u64,
        /// Upper bound, inclusive.
        max: u64,
    },
    /// A code word that names no enumeration value.
    #[error("{at}`{field}` = {value} is not a valid code")]
    Code {
        /// The block, which prefixes the message.
        at: At,
        /// The field as the scene file names it (`bias`, `material.diffuse.k`), so that
        /// the user can find the line to fix.
        field: &'static str,
        /// The word read, which no value of the field's enumeration has as its code.
        value: u32,
    },
    /// A light or object index beyond the map's capacity.
    #[error("{what} {index} does not exist (capacity {capacity})")]
    Index {
        /// "light" or "object".
        what: &'static str,
        /// The index asked for.
        index: usize,
        /// Blocks of that kind in the map (LIGHTS or OBJ): valid indices are below it.
        capacity: usize,
    },
    /// A register write that runs past the map.
    #[error("write of {len} words at offset {offset} runs past the {size}-word register map")]
    Bounds {
        /// Word offset the write starts at.
        offset: usize,
        /// Words in the write.
        len: usize,
        /// [`SceneRegs::WORDS`] of the map written to.
        size: usize,
    },
    /// A word slice of the wrong length.
    #[error("expected {expected} words, got {got}")]
    Length {
        /// [`SceneRegs::WORDS`] of the map built or copied.
        expected: usize,
        /// Length of the slice passed in.
        got: usize,
    },
    /// Word 0 is not [`MAGIC`].
    #[error("magic word is {found:#010x}, expected {MAGIC:#010x}")]
    Magic {
        /// Word 0 as received: anything else means the words are not a scene image, or
        /// are shifted.
        found: u32,
    },
    /// Word 1 does not match this map's version and capacities.
    #[error("version word is {found:#010x}, expected {expected:#010x} (version | OBJ << 16 | LIGHTS << 24)")]
    Version {
        /// Word 1 as received.
        found: u32,
        /// [`SceneRegs::VERSION_WORD`] of the capacities the receiver was built for.
        expected: u32,
    },
}

impl SceneError {
    fn at(self, at: At) -> Self {
        match self {
            SceneError::Q16 { field, value, .. } => SceneError::Q16 { at, field, value },
            SceneError::F32 { field, value, .. } => SceneError::F32 { at, field, value },
            SceneError::Int {
                field,
                value,
                min,
                max,
                ..
            } => SceneError::Int {
                at,
                field,
                value,
                min,
                max,
            },
            SceneError::Code { field, value, .. } => SceneError::Code { at, field, value },
            other => other,
        }
    }
}

/// Converts to Q16.16, rounding to nearest (ties away from zero); NaN, infinities and
/// values outside −32768 … 32767.99998 are errors naming `field`.
pub fn q16_from_f64(field: &'static str, value: f64) -> Result<i32, SceneError> {
    let err = SceneError::Q16 {
        at: At::Global,
        field,
        value,
    };
    let scaled = value * 65536.0;
    // NaN fails both comparisons.
    if !(-2_147_483_648.5..2_147_483_647.5).contains(&scaled) {
        return Err(err);
    }
    let r = if scaled >= 0.0 {
        (scaled + 0.5) as i64
    } else {
        -((-scaled + 0.5) as i64)
    };
    i32::try_from(r).map_err(|_| err)
}

/// The real a Q16.16 word holds; exact, as every Q16.16 value is an f64, so it undoes
/// [`q16_from_f64`] up to that function's rounding.
pub fn q16_to_f64(q: i32) -> f64 {
    f64::from(q) / 65536.0
}

/// Converts to IEEE binary32 bits, rounding to nearest even; NaN, infinities and
/// magnitudes that round beyond f32's largest finite value are errors naming `field`, as
/// [`q16_from_f64`] refuses what Q16.16 cannot hold.
pub fn f32_from_f64(field: &'static str, value: f64) -> Result<u32, SceneError> {
    let f = value as f32;
    if f.is_finite() {
        Ok(f.to_bits())
    } else {
        Err(SceneError::F32 {
            at: At::Global,
            field,
            value,
        })
    }
}

macro_rules! code_enum {
    ($(#[$m:meta])* $name:ident { $($(#[$vm:meta])* $v:ident = $c:literal),* $(,)? }) => {
        $(#[$m])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        pub enum $name {
            $($(#[$vm])* $v = $c),*
        }
        impl $name {
            /// Every value, in code order, for iterating over the codes (tests, fuzzers,
            /// `from_code`).
            pub const ALL: &'static [$name] = &[$($name::$v),*];
            /// The word this value is written as: part of the register map, so a change
            /// of codes is a change of [`VERSION`].
            pub const fn code(self) -> u32 {
                self as u32
            }
            /// The value a register word names, or `None` for a word no value has as its
            /// code (a reader reports it as [`SceneError::Code`]).
            pub fn from_code(c: u32) -> Option<Self> {
                Self::ALL.iter().copied().find(|v| v.code() == c)
            }
        }
    };
}

code_enum!(
    /// What a light block describes, and so which of its words are read; light 0 is
    /// always ambient and no other light may be.
    LightKind {
        /// Uniform ambient light L_a (only the colour is used).
        #[default]
        Ambient = 0,
        /// Point light with quadratic falloff (the direction and cone words are unused).
        Point = 1,
        /// Point light restricted to a cone (docs/requirements.md §4.4).
        Spot = 2,
    }
);

code_enum!(
    /// Canonical shape of an object (docs/requirements.md §4.3, all inside [−1, 1]³).
    Shape {
        /// Unit sphere.
        #[default]
        Sphere = 0,
        /// Plane y = 0.
        Plane = 1,
        /// Unit disk in y = 0.
        Disk = 2,
        /// Square |x|, |z| ≤ 1 in y = 0.
        Square = 3,
        /// x² + z² = 1 for y ∈ [−1, 1], open: no caps.
        Cylinder = 4,
        /// Radius 1 at y = 0 narrowing to the apex at y = 1, without a base.
        Cone = 5,
        /// Cube [−1, 1]³.
        Cube = 6,
    }
);

code_enum!(
    /// Diffuse BRDF f_d (docs/requirements.md §4.4).
    DiffuseModel {
        /// 1/π: ideal matte.
        #[default]
        Lambert = 0,
        /// Oren–Nayar rough matte, roughness from [`MaterialRegs::sigma2`].
        OrenNayar = 1,
    }
);

code_enum!(
    /// Specular BRDF f_s; both share the lobe D = (e + 2)/(2π)·(n·ω_h)^e
    /// (docs/requirements.md §4.4).
    SpecularModel {
        /// Normalised Blinn–Phong: D alone.
        #[default]
        BlinnPhong = 0,
        /// Torrance–Sparrow: D·G·F / (4 cos θ_o cos θ_i), F from
        /// [`MaterialRegs::spec_eta`] and [`MaterialRegs::spec_kappa`].
        TorranceSparrow = 1,
    }
);

code_enum!(
    /// How much of the mirror-reflected ray a surface passes on (docs/requirements.md
    /// §4.5); at [`RenderRegs::depth`] 1 no bounce is traced whatever the mode.
    ReflectionMode {
        /// No reflected ray.
        #[default]
        None = 0,
        /// r = [`MaterialRegs::reflectance`], whatever the angle.
        Constant = 1,
        /// Unpolarised Fresnel reflectance of η − iκ ([`MaterialRegs::eta`],
        /// [`MaterialRegs::kappa`]); κ > 0 is a conductor.
        Fresnel = 2,
        /// (beyond) Transmissive dielectric: Fresnel reflection plus a refracted ray of
        /// weight 1 − r, index η.
        Glass = 3,
    }
);

code_enum!(
    /// What fills a material's texture (docs/requirements.md §4.6). The grey kinds mix
    /// the diffuse colour with [`TextureRegs::color2`].
    TextureKind {
        /// No texture: the material's own colours.
        #[default]
        None = 0,
        /// Grey (x ⊕ y) & 255.
        Xor = 1,
        /// Grey squares of [`TextureRegs::seed`] texels.
        Checkerboard = 2,
        /// Consecutive texels red, green, blue.
        RgbDots = 3,
        /// Grey ½(1 + sin(f·x + t·turbulence)) of value noise seeded by
        /// [`TextureRegs::seed`].
        Marble = 4,
        /// Grey fract(rings·r + t·turbulence), seeded likewise.
        Wood = 5,
        /// Texels uploaded to texture memory at [`TextureRegs::base`]; the golden model
        /// generates only the procedural kinds and refuses it.
        Image = 6,
    }
);

code_enum!(
    /// How the object-space hit p ∈ [−1, 1]³ becomes texture coordinates (u, v) ∈ [0, 1)
    /// before [`TextureRegs::scale`] and [`TextureRegs::offset`] apply.
    Mapping {
        /// u = (x + 1)/2, v = (z + 1)/2.
        #[default]
        Planar = 0,
        /// u from atan2(x, z), v = (y + 1)/2.
        Cylindrical = 1,
        /// u from atan2(x, z), v = 1 − acos(y)/π.
        Spherical = 2,
    }
);

code_enum!(
    /// How a texture is sampled between texel centres (which sit at +0.5).
    TexFilter {
        /// The nearest texel: hard texel edges when magnified.
        #[default]
        Nearest = 0,
        /// Linear in u and v between the four nearest texels.
        Bilinear = 1,
    }
);

code_enum!(
    /// How the image's real values are written ([`hdr::VALUE_FORMAT`]; see the module
    /// docs): the datapath's own format where a float one can take IEEE words, so that
    /// the scene is not quantised to Q16.16 on the way to a float datapath.
    ValueFormat {
        /// Q16.16 two's complement: what the seed's `ap_fixed<32,16>` block reads.
        #[default]
        Q16_16 = 0,
        /// IEEE binary32 bits: what an HLS `float` port on AXI4-Lite reads.
        Binary32 = 1,
    }
);

impl ValueFormat {
    /// The word `value` is written as; a value this format cannot hold is an error
    /// naming `field` ([`q16_from_f64`], [`f32_from_f64`]).
    pub fn encode(self, field: &'static str, value: f64) -> Result<u32, SceneError> {
        match self {
            ValueFormat::Q16_16 => q16_from_f64(field, value).map(|q| q as u32),
            ValueFormat::Binary32 => f32_from_f64(field, value),
        }
    }

    /// The word `value` is written as when it is derived rather than given: rounded as
    /// [`Self::encode`] rounds, but clipped to the format's range instead of refused
    /// (NaN gives 0 in Q16.16), which is how a datapath in this format converts the same
    /// f64 (the golden model's `from_f64`), so that a core reading the word computes with
    /// the model's number.
    pub fn encode_saturating(self, value: f64) -> u32 {
        match self {
            ValueFormat::Q16_16 => {
                let scaled = value * 65536.0;
                let r = scaled + 0.5f64.copysign(scaled);
                // `as` saturates and maps NaN to 0; truncation toward zero after adding
                // ±½ is rounding half away from zero
                (r as i64).clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32 as u32
            }
            ValueFormat::Binary32 => (value as f32).to_bits(),
        }
    }

    /// The real `word` holds, exactly (both formats widen to f64 without rounding).
    pub fn decode(self, word: u32) -> f64 {
        match self {
            ValueFormat::Q16_16 => q16_to_f64(word as i32),
            ValueFormat::Binary32 => f64::from(f32::from_bits(word)),
        }
    }

    /// The format a target that announced `caps` wants for a frame computed in
    /// `numeric`: binary32 where [`crate::frame::Caps::float_regs`] lists the format,
    /// Q16.16 otherwise (so a target that says nothing gets the seed's image).
    pub fn for_caps(caps: &crate::frame::Caps, numeric: crate::frame::Numeric) -> Self {
        if caps.float_regs.contains(numeric) {
            ValueFormat::Binary32
        } else {
            ValueFormat::Q16_16
        }
    }
}

/// The header's frame settings, as [`SceneRegs::set_render`] writes them (`[render]` of
/// the scene file; docs/requirements.md §4.1).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RenderRegs {
    /// Frame width in pixels, 1 … 65535.
    pub width: u32,
    /// Frame height in pixels, 1 … 65535.
    pub height: u32,
    /// RAYTRACING_DEPTH, 1 … 16: 1 traces primary rays only, each further level one
    /// more reflection bounce (and its shadow rays).
    pub depth: u32,
    /// CORE_BIAS, world units: hits nearer than this are ignored, so that a secondary
    /// ray does not hit the surface it starts on.
    pub bias: f64,
    /// MAX_DISTANCE, world units: hits beyond it count as misses. Stored as f32 bits
    /// in both value formats because the seed's 1e6 is beyond Q16.16, so it must be a
    /// finite f32.
    pub max_distance: f64,
    /// Linear RGB of rays that hit nothing (1.0 = full scale before clamping).
    pub background: [f64; 3],
    /// Samples per pixel, 1 … 65536, on a regular grid of ⌈√spp⌉² positions.
    pub spp: u32,
    /// [`FLAG_SHADOWS`] and the other `FLAG_*` bits: the seed's compile-time switches,
    /// chosen per frame.
    pub flags: u32,
    /// Seed for sample jitter; the golden model samples a fixed grid and ignores it.
    pub seed: u32,
}

/// The camera in both the scene file's form and ViRAY's (basis + near plane); the host
/// derives the latter from the former (docs/requirements.md §4.2), so a block can read
/// whichever it was built for. The register map does not check that the two agree.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CameraRegs {
    /// Eye position, world units: where every primary ray starts.
    pub position: [f64; 3],
    /// The point at the centre of the image; w = normalize(position − look_at).
    pub look_at: [f64; 3],
    /// Up hint: only its part across the view direction counts, and it must not be
    /// parallel to it (u = normalize(up × w)).
    pub up: [f64; 3],
    /// Vertical field of view in degrees; the horizontal one follows from width / height.
    pub fov_y: f64,
    /// Unit vector to the image's right.
    pub u: [f64; 3],
    /// Unit vector to the image's top, w × u.
    pub v: [f64; 3],
    /// Unit vector pointing backwards, away from look_at: rays leave along −w.
    pub w: [f64; 3],
    /// Distance of the image plane along −w; the host writes 1.
    pub near_plane: f64,
    /// The pixel pitch K = tan(fov_y / 2) / (height · g) on the image plane at distance
    /// 1, in units of 2⁻⁴⁰ (g = ⌈√spp⌉, the sub-pixel grid's side), derived by the host:
    /// sample column c of the `width · g` columns lies at x = (2c + 1 − width · g) · K and
    /// sample row r at y = (height · g − 2r − 1) · K. An integer, so that a fixed-point
    /// core forms every x and y as the same word the model rounds from f64 (see
    /// `docs/rt-core.md`); a plain u64 in both value formats.
    pub pitch: u64,
}

/// A light block (docs/requirements.md §4.4). Words a kind does not use are written as
/// given and ignored by the device.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LightRegs {
    /// Decides which of the other fields the device reads.
    pub kind: LightKind,
    /// Where a point or spot light sits, world units.
    pub position: [f64; 3],
    /// L_a for the ambient light; for the others the radiant intensity per channel,
    /// falling off with 1/d².
    pub color: [f64; 3],
    /// Axis of a spot cone, pointing away from the light; need not be unit length.
    pub direction: [f64; 3],
    /// cos(α/2): outside the cone of half-angle α/2 a spot gives no light.
    pub cos_outer: f64,
    /// cos(β/2) ≥ cos_outer: inside this cone a spot is at full strength; between the
    /// two it ramps linearly in the cosine.
    pub cos_inner: f64,
}

/// One term of the shading sum, k · colour (k_a c_a, k_d c_d or k_s c_s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TermRegs {
    /// Weight of the term; 0 switches it off (a reader takes an ambient or specular term
    /// with k = 0 as absent). k_d + k_s ≤ 1 conserves energy but is not enforced.
    pub k: f64,
    /// Per-channel colour the light is multiplied by (0 … 1 for a physical surface; not
    /// enforced).
    pub color: [f64; 3],
}

/// An object's material, inside its block: ViRAY has no material table, so a material
/// shared in the scene file is written once per object using it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MaterialRegs {
    /// Weighs the ambient light L_a; a texture replaces its colour.
    pub ambient: TermRegs,
    /// Weighs the point and spot lights through the diffuse BRDF; a texture replaces
    /// its colour.
    pub diffuse: TermRegs,
    /// The diffuse BRDF.
    pub diffuse_model: DiffuseModel,
    /// Oren–Nayar roughness σ² (0 behaves as Lambert); read only with
    /// [`DiffuseModel::OrenNayar`].
    pub sigma2: f64,
    /// Weighs the point and spot lights through the specular BRDF.
    pub specular: TermRegs,
    /// The specular BRDF.
    pub specular_model: SpecularModel,
    /// Exponent e of the specular lobe, 0 … 1023: the seed's power by repeated squaring
    /// takes ten steps.
    pub exponent: u32,
    /// Whether and how a reflected ray is traced.
    pub reflection: ReflectionMode,
    /// Refractive index η of [`ReflectionMode::Fresnel`], and the index of refraction of
    /// [`ReflectionMode::Glass`] (against vacuum).
    pub eta: f64,
    /// Extinction coefficient κ of [`ReflectionMode::Fresnel`]; 0 for dielectrics.
    pub kappa: f64,
    /// η of the Fresnel factor inside [`SpecularModel::TorranceSparrow`], separate from
    /// the reflection's (the scene file's `specular.eta`, default 1.5).
    pub spec_eta: f64,
    /// κ of that Fresnel factor (`specular.extinction`, default 0).
    pub spec_kappa: f64,
    /// r of [`ReflectionMode::Constant`] (the scene file's `reflection.r`, default k_s).
    pub reflectance: f64,
    /// Replaces the ambient and diffuse colours; [`TextureKind::None`] leaves them.
    pub texture: TextureRegs,
}

/// A material's texture (docs/requirements.md §4.6). The texture memory holds 256 × 256
/// 32-bit texels shared by every texture, so each names its own square of it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TextureRegs {
    /// What generates the texels; [`TextureKind::None`] makes the other fields unused.
    pub kind: TextureKind,
    /// How the hit point becomes (u, v).
    pub mapping: Mapping,
    /// Repeats of the texture across the mapping's range: u′ = fract(u · scale + offset).
    pub scale: [f64; 2],
    /// Shift of the texture, in repeats, added after scaling.
    pub offset: [f64; 2],
    /// Colour of a grey texture's black texels: white ones take the diffuse colour and
    /// greys blend the two.
    pub color2: [f64; 3],
    /// How texels are sampled between their centres.
    pub filter: TexFilter,
    /// The noise seed of [`TextureKind::Marble`] and [`TextureKind::Wood`], or the square
    /// size in texels of [`TextureKind::Checkerboard`]; unused by the other kinds.
    pub seed: u32,
    /// First texel of this texture in texture memory, 0 … 65535.
    pub base: u32,
    /// log2 of the width in texels, 0 … 8 (256 is the texture memory's side).
    pub width_log2: u8,
    /// log2 of the height in texels, 0 … 8.
    pub height_log2: u8,
}

/// An object block: a canonical shape placed by scale, then rotation, then translation
/// (docs/requirements.md §4.3).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ObjectRegs {
    /// The canonical shape, inside [−1, 1]³ before the transform.
    pub shape: Shape,
    /// Where the shape's origin goes, world units; applied last.
    pub translate: [f64; 3],
    /// Per-axis scale, applied first: a sphere of scale (2, 1, 1) is an ellipsoid.
    pub scale: [f64; 3],
    /// Rotation in degrees about x, then y, then z, between scale and translation.
    pub rotate: [f64; 3],
    /// The inverse of the linear part, M⁻¹ = S⁻¹·Rᵀ, row-major, derived by the host from
    /// `scale` and `rotate` (rays go into object space by M⁻¹, normals out by its
    /// transpose): a core without sines reads it instead of the degrees. Written
    /// saturating, as the model converts it: a scale below the value format's resolution
    /// gives the format's largest value rather than an error.
    pub minv: [[f64; 3]; 3],
    /// How the surface shades.
    pub material: MaterialRegs,
}

// Block encoders and decoders: `w` is the block's words, `fmt` the image's value format.
fn put_r(
    fmt: ValueFormat,
    w: &mut [u32],
    at: usize,
    field: &'static str,
    v: f64,
) -> Result<(), SceneError> {
    w[at] = fmt.encode(field, v)?;
    Ok(())
}
fn put_rv<const N: usize>(
    fmt: ValueFormat,
    w: &mut [u32],
    at: usize,
    field: &'static str,
    v: [f64; N],
) -> Result<(), SceneError> {
    for (i, x) in v.iter().enumerate() {
        put_r(fmt, w, at + i, field, *x)?;
    }
    Ok(())
}
fn get_r(fmt: ValueFormat, w: &[u32], at: usize) -> f64 {
    fmt.decode(w[at])
}
fn get_rv<const N: usize>(fmt: ValueFormat, w: &[u32], at: usize) -> [f64; N] {
    core::array::from_fn(|i| get_r(fmt, w, at + i))
}
/// The ranges [`RenderRegs`] documents for the frame's size, depth and samples.
fn check_render(r: &RenderRegs) -> Result<(), SceneError> {
    int("width", u64::from(r.width), 1, u64::from(u16::MAX))?;
    int("height", u64::from(r.height), 1, u64::from(u16::MAX))?;
    int("depth", u64::from(r.depth), 1, 16)?;
    int("spp", u64::from(r.spp), 1, 1 << 16)
}

fn int(field: &'static str, value: u64, min: u64, max: u64) -> Result<(), SceneError> {
    if value < min || value > max {
        Err(SceneError::Int {
            at: At::Global,
            field,
            value,
            min,
            max,
        })
    } else {
        Ok(())
    }
}
fn code<T>(field: &'static str, value: u32, f: fn(u32) -> Option<T>) -> Result<T, SceneError> {
    f(value).ok_or(SceneError::Code {
        at: At::Global,
        field,
        value,
    })
}

/// Words in the map of a device with room for `objects` objects and `lights` lights
/// (ambient included): for a controller that learns the capacities at run time from the
/// target's [`crate::frame::Caps`] and must refuse register writes past the end.
pub const fn map_words(objects: usize, lights: usize) -> usize {
    light::OFFSET + lights * light::WORDS + objects * obj::WORDS
}

/// The register image for `OBJ` objects and `LIGHTS` lights.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneRegs<const OBJ: usize = 8, const LIGHTS: usize = 2> {
    header: [u32; hdr::WORDS],
    camera: [u32; cam::WORDS],
    lights: [[u32; light::WORDS]; LIGHTS],
    objects: [[u32; obj::WORDS]; OBJ],
}

impl<const OBJ: usize, const LIGHTS: usize> Default for SceneRegs<OBJ, LIGHTS> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const OBJ: usize, const LIGHTS: usize> SceneRegs<OBJ, LIGHTS> {
    /// Words in the map ([`map_words`] of its capacities): 494 for the defaults.
    pub const WORDS: usize = map_words(OBJ, LIGHTS);
    /// Word offset of object 0's block, right after the light blocks.
    pub const OBJECTS_OFFSET: usize = light::OFFSET + LIGHTS * light::WORDS;
    /// Object blocks in the image (OBJ): a const a generic caller can read.
    pub const OBJ_CAPACITY: usize = OBJ;
    /// Light blocks in the image (LIGHTS, the ambient light's included).
    pub const LIGHT_CAPACITY: usize = LIGHTS;
    /// Word 1: version and capacities, so that a map built for other sizes is refused.
    pub const VERSION_WORD: u32 = VERSION as u32 | (OBJ as u32) << 16 | (LIGHTS as u32) << 24;
    // RegWrite offsets are u16 and the capacities must fit their bytes in word 1. Compared
    // as u64: `1 << 16` overflows a 16-bit usize (MSP430).
    const FITS: () =
        assert!(Self::WORDS as u64 <= 1 << 16 && OBJ < 256 && LIGHTS < 256 && LIGHTS >= 1);

    /// An empty Q16.16 scene: header magic and version set, no objects or lights, all
    /// else 0 (the device's power-on register file).
    pub fn new() -> Self {
        Self::with_format(ValueFormat::Q16_16)
    }

    /// An empty scene whose reals are written in `format`. The format is fixed when the
    /// image is made, not settable later, so that no value already written can be reread
    /// in another format than it was written in.
    pub fn with_format(format: ValueFormat) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::FITS;
        let mut header = [0; hdr::WORDS];
        header[hdr::MAGIC] = MAGIC;
        header[hdr::VERSION] = Self::VERSION_WORD;
        header[hdr::VALUE_FORMAT] = format.code();
        SceneRegs {
            header,
            camera: [0; cam::WORDS],
            lights: [[0; light::WORDS]; LIGHTS],
            objects: [[0; obj::WORDS]; OBJ],
        }
    }

    /// Word offset of light `i`'s block, for addressing one of its words in a write (not
    /// checked against LIGHTS).
    pub const fn light_offset(i: usize) -> usize {
        light::OFFSET + i * light::WORDS
    }

    /// Word offset of object `i`'s block (not checked against OBJ).
    pub const fn object_offset(i: usize) -> usize {
        Self::OBJECTS_OFFSET + i * obj::WORDS
    }

    /// The word at `offset`, or `None` past the map: what a device's register read
    /// returns.
    pub fn word(&self, offset: usize) -> Option<u32> {
        self.word_ref(offset)
    }

    fn word_mut(&mut self, offset: usize) -> Option<&mut u32> {
        if offset < hdr::WORDS {
            return self.header.get_mut(offset);
        }
        let o = offset - hdr::WORDS;
        if o < cam::WORDS {
            return self.camera.get_mut(o);
        }
        let o = o - cam::WORDS;
        if o < LIGHTS * light::WORDS {
            return self.lights[o / light::WORDS].get_mut(o % light::WORDS);
        }
        let o = o - LIGHTS * light::WORDS;
        self.objects
            .get_mut(o / obj::WORDS)
            .and_then(|b| b.get_mut(o % obj::WORDS))
    }

    /// Every word in offset order: the image as the device's register file holds it.
    pub fn words(&self) -> impl Iterator<Item = u32> + '_ {
        self.header
            .iter()
            .chain(self.camera.iter())
            .chain(self.lights.iter().flatten())
            .chain(self.objects.iter().flatten())
            .copied()
    }

    /// Copies the image into `out` (at least [`Self::WORDS`] long); returns the length.
    pub fn to_words(&self, out: &mut [u32]) -> Result<usize, SceneError> {
        if out.len() < Self::WORDS {
            return Err(SceneError::Length {
                expected: Self::WORDS,
                got: out.len(),
            });
        }
        for (o, w) in out.iter_mut().zip(self.words()) {
            *o = w;
        }
        Ok(Self::WORDS)
    }

    /// The format the image's reals are in (word 15). Always a known one: the
    /// constructors write one and [`Self::from_words`] and [`Self::write`] refuse others.
    pub fn value_format(&self) -> ValueFormat {
        ValueFormat::from_code(self.header[hdr::VALUE_FORMAT]).unwrap_or_default()
    }

    /// Refuses a value-format word that names no [`ValueFormat`], so that a held image
    /// never has reals of an unknown format.
    fn check_value_format(word: u32) -> Result<(), SceneError> {
        code("value_format", word, ValueFormat::from_code).map(|_| ())
    }

    /// Rebuilds an image from exactly [`Self::WORDS`] words, checking magic, version and
    /// value format. Other field values are not checked here (the typed getters do that).
    pub fn from_words(words: &[u32]) -> Result<Self, SceneError> {
        if words.len() != Self::WORDS {
            return Err(SceneError::Length {
                expected: Self::WORDS,
                got: words.len(),
            });
        }
        if words[hdr::MAGIC] != MAGIC {
            return Err(SceneError::Magic {
                found: words[hdr::MAGIC],
            });
        }
        if words[hdr::VERSION] != Self::VERSION_WORD {
            return Err(SceneError::Version {
                found: words[hdr::VERSION],
                expected: Self::VERSION_WORD,
            });
        }
        Self::check_value_format(words[hdr::VALUE_FORMAT])?;
        let mut s = Self::new();
        for (i, &w) in words.iter().enumerate() {
            if let Some(slot) = s.word_mut(i) {
                *slot = w;
            }
        }
        Ok(s)
    }

    /// Writes a run of words, as the device does for a [`RegWrite`]; a write past the map
    /// or of an unknown value-format code changes nothing.
    pub fn write(&mut self, offset: usize, words: &[u32]) -> Result<(), SceneError> {
        if offset
            .checked_add(words.len())
            .is_none_or(|end| end > Self::WORDS)
        {
            return Err(SceneError::Bounds {
                offset,
                len: words.len(),
                size: Self::WORDS,
            });
        }
        if let Some(&f) = hdr::VALUE_FORMAT
            .checked_sub(offset)
            .and_then(|i| words.get(i))
        {
            Self::check_value_format(f)?;
        }
        for (i, &w) in words.iter().enumerate() {
            if let Some(slot) = self.word_mut(offset + i) {
                *slot = w;
            }
        }
        Ok(())
    }

    /// Sets the numbers of objects and lights in use (lights include the ambient one).
    pub fn set_counts(&mut self, objects: usize, lights: usize) -> Result<(), SceneError> {
        int("object_count", objects as u64, 0, OBJ as u64)?;
        int("light_count", lights as u64, 0, LIGHTS as u64)?;
        self.header[hdr::OBJECT_COUNT] = objects as u32;
        self.header[hdr::LIGHT_COUNT] = lights as u32;
        Ok(())
    }

    /// Objects in use (word 2): a reader renders blocks 0 … count − 1 and ignores the
    /// rest.
    pub fn object_count(&self) -> u32 {
        self.header[hdr::OBJECT_COUNT]
    }

    /// Lights in use, the ambient one included (word 3).
    pub fn light_count(&self) -> u32 {
        self.header[hdr::LIGHT_COUNT]
    }

    /// Writes the header's frame settings, checking the ranges [`RenderRegs`] documents;
    /// on an error nothing is written.
    pub fn set_render(&mut self, r: &RenderRegs) -> Result<(), SceneError> {
        check_render(r)?;
        let fmt = self.value_format();
        let mut h = self.header;
        h[hdr::WIDTH] = r.width;
        h[hdr::HEIGHT] = r.height;
        h[hdr::DEPTH] = r.depth;
        put_r(fmt, &mut h, hdr::BIAS, "bias", r.bias)?;
        h[hdr::MAX_DISTANCE] = f32_from_f64("max_distance", r.max_distance)?;
        put_rv(fmt, &mut h, hdr::BACKGROUND, "background", r.background)?;
        h[hdr::SPP] = r.spp;
        h[hdr::FLAGS] = r.flags;
        h[hdr::SEED] = r.seed;
        self.header = h;
        Ok(())
    }

    /// Reads the frame settings back as the words hold them, in range or not (an image
    /// built by [`Self::set_render`] always is); [`Self::render_checked`] refuses the
    /// words a writer could not have written.
    pub fn render(&self) -> RenderRegs {
        let fmt = self.value_format();
        let h = &self.header;
        RenderRegs {
            width: h[hdr::WIDTH],
            height: h[hdr::HEIGHT],
            depth: h[hdr::DEPTH],
            bias: get_r(fmt, h, hdr::BIAS),
            max_distance: f64::from(f32::from_bits(h[hdr::MAX_DISTANCE])),
            background: get_rv(fmt, h, hdr::BACKGROUND),
            spp: h[hdr::SPP],
            flags: h[hdr::FLAGS],
            seed: h[hdr::SEED],
        }
    }

    /// Reads the frame settings back, refusing a size, depth or sample count outside
    /// the ranges [`RenderRegs`] documents: what a reader of an image it did not build
    /// (the device) runs, so that a corrupt word is an error rather than a frame of
    /// 2³² columns.
    pub fn render_checked(&self) -> Result<RenderRegs, SceneError> {
        let r = self.render();
        check_render(&r)?;
        Ok(r)
    }

    /// Writes the camera block; a value the value format cannot hold is an error naming
    /// the field, and then nothing is written.
    pub fn set_camera(&mut self, c: &CameraRegs) -> Result<(), SceneError> {
        let fmt = self.value_format();
        let mut w = [0; cam::WORDS];
        put_rv(fmt, &mut w, cam::POSITION, "camera.position", c.position)?;
        put_rv(fmt, &mut w, cam::LOOK_AT, "camera.look_at", c.look_at)?;
        put_rv(fmt, &mut w, cam::UP, "camera.up", c.up)?;
        put_r(fmt, &mut w, cam::FOV_Y, "camera.fov_y", c.fov_y)?;
        put_rv(fmt, &mut w, cam::U, "camera.u", c.u)?;
        put_rv(fmt, &mut w, cam::V, "camera.v", c.v)?;
        put_rv(fmt, &mut w, cam::W, "camera.w", c.w)?;
        put_r(
            fmt,
            &mut w,
            cam::NEAR_PLANE,
            "camera.near_plane",
            c.near_plane,
        )?;
        w[cam::PITCH] = c.pitch as u32;
        w[cam::PITCH + 1] = (c.pitch >> 32) as u32;
        self.camera = w;
        Ok(())
    }

    /// Reads the camera block back. Cannot fail: every word is some value in either
    /// format.
    pub fn camera(&self) -> CameraRegs {
        let fmt = self.value_format();
        let w = &self.camera;
        CameraRegs {
            position: get_rv(fmt, w, cam::POSITION),
            look_at: get_rv(fmt, w, cam::LOOK_AT),
            up: get_rv(fmt, w, cam::UP),
            fov_y: get_r(fmt, w, cam::FOV_Y),
            u: get_rv(fmt, w, cam::U),
            v: get_rv(fmt, w, cam::V),
            w: get_rv(fmt, w, cam::W),
            near_plane: get_r(fmt, w, cam::NEAR_PLANE),
            pitch: u64::from(w[cam::PITCH]) | u64::from(w[cam::PITCH + 1]) << 32,
        }
    }

    fn light_index(i: usize) -> Result<(), SceneError> {
        if i < LIGHTS {
            Ok(())
        } else {
            Err(SceneError::Index {
                what: "light",
                index: i,
                capacity: LIGHTS,
            })
        }
    }

    fn object_index(i: usize) -> Result<(), SceneError> {
        if i < OBJ {
            Ok(())
        } else {
            Err(SceneError::Index {
                what: "object",
                index: i,
                capacity: OBJ,
            })
        }
    }

    /// Writes light `i`. Light 0 must be ambient and only light 0 may be.
    pub fn set_light(&mut self, i: usize, l: &LightRegs) -> Result<(), SceneError> {
        Self::light_index(i)?;
        let at = At::Light(i);
        if (i == 0) != (l.kind == LightKind::Ambient) {
            return Err(SceneError::Code {
                at,
                field: "kind",
                value: l.kind.code(),
            });
        }
        let fmt = self.value_format();
        let enc = || -> Result<[u32; light::WORDS], SceneError> {
            let mut w = [0; light::WORDS];
            w[light::KIND] = l.kind.code();
            put_rv(fmt, &mut w, light::POSITION, "position", l.position)?;
            put_rv(fmt, &mut w, light::COLOR, "color", l.color)?;
            put_rv(fmt, &mut w, light::DIRECTION, "direction", l.direction)?;
            put_r(fmt, &mut w, light::COS_OUTER, "cos_outer", l.cos_outer)?;
            put_r(fmt, &mut w, light::COS_INNER, "cos_inner", l.cos_inner)?;
            Ok(w)
        };
        self.lights[i] = enc().map_err(|e| e.at(at))?;
        Ok(())
    }

    /// Reads light `i`; fails for an index beyond LIGHTS or a kind word that names no
    /// [`LightKind`].
    pub fn light(&self, i: usize) -> Result<LightRegs, SceneError> {
        Self::light_index(i)?;
        let fmt = self.value_format();
        let w = &self.lights[i];
        Ok(LightRegs {
            kind: code("kind", w[light::KIND], LightKind::from_code)
                .map_err(|e| e.at(At::Light(i)))?,
            position: get_rv(fmt, w, light::POSITION),
            color: get_rv(fmt, w, light::COLOR),
            direction: get_rv(fmt, w, light::DIRECTION),
            cos_outer: get_r(fmt, w, light::COS_OUTER),
            cos_inner: get_r(fmt, w, light::COS_INNER),
        })
    }

    /// Writes object `i`, checking every field first: on an error the block is unchanged
    /// and the error names the object and the field.
    pub fn set_object(&mut self, i: usize, o: &ObjectRegs) -> Result<(), SceneError> {
        Self::object_index(i)?;
        self.objects[i] = encode_object(o, self.value_format()).map_err(|e| e.at(At::Object(i)))?;
        Ok(())
    }

    /// Reads object `i`; fails for an index beyond OBJ, a code word that names nothing or
    /// an integer out of range (an image made by [`SceneRegs::from_words`] is checked only
    /// here).
    pub fn object(&self, i: usize) -> Result<ObjectRegs, SceneError> {
        Self::object_index(i)?;
        decode_object(&self.objects[i], self.value_format()).map_err(|e| e.at(At::Object(i)))
    }
}

fn encode_object(o: &ObjectRegs, fmt: ValueFormat) -> Result<[u32; obj::WORDS], SceneError> {
    let m = &o.material;
    let t = &m.texture;
    int("material.specular.exponent", u64::from(m.exponent), 0, 1023)?;
    int("material.texture.width_log2", u64::from(t.width_log2), 0, 8)?;
    int(
        "material.texture.height_log2",
        u64::from(t.height_log2),
        0,
        8,
    )?;
    int("material.texture.base", u64::from(t.base), 0, (1 << 16) - 1)?;
    let mut w = [0; obj::WORDS];
    w[obj::SHAPE] = o.shape.code();
    put_rv(fmt, &mut w, obj::TRANSLATE, "translate", o.translate)?;
    put_rv(fmt, &mut w, obj::SCALE, "scale", o.scale)?;
    put_rv(fmt, &mut w, obj::ROTATE, "rotate", o.rotate)?;
    put_r(
        fmt,
        &mut w,
        obj::AMBIENT_K,
        "material.ambient.k",
        m.ambient.k,
    )?;
    put_rv(
        fmt,
        &mut w,
        obj::AMBIENT_COLOR,
        "material.ambient.color",
        m.ambient.color,
    )?;
    put_r(
        fmt,
        &mut w,
        obj::DIFFUSE_K,
        "material.diffuse.k",
        m.diffuse.k,
    )?;
    put_rv(
        fmt,
        &mut w,
        obj::DIFFUSE_COLOR,
        "material.diffuse.color",
        m.diffuse.color,
    )?;
    w[obj::DIFFUSE_MODEL] = m.diffuse_model.code();
    put_r(
        fmt,
        &mut w,
        obj::SIGMA2,
        "material.diffuse.sigma2",
        m.sigma2,
    )?;
    put_r(
        fmt,
        &mut w,
        obj::SPECULAR_K,
        "material.specular.k",
        m.specular.k,
    )?;
    put_rv(
        fmt,
        &mut w,
        obj::SPECULAR_COLOR,
        "material.specular.color",
        m.specular.color,
    )?;
    w[obj::SPECULAR_MODEL] = m.specular_model.code();
    w[obj::EXPONENT] = m.exponent;
    w[obj::REFLECTION_MODE] = m.reflection.code();
    put_r(fmt, &mut w, obj::ETA, "material.reflection.eta", m.eta)?;
    put_r(fmt, &mut w, obj::KAPPA, "material.reflection.k", m.kappa)?;
    put_r(
        fmt,
        &mut w,
        obj::SPEC_ETA,
        "material.specular.eta",
        m.spec_eta,
    )?;
    put_r(
        fmt,
        &mut w,
        obj::SPEC_KAPPA,
        "material.specular.extinction",
        m.spec_kappa,
    )?;
    put_r(
        fmt,
        &mut w,
        obj::REFLECTANCE,
        "material.reflection.r",
        m.reflectance,
    )?;
    for (r, row) in o.minv.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            w[obj::MINV + 3 * r + c] = fmt.encode_saturating(*v);
        }
    }
    w[obj::TEX_KIND] = t.kind.code();
    w[obj::TEX_MAPPING] = t.mapping.code();
    put_rv(
        fmt,
        &mut w,
        obj::TEX_SCALE,
        "material.texture.scale",
        t.scale,
    )?;
    put_rv(
        fmt,
        &mut w,
        obj::TEX_OFFSET,
        "material.texture.offset",
        t.offset,
    )?;
    put_rv(
        fmt,
        &mut w,
        obj::TEX_COLOR2,
        "material.texture.color2",
        t.color2,
    )?;
    w[obj::TEX_FILTER] = t.filter.code();
    w[obj::TEX_SEED] = t.seed;
    w[obj::TEX_BASE] = t.base;
    w[obj::TEX_SIZE] = u32::from(t.width_log2) | u32::from(t.height_log2) << 8;
    Ok(w)
}

fn decode_object(w: &[u32; obj::WORDS], fmt: ValueFormat) -> Result<ObjectRegs, SceneError> {
    let size = w[obj::TEX_SIZE];
    int("material.texture.size", u64::from(size), 0, 0x0808)?;
    int("material.texture.width_log2", u64::from(size & 0xff), 0, 8)?;
    int(
        "material.specular.exponent",
        u64::from(w[obj::EXPONENT]),
        0,
        1023,
    )?;
    int(
        "material.texture.base",
        u64::from(w[obj::TEX_BASE]),
        0,
        (1 << 16) - 1,
    )?;
    Ok(ObjectRegs {
        shape: code("shape", w[obj::SHAPE], Shape::from_code)?,
        translate: get_rv(fmt, w, obj::TRANSLATE),
        scale: get_rv(fmt, w, obj::SCALE),
        rotate: get_rv(fmt, w, obj::ROTATE),
        minv: core::array::from_fn(|r| get_rv(fmt, w, obj::MINV + 3 * r)),
        material: MaterialRegs {
            ambient: TermRegs {
                k: get_r(fmt, w, obj::AMBIENT_K),
                color: get_rv(fmt, w, obj::AMBIENT_COLOR),
            },
            diffuse: TermRegs {
                k: get_r(fmt, w, obj::DIFFUSE_K),
                color: get_rv(fmt, w, obj::DIFFUSE_COLOR),
            },
            diffuse_model: code(
                "material.diffuse.model",
                w[obj::DIFFUSE_MODEL],
                DiffuseModel::from_code,
            )?,
            sigma2: get_r(fmt, w, obj::SIGMA2),
            specular: TermRegs {
                k: get_r(fmt, w, obj::SPECULAR_K),
                color: get_rv(fmt, w, obj::SPECULAR_COLOR),
            },
            specular_model: code(
                "material.specular.model",
                w[obj::SPECULAR_MODEL],
                SpecularModel::from_code,
            )?,
            exponent: w[obj::EXPONENT],
            reflection: code(
                "material.reflection.mode",
                w[obj::REFLECTION_MODE],
                ReflectionMode::from_code,
            )?,
            eta: get_r(fmt, w, obj::ETA),
            kappa: get_r(fmt, w, obj::KAPPA),
            spec_eta: get_r(fmt, w, obj::SPEC_ETA),
            spec_kappa: get_r(fmt, w, obj::SPEC_KAPPA),
            reflectance: get_r(fmt, w, obj::REFLECTANCE),
            texture: TextureRegs {
                kind: code(
                    "material.texture.kind",
                    w[obj::TEX_KIND],
                    TextureKind::from_code,
                )?,
                mapping: code(
                    "material.texture.mapping",
                    w[obj::TEX_MAPPING],
                    Mapping::from_code,
                )?,
                scale: get_rv(fmt, w, obj::TEX_SCALE),
                offset: get_rv(fmt, w, obj::TEX_OFFSET),
                color2: get_rv(fmt, w, obj::TEX_COLOR2),
                filter: code(
                    "material.texture.filter",
                    w[obj::TEX_FILTER],
                    TexFilter::from_code,
                )?,
                seed: w[obj::TEX_SEED],
                base: w[obj::TEX_BASE],
                width_log2: (size & 0xff) as u8,
                height_log2: (size >> 8) as u8,
            },
        },
    })
}

/// Unchanged words a run may bridge rather than start a new [`RegWrite`]. A new run costs
/// a new message: about 10 bytes of link framing plus ~4 bytes of header, while a bridged
/// word costs at most 5 bytes (a worst-case postcard varint), so bridging pays up to two
/// words.
pub const DEFAULT_MERGE_GAP: usize = 2;

/// The register writes that turn `old` into `new`: runs of at most [`REG_WRITE_WORDS`]
/// words, covering every changed word and unchanged ones only inside gaps of at most
/// [`DEFAULT_MERGE_GAP`] words.
pub fn diff<'a, const OBJ: usize, const LIGHTS: usize>(
    old: &'a SceneRegs<OBJ, LIGHTS>,
    new: &'a SceneRegs<OBJ, LIGHTS>,
) -> Diff<'a, OBJ, LIGHTS> {
    diff_with_gap(old, new, DEFAULT_MERGE_GAP)
}

/// [`diff`] with an explicit merge gap (0 = never write an unchanged word).
pub fn diff_with_gap<'a, const OBJ: usize, const LIGHTS: usize>(
    old: &'a SceneRegs<OBJ, LIGHTS>,
    new: &'a SceneRegs<OBJ, LIGHTS>,
    max_gap: usize,
) -> Diff<'a, OBJ, LIGHTS> {
    Diff {
        old,
        new,
        pos: 0,
        max_gap,
    }
}

/// Iterator returned by [`diff`].
#[derive(Debug)]
pub struct Diff<'a, const OBJ: usize, const LIGHTS: usize> {
    old: &'a SceneRegs<OBJ, LIGHTS>,
    new: &'a SceneRegs<OBJ, LIGHTS>,
    pos: usize,
    max_gap: usize,
}

impl<const OBJ: usize, const LIGHTS: usize> Iterator for Diff<'_, OBJ, LIGHTS> {
    type Item = RegWrite;

    fn next(&mut self) -> Option<RegWrite> {
        let n = SceneRegs::<OBJ, LIGHTS>::WORDS;
        let changed = |i: usize| self.old.word_ref(i) != self.new.word_ref(i);
        let start = (self.pos..n).find(|&i| changed(i))?;
        let mut last = start;
        let mut j = start + 1;
        while j < n && j - start < REG_WRITE_WORDS && j - last <= self.max_gap + 1 {
            if changed(j) {
                last = j;
            }
            j += 1;
        }
        self.pos = last + 1;
        let mut words = Vec::new();
        for i in start..=last {
            // At most REG_WRITE_WORDS words by construction of the loop above.
            let _ = words.push(self.new.word_ref(i).unwrap_or(0));
        }
        Some(RegWrite {
            offset: start as u16,
            words,
        })
    }
}

impl<const OBJ: usize, const LIGHTS: usize> SceneRegs<OBJ, LIGHTS> {
    fn word_ref(&self, offset: usize) -> Option<u32> {
        if offset < hdr::WORDS {
            return self.header.get(offset).copied();
        }
        let o = offset - hdr::WORDS;
        if o < cam::WORDS {
            return self.camera.get(o).copied();
        }
        let o = o - cam::WORDS;
        if o < LIGHTS * light::WORDS {
            return self.lights[o / light::WORDS].get(o % light::WORDS).copied();
        }
        let o = o - LIGHTS * light::WORDS;
        self.objects
            .get(o / obj::WORDS)
            .and_then(|b| b.get(o % obj::WORDS))
            .copied()
    }
}

/// Applies one register write, as the device does; a write past the map is an error and
/// changes nothing.
pub fn apply<const OBJ: usize, const LIGHTS: usize>(
    regs: &mut SceneRegs<OBJ, LIGHTS>,
    w: &RegWrite,
) -> Result<(), SceneError> {
    regs.write(usize::from(w.offset), &w.words)
}

/// Writes `hw/rt-core/rtl/rt_map.vh`, the ray-casting core's view of this image: the
/// shape codes its intersection unit decodes (and, as the core grows, the word offsets it
/// reads), so the Verilog never types a code the Rust defines. The test
/// `rt_map_header_matches_the_rust_map` fails while the committed header differs
/// (`FPGFX_BLESS=1` rewrites it).
pub fn write_verilog_header(out: &mut impl core::fmt::Write) -> core::fmt::Result {
    use core::fmt::Write as _;
    writeln!(
        out,
        "// rt_map.vh -- the ray-casting core's codes from the scene register image."
    )?;
    writeln!(out, "//")?;
    writeln!(
        out,
        "// GENERATED from protocol::scene (protocol/src/scene.rs); do not edit."
    )?;
    writeln!(
        out,
        "// `FPGFX_BLESS=1 cargo test -p protocol --test integration rt_map` rewrites it."
    )?;
    writeln!(out, "`ifndef RT_MAP_VH")?;
    writeln!(out, "`define RT_MAP_VH")?;
    writeln!(out, "// bits of a shape code")?;
    writeln!(out, "`define RT_SHAPE_BITS {SHAPE_BITS}")?;
    for s in Shape::ALL {
        let mut name = heapless::String::<16>::new();
        // 16 bytes hold the longest shape name
        let _ = write!(name, "{s:?}");
        writeln!(out, "// shape code: {s:?}")?;
        write!(out, "`define RT_SHAPE_")?;
        for c in name.chars() {
            out.write_char(c.to_ascii_uppercase())?;
        }
        writeln!(out, " {SHAPE_BITS}'d{}", s.code())?;
    }
    type Default = SceneRegs;
    let offsets: [(&str, usize, &str); 40] = [
        (
            "SCENE_WORDS",
            Default::WORDS,
            "words in the image (default capacities)",
        ),
        (
            "OBJ_CAPACITY",
            Default::OBJ_CAPACITY,
            "object blocks in the image",
        ),
        (
            "LIGHT_CAPACITY",
            Default::LIGHT_CAPACITY,
            "light blocks in the image",
        ),
        (
            "HDR_VERSION",
            hdr::VERSION,
            "header: version | OBJ << 16 | LIGHTS << 24",
        ),
        (
            "HDR_OBJECT_COUNT",
            hdr::OBJECT_COUNT,
            "header: object count",
        ),
        (
            "HDR_LIGHT_COUNT",
            hdr::LIGHT_COUNT,
            "header: light count (ambient included)",
        ),
        ("HDR_WIDTH", hdr::WIDTH, "header: frame width"),
        ("HDR_HEIGHT", hdr::HEIGHT, "header: frame height"),
        ("HDR_DEPTH", hdr::DEPTH, "header: ray depth"),
        ("HDR_BIAS", hdr::BIAS, "header: CORE_BIAS (real)"),
        (
            "HDR_MAX_DISTANCE",
            hdr::MAX_DISTANCE,
            "header: MAX_DISTANCE (binary32 bits)",
        ),
        (
            "HDR_BACKGROUND",
            hdr::BACKGROUND,
            "header: background colour (real x 3)",
        ),
        ("HDR_SPP", hdr::SPP, "header: samples per pixel"),
        ("HDR_FLAGS", hdr::FLAGS, "header: flags"),
        (
            "HDR_VALUE_FORMAT",
            hdr::VALUE_FORMAT,
            "header: value format code",
        ),
        (
            "CAM_POSITION",
            cam::OFFSET + cam::POSITION,
            "camera position (real x 3)",
        ),
        (
            "CAM_U",
            cam::OFFSET + cam::U,
            "camera basis u (real x 3, derived)",
        ),
        (
            "CAM_V",
            cam::OFFSET + cam::V,
            "camera basis v (real x 3, derived)",
        ),
        (
            "CAM_W",
            cam::OFFSET + cam::W,
            "camera basis w (real x 3, derived)",
        ),
        (
            "CAM_PITCH",
            cam::OFFSET + cam::PITCH,
            "pixel pitch, 2^-40 units, low then high word (derived)",
        ),
        (
            "OBJECTS_OFFSET",
            Default::OBJECTS_OFFSET,
            "first word of object 0",
        ),
        ("OBJ_WORDS", obj::WORDS, "words per object block"),
        ("OBJ_SHAPE", obj::SHAPE, "object block: shape code"),
        (
            "OBJ_TRANSLATE",
            obj::TRANSLATE,
            "object block: translate (real x 3)",
        ),
        (
            "OBJ_MINV",
            obj::MINV,
            "object block: inverse transform, row-major (real x 9, derived)",
        ),
        (
            "OBJ_AMBIENT_K",
            obj::AMBIENT_K,
            "object block: ambient k (real)",
        ),
        (
            "OBJ_AMBIENT_COLOR",
            obj::AMBIENT_COLOR,
            "object block: ambient colour (real x 3)",
        ),
        (
            "OBJ_DIFFUSE_K",
            obj::DIFFUSE_K,
            "object block: diffuse k (real)",
        ),
        (
            "OBJ_DIFFUSE_COLOR",
            obj::DIFFUSE_COLOR,
            "object block: diffuse colour (real x 3)",
        ),
        (
            "OBJ_DIFFUSE_MODEL",
            obj::DIFFUSE_MODEL,
            "object block: diffuse model code",
        ),
        (
            "OBJ_SPECULAR_K",
            obj::SPECULAR_K,
            "object block: specular k (real)",
        ),
        (
            "OBJ_SPECULAR_COLOR",
            obj::SPECULAR_COLOR,
            "object block: specular colour (real x 3)",
        ),
        (
            "OBJ_SPECULAR_MODEL",
            obj::SPECULAR_MODEL,
            "object block: specular model code",
        ),
        (
            "OBJ_EXPONENT",
            obj::EXPONENT,
            "object block: specular exponent (u32)",
        ),
        (
            "OBJ_REFLECTION_MODE",
            obj::REFLECTION_MODE,
            "object block: reflection mode code",
        ),
        (
            "OBJ_TEX_KIND",
            obj::TEX_KIND,
            "object block: texture kind code",
        ),
        (
            "LIGHTS_OFFSET",
            light::OFFSET,
            "first word of light 0 (the ambient light)",
        ),
        ("LIGHT_WORDS", light::WORDS, "words per light block"),
        ("LIGHT_KIND", light::KIND, "light block: kind code"),
        (
            "LIGHT_POSITION",
            light::POSITION,
            "light block: position (real x 3)",
        ),
    ];
    writeln!(out, "// word offsets in the scene image")?;
    for (name, value, what) in offsets {
        writeln!(out, "// {what}")?;
        writeln!(out, "`define RT_{name} {value}")?;
    }
    writeln!(out, "// light block: colour (real x 3)")?;
    writeln!(out, "`define RT_LIGHT_COLOR {}", light::COLOR)?;
    writeln!(out, "// light kind code of a point light")?;
    writeln!(out, "`define RT_LIGHT_POINT {}", LightKind::Point.code())?;
    writeln!(out, "// header flags: shadows")?;
    writeln!(out, "`define RT_FLAG_SHADOWS {FLAG_SHADOWS}")?;
    writeln!(
        out,
        "// model codes the core builds: Lambert, Blinn-Phong, no reflection, no texture"
    )?;
    writeln!(
        out,
        "`define RT_DIFFUSE_LAMBERT {}",
        DiffuseModel::Lambert.code()
    )?;
    writeln!(
        out,
        "`define RT_SPECULAR_BLINN_PHONG {}",
        SpecularModel::BlinnPhong.code()
    )?;
    writeln!(
        out,
        "`define RT_REFLECTION_NONE {}",
        ReflectionMode::None.code()
    )?;
    writeln!(out, "`define RT_TEXTURE_NONE {}", TextureKind::None.code())?;
    writeln!(out, "// value format codes")?;
    writeln!(
        out,
        "`define RT_FORMAT_Q16_16 {}",
        ValueFormat::Q16_16.code()
    )?;
    writeln!(
        out,
        "`define RT_FORMAT_BINARY32 {}",
        ValueFormat::Binary32.code()
    )?;
    writeln!(out, "// register-map version")?;
    writeln!(out, "`define RT_MAP_VERSION {VERSION}")?;
    writeln!(out, "// fraction bits of the pixel pitch")?;
    writeln!(out, "`define RT_PITCH_FRAC_BITS {PITCH_FRAC_BITS}")?;
    writeln!(out, "`endif")
}

/// Fraction bits of [`CameraRegs::pitch`]: the pitch is an integer number of 2⁻⁴⁰ (why
/// 40: `sim_target::rt::derive::PITCH_FRAC_BITS`, which is this constant).
pub const PITCH_FRAC_BITS: u32 = 40;

/// Bits the core's shape codes take (every [`Shape::ALL`] code fits).
pub const SHAPE_BITS: u32 = 3;

const _: () = {
    let mut i = 0;
    while i < Shape::ALL.len() {
        assert!(Shape::ALL[i].code() < 1 << SHAPE_BITS);
        i += 1;
    }
};
