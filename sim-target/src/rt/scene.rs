//! The scene as the ray-trace block is given it: plain f64 numbers, format-independent.
//! The kernel converts it once into the chosen format (see `kernel::Prepared`).

// The enumerations the register map already defines are the same here: one definition,
// so a shape or mapping added to the hardware interface is added to the model at once.
pub use protocol::scene::{Mapping, Shape, TexFilter as Filter};

/// Camera as in the scene file: w = normalize(position − look_at), u = normalize(up × w).
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    /// Where the eye is, in world units: the origin of every primary ray.
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
    /// Where the light is, in world units (distance to it sets the 1/d² fall-off).
    pub position: [f64; 3],
    /// Radiant intensity per channel (falls off with 1/d²).
    pub color: [f64; 3],
    /// Spot cone, if any.
    pub spot: Option<Spot>,
}

/// k and colour of a term.
#[derive(Debug, Clone, PartialEq)]
pub struct Term {
    /// Weight the term's contribution is multiplied by (the seed's k_a, k_d).
    pub k: f64,
    /// Linear RGB the term reflects, per channel.
    pub color: [f64; 3],
}

/// Which diffuse BRDF a material uses: Lambert, or Oren–Nayar for rough surfaces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DiffuseModel {
    /// 1/π.
    Lambert,
    /// Oren–Nayar with roughness variance σ².
    OrenNayar {
        /// Roughness variance σ² (0 is Lambert's result at Oren–Nayar's cost).
        sigma2: f64,
    },
}

/// Which specular BRDF a specular term uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpecularModel {
    /// Normalised Blinn–Phong.
    BlinnPhong,
    /// Torrance–Sparrow with Fresnel of complex index η − ik.
    TorranceSparrow {
        /// Real part η of the complex refractive index in the Fresnel factor.
        eta: f64,
        /// Extinction coefficient k, the imaginary part (0 for a dielectric).
        k: f64,
    },
}

/// A material's optional specular term: a highlight per point/spot light.
#[derive(Debug, Clone, PartialEq)]
pub struct Specular {
    /// Weight the highlight is multiplied by (the seed's k_s).
    pub k: f64,
    /// Linear RGB of the highlight, per channel.
    pub color: [f64; 3],
    /// Which BRDF shapes the highlight.
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
        /// Real part η of the complex refractive index.
        eta: f64,
        /// Extinction coefficient k, the imaginary part (> 0: a conductor).
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
        /// Seed of the turbulence's value noise: one marble pattern per seed.
        seed: u32,
    },
    /// fract(rings·r + t·turbulence).
    Wood {
        /// Seed of the turbulence's value noise: one grain pattern per seed.
        seed: u32,
    },
}

/// A texture applied to a material's ambient and diffuse colours.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// Which procedural pattern fills the texture memory.
    pub kind: TextureKind,
    /// How a hit point becomes (u, v): planar, cylindrical or spherical.
    pub mapping: Mapping,
    /// (u, v) scale (repeat count).
    pub scale: [f64; 2],
    /// (u, v) offset.
    pub offset: [f64; 2],
    /// Second colour of grey textures (the first is the diffuse colour).
    pub color2: [f64; 3],
    /// Nearest or bilinear lookup between texels.
    pub filter: Filter,
}

/// A material. Only `diffuse` is mandatory; absent terms are skipped by the plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Name from the scene file.
    pub name: String,
    /// Response to the scene's ambient light; none skips the term.
    pub ambient: Option<Term>,
    /// Response to each point/spot light that reaches the surface.
    pub diffuse: Term,
    /// BRDF of the diffuse term.
    pub diffuse_model: DiffuseModel,
    /// Highlight per light; none skips the term (and the plan drops it from the kernel).
    pub specular: Option<Specular>,
    /// What a reflected (or refracted) ray adds; [`Reflection::None`] traces none.
    pub reflection: Reflection,
    /// Pattern applied to the ambient and diffuse colours; none samples nothing.
    pub texture: Option<Texture>,
}

/// An object: canonical shape, then scale, rotation (degrees, X then Y then Z), translation.
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    /// The canonical shape, before scale, rotation and translation.
    pub shape: Shape,
    /// Offset in world units, applied last.
    pub translate: [f64; 3],
    /// Per-axis scale (> 0).
    pub scale: [f64; 3],
    /// Rotation in degrees about x, y, z (beyond the seed).
    pub rotate: [f64; 3],
    /// Index into [`Scene::materials`].
    pub material: usize,
}

/// Everything one frame is rendered from: what a scene file parses to and what the
/// register image ([`crate::scene_regs`]) holds.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// RAYTRACING_DEPTH (1 = primary rays only).
    pub depth: u32,
    /// CORE_BIAS: the smallest hit distance t that counts, and how far secondary rays
    /// start off their surface (so a surface does not shadow itself).
    pub bias: f64,
    /// MAX_DISTANCE: the largest hit distance t that counts, the model's "infinity".
    pub max_distance: f64,
    /// Colour of rays that hit nothing.
    pub background: [f64; 3],
    /// Samples per pixel.
    pub spp: u32,
    /// SHADOW_ENABLE: point/spot lights are tested for occluders (false: every light
    /// reaches every surface facing it, and the plan drops shadow rays from the kernel).
    pub shadows: bool,
    /// Where primary rays start and which way they look.
    pub camera: Camera,
    /// Ambient light L_a (light 0).
    pub ambient: [f64; 3],
    /// Point and spot lights (the ambient light is [`Scene::ambient`]).
    pub lights: Vec<Light>,
    /// Materials, shared by index ([`Object::material`]).
    pub materials: Vec<Material>,
    /// Objects in scene-file order (every ray tests all of them unless culled).
    pub objects: Vec<Object>,
}
