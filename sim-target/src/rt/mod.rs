//! The ray-trace block (ViRAY, seed 002) as a golden model generic over number formats.
//!
//! Entry point: [`render`]. The scene ([`Scene`]; a TOML scene file becomes one through
//! the `jobs` crate's `scene::parse`) is compiled once into a [`Plan`] and a
//! format-specific prepared scene. The plan's feature set ([`Features`]: shadows,
//! textures, specular, reflection depth, spheres only) selects one of 32 monomorphised
//! kernels (const generics), so a kernel's hot loop contains no test of a feature the
//! scene does not use; the general kernel (everything compiled in, runtime checks) stays
//! selectable through [`RenderOptions::kernel`] for comparison. Rows are rendered in
//! parallel with rayon. Only the two formats the block is built in, f32 and Q16.16, get
//! all 32 kernels; the other formats and the instrumented wrappers get four, with the
//! same images and operation counts (the `kernel` module says why).
//!
//! The renderer is split by stage into private modules, their public items re-exported
//! here: `plan` (the plan, its feature set and the scene's validation), `prepare` (the
//! scene compiled for one number format, and the camera), `kernel` (the kernels'
//! dispatch, `trace`, `row`, hits and ray counts) and `render` (the entry points, their
//! options, the frame, its stats and errors). The scene model, the vectors, the output
//! packers and the feature subsets are private modules re-exported here too; the
//! secondary rays' pretest is internal.
//!
//! [`core`] is the clock count of a frame on the RTL ray-casting core (hw/rt-core).
//! The frame constants a scene implies ([`derive`]: camera basis, pixel pitch, inverse
//! transforms) are public for the host, which writes them into the register image.
//! The kernel's stages ([`cull`], [`shade`], [`shapes`], [`texture`]) are public as
//! namespaces: each is tested on its own against an f64 reference (the integration
//! tests) and benched (`benches/rt.rs`), and their functions read right only qualified
//! (`shapes::sphere`, `shade::fresnel`, `texture::texel`, `cull::bounds`). So is [`f`],
//! the scene's f64 vector arithmetic (`f::normalize`, `f::rotation`).

pub mod core;
pub mod cull;
pub mod derive;
pub mod shade;
pub mod shapes;
pub mod texture;

mod kernel;
mod output;
mod packet;
mod plan;
mod prepare;
mod pretest;
mod render;
mod scene;
mod subset;
mod vec;

/// PSNR for comparing formats: the comparison crate's, so that `fpgfx compare` and the
/// numerics study measure with one definition.
pub use compare::psnr;
pub use output::{
    pack_kcu116, pack_rgb888, read_pfm, unpack_kcu116, unpack_rgb888, write_pfm, Pfm, PfmError,
};
pub use plan::{plan, Features, Plan};
pub use protocol::frame::Numeric;
pub use render::{
    nominal_rays, primary_candidates, render, render_instrumented, render_with_progress, Dispatch,
    Frame, Kernel, Math, RenderOptions, RtError, Stats, ToneMap, BOARD_CLOCK_HZ,
    BOARD_FRAME_OVERHEAD, BOARD_II, NO_OBJECT, PACKET_FORMATS,
};
pub use scene::{
    Camera, DiffuseModel, Filter, Light, Mapping, Material, Object, Reflection, Scene, Shape,
    Specular, SpecularModel, Spot, Term, Texture, TextureKind,
};
pub use shapes::Quadratic;
pub use subset::Subset;
pub use vec::{f, V3};
