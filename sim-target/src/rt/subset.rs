//! Feature subsets of a scene, so that the planned kernels can be measured on scenes that
//! use only part of the block (the subset of the plan's target, docs/requirements.md §7.4: spheres only, no shadows, no textures, depth 1).

use super::scene::{Reflection, Scene, Shape};

/// What to strip from a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Subset {
    /// The scene unchanged.
    Full,
    /// Spheres only, shadows off, textures removed, depth 1: the smallest kernel.
    SpheresFlat,
    /// SHADOW_ENABLE off.
    NoShadows,
    /// Every texture removed (materials keep their diffuse colour).
    NoTextures,
    /// RAYTRACING_DEPTH = 1 (primary rays and their shadow rays only).
    Depth1,
}

impl Subset {
    /// Every subset, in the order benches and tables list them.
    pub const ALL: [Subset; 5] = [
        Subset::Full,
        Subset::SpheresFlat,
        Subset::NoShadows,
        Subset::NoTextures,
        Subset::Depth1,
    ];

    /// Short label for tables and bench ids.
    pub fn label(self) -> &'static str {
        match self {
            Subset::Full => "full",
            Subset::SpheresFlat => "spheres-noshadow-notex-depth1",
            Subset::NoShadows => "no-shadows",
            Subset::NoTextures => "no-textures",
            Subset::Depth1 => "depth1",
        }
    }

    /// The scene restricted to this subset.
    pub fn apply(self, scene: &Scene) -> Scene {
        let mut s = scene.clone();
        match self {
            Subset::Full => {}
            Subset::SpheresFlat => {
                s.objects.retain(|o| o.shape == Shape::Sphere);
                s.shadows = false;
                strip_textures(&mut s);
                s.depth = 1;
                for m in &mut s.materials {
                    m.reflection = Reflection::None;
                }
            }
            Subset::NoShadows => s.shadows = false,
            Subset::NoTextures => strip_textures(&mut s),
            Subset::Depth1 => s.depth = 1,
        }
        s
    }
}

fn strip_textures(s: &mut Scene) {
    for m in &mut s.materials {
        m.texture = None;
    }
}
