//! A scene written into the ray tracer's register image ([`protocol::scene::SceneRegs`]):
//! what the host sends. The device reads it back with `sim_target::scene_regs::from_regs`.
//!
//! The register image is what a board receives, so rendering through it (rather than
//! from the parsed file) is what makes built-in mode a faithful model: every value is
//! rounded to the image's value format (Q16.16, or binary32 for a float datapath; see
//! [`protocol::scene`]) exactly as the MicroBlaze would write it. Materials are per object
//! in the registers (ViRAY has no material table), so shared materials are expanded.

use protocol::scene::{
    self as regs, CameraRegs, LightRegs, MaterialRegs, ObjectRegs, RenderRegs, SceneError,
    TermRegs, TextureRegs, ValueFormat,
};
use sim_target::rt::{derive, f};
use sim_target::rt::{DiffuseModel, Material, Reflection, Scene, SpecularModel, Term, TextureKind};
use sim_target::scene_regs::{from_regs, Regs, SceneRegsError};

/// `a`'s direction, or `None` when it is too short to have one (a camera without a basis).
fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    (f::length(a) > 1e-12).then(|| f::normalize(a))
}

fn term(t: &Option<Term>) -> TermRegs {
    t.as_ref().map_or(TermRegs::default(), |t| TermRegs {
        k: t.k,
        color: t.color,
    })
}

fn material(m: &Material) -> Result<MaterialRegs, SceneRegsError> {
    let mut out = MaterialRegs {
        ambient: term(&m.ambient),
        diffuse: TermRegs {
            k: m.diffuse.k,
            color: m.diffuse.color,
        },
        ..Default::default()
    };
    if let DiffuseModel::OrenNayar { sigma2 } = m.diffuse_model {
        out.diffuse_model = regs::DiffuseModel::OrenNayar;
        out.sigma2 = sigma2;
    }
    if let Some(s) = &m.specular {
        out.specular = TermRegs {
            k: s.k,
            color: s.color,
        };
        out.exponent = s.exponent;
        if let SpecularModel::TorranceSparrow { eta, k } = s.model {
            out.specular_model = regs::SpecularModel::TorranceSparrow;
            out.spec_eta = eta;
            out.spec_kappa = k;
        }
    }
    match m.reflection {
        Reflection::None => {}
        Reflection::Constant(r) => {
            out.reflection = regs::ReflectionMode::Constant;
            out.reflectance = r;
        }
        Reflection::Fresnel { eta, k } => {
            out.reflection = regs::ReflectionMode::Fresnel;
            out.eta = eta;
            out.kappa = k;
        }
        Reflection::Glass { eta } => {
            out.reflection = regs::ReflectionMode::Glass;
            out.eta = eta;
        }
    }
    if let Some(t) = &m.texture {
        let (kind, seed) = match t.kind {
            TextureKind::Xor => (regs::TextureKind::Xor, 0),
            TextureKind::Checkerboard { cell } => (regs::TextureKind::Checkerboard, cell),
            TextureKind::RgbDots => (regs::TextureKind::RgbDots, 0),
            TextureKind::Marble { seed } => (regs::TextureKind::Marble, seed),
            TextureKind::Wood { seed } => (regs::TextureKind::Wood, seed),
        };
        out.texture = TextureRegs {
            kind,
            mapping: t.mapping,
            scale: t.scale,
            offset: t.offset,
            color2: t.color2,
            filter: t.filter,
            seed,
            base: 0,
            width_log2: 8,
            height_log2: 8,
        };
    }
    Ok(out)
}

/// Writes a scene into a Q16.16 register image: the seed's, which every target reads (the
/// image a target gets when its caps list no float registers).
pub fn to_regs(scene: &Scene) -> Result<Regs, SceneRegsError> {
    to_regs_as(scene, ValueFormat::Q16_16)
}

/// Writes a scene into a register image whose reals are in `format` (what the host
/// sends: the format [`ValueFormat::for_caps`] picks for the target and the frame's
/// number format).
pub fn to_regs_as(scene: &Scene, format: ValueFormat) -> Result<Regs, SceneRegsError> {
    let mut r = Regs::with_format(format);
    r.set_counts(scene.objects.len(), 1 + scene.lights.len())?;
    r.set_render(&RenderRegs {
        width: scene.width,
        height: scene.height,
        depth: scene.depth,
        bias: scene.bias,
        max_distance: scene.max_distance,
        background: scene.background,
        spp: scene.spp,
        flags: if scene.shadows { regs::FLAG_SHADOWS } else { 0 }
            | regs::FLAG_INTERNAL_SHADING
            | regs::FLAG_TEXTURES,
        seed: 0,
    })?;
    let c = &scene.camera;
    let w = normalize(f::sub(c.position, c.look_at)).ok_or(SceneRegsError::Camera)?;
    normalize(f::cross(c.up, w)).ok_or(SceneRegsError::Camera)?;
    r.set_camera(&CameraRegs {
        position: c.position,
        look_at: c.look_at,
        up: c.up,
        fov_y: c.fov_y,
        near_plane: 1.0,
        // derived below, from the image's own values
        ..Default::default()
    })?;
    r.set_light(
        0,
        &LightRegs {
            kind: regs::LightKind::Ambient,
            color: scene.ambient,
            ..Default::default()
        },
    )?;
    for (i, l) in scene.lights.iter().enumerate() {
        let mut light = LightRegs {
            kind: regs::LightKind::Point,
            position: l.position,
            color: l.color,
            ..Default::default()
        };
        if let Some(s) = &l.spot {
            light.kind = regs::LightKind::Spot;
            light.direction = s.direction;
            light.cos_outer = s.cos_outer;
            light.cos_inner = s.cos_inner;
        }
        r.set_light(i + 1, &light)?;
    }
    for (i, o) in scene.objects.iter().enumerate() {
        let m = scene.materials.get(o.material).ok_or(SceneError::Bounds {
            offset: Regs::object_offset(i),
            len: 0,
            size: Regs::WORDS,
        })?;
        r.set_object(
            i,
            &ObjectRegs {
                shape: o.shape,
                translate: o.translate,
                scale: o.scale,
                rotate: o.rotate,
                minv: [[0.0; 3]; 3],
                material: material(m)?,
            },
        )?;
    }
    derive_words(&mut r)?;
    Ok(r)
}

/// Writes the image's derived words (camera basis, pixel pitch, inverse transforms; see
/// `protocol::scene`, "Derived words") from the values the image holds, with the model's
/// own functions: derived from the scene file's unrounded numbers they could differ from
/// the model's in the last bit, and a core reading them would then trace other rays.
fn derive_words(r: &mut Regs) -> Result<(), SceneRegsError> {
    let held = from_regs(r)?;
    let mut cam = r.camera();
    [cam.u, cam.v, cam.w] = derive::basis(&held.camera);
    cam.pitch = derive::pitch(held.camera.fov_y, held.height, held.spp);
    r.set_camera(&cam)?;
    for (i, o) in held.objects.iter().enumerate() {
        let mut regs = r.object(i)?;
        regs.minv = derive::inverse_linear(o.rotate, o.scale);
        r.set_object(i, &regs)?;
    }
    Ok(())
}
