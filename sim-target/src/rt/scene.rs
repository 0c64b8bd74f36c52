//! The scene as the ray-trace block is given it: plain f64 numbers, format-independent.
//! The kernel converts it once into the chosen format (see `kernel::Prepared`).

// The enumerations the register map already defines are the same here: one definition,
// so a shape or mapping added to the hardware interface is added to the model at once.
pub use protocol::scene::{Mapping, Shape, TexFilter as Filter};

/// Camera as in the scene file: w = normalize(position − look_at), u = normalize(up × w).
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub position: [f64; 3],
    /// Point looked at.
    pub look_at: [f64; 3],
    /// Up hint (must not be parallel to the view direction).
    pub up: [f64; 3],
    /// Vertical field of view in degrees.
    pub fov_y: f64,
}

/// Spot cone of a point light (docs/requirements.md §4.4: seed eq. 3.2.10 with l_dir in place of the seed's n).
#[derive(Debug, Clone, PartialEq)]
pub struct Spot {
    /// Axis of the cone (need not be unit length).
    pub direction: [f64; 3],
    /// cos(α/2): outside this the light is off.
    pub cos_outer: f64,
    /// cos(β/2) ≥ cos_outer: inside this the light is full.
    pub cos_inner: f64,
}

/// A point light, optionally a spot light.
#[derive(Debug, Clone, PartialEq)]
pub struct Light {
    /// Position.
    pub position: [f64; 3],
    /// Radiant intensity per channel (falls off with 1/d²).
    pub color: [f64; 3],
    /// Spot cone, if any.
    pub spot: Option<Spot>,
}

/// k and colour of a term.
#[derive(Debug, Clone, PartialEq)]
pub struct Term {
    /// Weight.
    pub k: f64,
    /// Colour.
    pub color: [f64; 3],
}

/// Diffuse BRDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DiffuseModel {
    /// 1/π.
    Lambert,
    /// Oren–Nayar with roughness variance σ².
    OrenNayar {
        /// σ².
        sigma2: f64,
    },
}

/// Specular BRDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpecularModel {
    /// Normalised Blinn–Phong.
    BlinnPhong,
    /// Torrance–Sparrow with Fresnel of complex index η − ik.
    TorranceSparrow {
        /// Refractive index.
        eta: f64,
        /// Extinction coefficient.
        k: f64,
    },
}

/// Specular term.
#[derive(Debug, Clone, PartialEq)]
pub struct Specular {
    /// Weight.
    pub k: f64,
    /// Colour.
    pub color: [f64; 3],
    /// BRDF.
    pub model: SpecularModel,
    /// Phong exponent (≤ 1023, power by repeated squaring).
    pub exponent: u32,
}

/// How much of the mirror-reflected ray's radiance a surface passes on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reflection {
    /// No reflected ray.
    None,
    /// Constant reflectance r.
    Constant(f64),
    /// Unpolarised Fresnel reflectance of η − ik; k > 0 is a conductor (θt = 0).
    Fresnel {
        /// Refractive index.
        eta: f64,
        /// Extinction coefficient.
        k: f64,
    },
    /// (beyond) A transmissive dielectric: Fresnel reflectance r plus a refracted ray of
    /// weight 1 − r (Snell's law, total internal reflection when leaving a denser medium).
    Glass {
        /// Refractive index (the other side is taken to be vacuum).
        eta: f64,
    },
}

/// Procedural texture generator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureKind {
    /// grey = (x ⊕ y) & 255.
    Xor,
    /// Grey squares of `cell` texels.
    Checkerboard {
        /// Square size in texels.
        cell: u32,
    },
    /// Consecutive texels red, green, blue.
    RgbDots,
    /// ½(1 + sin(f·x + t·turbulence)).
    Marble {
        /// Noise seed.
        seed: u32,
    },
    /// fract(rings·r + t·turbulence).
    Wood {
        /// Noise seed.
        seed: u32,
    },
}

/// A texture applied to a material's ambient and diffuse colours.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// Generator.
    pub kind: TextureKind,
    /// Mapping.
    pub mapping: Mapping,
    /// (u, v) scale (repeat count).
    pub scale: [f64; 2],
    /// (u, v) offset.
    pub offset: [f64; 2],
    /// Second colour of grey textures (the first is the diffuse colour).
    pub color2: [f64; 3],
    /// Filter.
    pub filter: Filter,
}

/// A material. Only `diffuse` is mandatory; absent terms are skipped by the plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Name from the scene file.
    pub name: String,
    /// Ambient term.
    pub ambient: Option<Term>,
    /// Diffuse term.
    pub diffuse: Term,
    /// Diffuse model.
    pub diffuse_model: DiffuseModel,
    /// Specular term.
    pub specular: Option<Specular>,
    /// Reflection.
    pub reflection: Reflection,
    /// Texture.
    pub texture: Option<Texture>,
}

/// An object: canonical shape, then scale, rotation (degrees, X then Y then Z), translation.
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    /// Shape.
    pub shape: Shape,
    /// Translation.
    pub translate: [f64; 3],
    /// Per-axis scale (> 0).
    pub scale: [f64; 3],
    /// Rotation in degrees about x, y, z (beyond the seed).
    pub rotate: [f64; 3],
    /// Index into [`Scene::materials`].
    pub material: usize,
}

/// A whole scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Frame width.
    pub width: u32,
    /// Frame height.
    pub height: u32,
    /// RAYTRACING_DEPTH (1 = primary rays only).
    pub depth: u32,
    /// CORE_BIAS.
    pub bias: f64,
    /// MAX_DISTANCE.
    pub max_distance: f64,
    /// Colour of rays that hit nothing.
    pub background: [f64; 3],
    /// Samples per pixel.
    pub spp: u32,
    /// SHADOW_ENABLE: point/spot lights are tested for occluders (false: every light
    /// reaches every surface facing it, and the plan drops shadow rays from the kernel).
    pub shadows: bool,
    /// Camera.
    pub camera: Camera,
    /// Ambient light L_a (light 0).
    pub ambient: [f64; 3],
    /// Point/spot lights.
    pub lights: Vec<Light>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Objects.
    pub objects: Vec<Object>,
}
