//! The plan: what a scene needs, decided once before rendering (shapes present, lights,
//! textures, specular terms, the depth actually traced), the kernel feature set it
//! compiles to, and the checks a scene must pass before anything is computed.

use super::{f, texture, Reflection, RtError, Scene, Shape};

/// What a scene needs, decided once before rendering.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Plan {
    /// Distinct shapes present.
    pub shapes: Vec<Shape>,
    /// Point/spot lights (so shadow rays exist).
    pub lights: usize,
    /// Any spot light.
    pub spot: bool,
    /// Number of textures in memory.
    pub textures: usize,
    /// Texture side in texels.
    pub texture_side: usize,
    /// Any material with a specular term.
    pub specular: bool,
    /// Depth actually traced (1 if no material reflects).
    pub depth: u32,
    /// Shadow rays are traced (lights present and the scene's SHADOW_ENABLE).
    pub shadows: bool,
    /// Every object is a sphere.
    pub spheres_only: bool,
}

impl Plan {
    /// The kernel feature set this plan compiles to.
    pub fn features(&self) -> Features {
        Features {
            shadows: self.shadows,
            textures: self.textures > 0,
            specular: self.specular,
            reflect: self.depth > 1,
            spheres_only: self.spheres_only,
        }
    }
}

/// Refuses a scene the kernel cannot render as given: an empty frame, depth 0, a
/// material index out of range, a non-positive scale, a degenerate camera.
pub(super) fn validate(scene: &Scene) -> Result<(), RtError> {
    let bad = |s: String| Err(RtError::InvalidScene(s));
    if scene.width == 0 || scene.height == 0 {
        return bad(format!("frame size {}x{}", scene.width, scene.height));
    }
    // The framebuffer and its planes are held whole; a side past the protocol's is a
    // frame no target reads back, and its size in bytes would overflow on the way.
    let max = protocol::MAX_FRAME_SIDE;
    if scene.width > max || scene.height > max {
        return bad(format!(
            "frame size {}x{} is larger than {max} per side",
            scene.width, scene.height
        ));
    }
    if scene.depth == 0 {
        return bad("depth must be at least 1".into());
    }
    for (i, o) in scene.objects.iter().enumerate() {
        if o.material >= scene.materials.len() {
            return bad(format!(
                "object {i}: material index {} out of range",
                o.material
            ));
        }
        if o.scale
            .iter()
            .any(|s| s.is_nan() || *s <= 0.0 || !s.is_finite())
        {
            return bad(format!("object {i}: non-positive scale"));
        }
    }
    let c = &scene.camera;
    let w = f::normalize(f::sub(c.position, c.look_at));
    let u = f::cross(c.up, w);
    if u.iter().all(|v| v.abs() < 1e-12) {
        return bad("camera up is parallel to the view direction".into());
    }
    if !(c.fov_y > 0.0 && c.fov_y < 180.0) {
        return bad(format!("fov_y {} not in (0, 180)", c.fov_y));
    }
    Ok(())
}

/// Compile the plan of a scene.
pub fn plan(scene: &Scene) -> Plan {
    let mut shapes: Vec<Shape> = Vec::new();
    for o in &scene.objects {
        if !shapes.contains(&o.shape) {
            shapes.push(o.shape);
        }
    }
    let textures = scene
        .materials
        .iter()
        .filter(|m| m.texture.is_some())
        .count();
    let reflects = scene
        .materials
        .iter()
        .any(|m| !matches!(m.reflection, Reflection::None));
    Plan {
        shapes,
        lights: scene.lights.len(),
        spot: scene.lights.iter().any(|l| l.spot.is_some()),
        textures,
        texture_side: texture::side_for(textures),
        specular: scene.materials.iter().any(|m| m.specular.is_some()),
        depth: if reflects { scene.depth } else { 1 },
        shadows: scene.shadows && !scene.lights.is_empty(),
        spheres_only: !scene.objects.is_empty()
            && scene.objects.iter().all(|o| o.shape == Shape::Sphere),
    }
}

/// The feature set a kernel is compiled for, decided by the plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Features {
    /// Shadow rays (point/spot lights present and SHADOW_ENABLE).
    pub shadows: bool,
    /// Texture lookups: some material has a texture.
    pub textures: bool,
    /// Specular BRDF terms: some material has one.
    pub specular: bool,
    /// Secondary (reflected/refracted) rays: traced depth > 1.
    pub reflect: bool,
    /// Only spheres: no shape dispatch, sphere normal = object-space hit point, and the
    /// primary rays' c = |o′|² − 1 precomputed per object.
    pub spheres_only: bool,
}

impl Features {
    /// Everything on: the general kernel's set.
    pub const ALL: Features = Features {
        shadows: true,
        textures: true,
        specular: true,
        reflect: true,
        spheres_only: false,
    };
}

impl std::fmt::Display for Features {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let b = |v: bool| if v { '1' } else { '0' };
        write!(
            f,
            "sh{}-tx{}-sp{}-rf{}-so{}",
            b(self.shadows),
            b(self.textures),
            b(self.specular),
            b(self.reflect),
            b(self.spheres_only)
        )
    }
}
