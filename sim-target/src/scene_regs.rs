//! From the ray tracer's register image ([`protocol::scene::SceneRegs`]) to the scene it
//! renders ([`crate::rt::Scene`]): what the device reads. The other direction, a scene
//! written into registers, is the host's, in the `jobs` crate (`jobs::scene::to_regs`).
//!
//! The register image is what a board receives, so rendering through it (rather than
//! from the parsed file) is what makes built-in mode a faithful model: every value is
//! rounded to the image's value format (Q16.16, or binary32 for a float datapath; see
//! [`protocol::scene`]) exactly as the MicroBlaze would write it. Materials are per object
//! in the registers (ViRAY has no material table), so shared materials are expanded.

use protocol::scene::{self as regs, SceneError, SceneRegs, TermRegs};

use crate::rt::{
    derive, Camera, DiffuseModel, Light, Material, Object, Reflection, Scene, Specular,
    SpecularModel, Spot, Term, Texture, TextureKind,
};

/// The default register image: the seed's OBJ_NUM = 8 and LIGHTS_NUM = 2.
pub type Regs = SceneRegs<8, 2>;

/// Why a scene and a register image could not be converted.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneRegsError {
    /// A value the register map cannot hold (range, count, code).
    #[error("scene registers: {0}")]
    Map(#[from] SceneError),
    /// The camera's up vector is parallel to its view direction (no basis).
    #[error("camera: `up` is parallel to the view direction, so the camera has no basis")]
    Camera,
    /// An uploaded-image texture: the model only generates procedural ones.
    #[error("object {0}: image textures are not supported by this model")]
    ImageTexture(usize),
    /// The target's ray tracer does not build what the scene asks for
    /// (`protocol::frame::RtBuild`); the message names the scene field.
    #[error("the target does not build this scene: {0}")]
    NotBuilt(String),
    /// A derived word (camera basis, pixel pitch, an object's inverse transform) is not
    /// what the image's other words imply: a core reading it would trace other rays than
    /// the model.
    #[error(
        "{field} (word {offset}) holds {held:#x}, but the image's other words imply \
         {derived:#x}: the derived words are stale or were computed another way"
    )]
    Derived {
        /// The field, with its block (`camera.u[0]`, `object 2 minv[1][0]`).
        field: String,
        /// Word offset in the image.
        offset: usize,
        /// What the image holds.
        held: u64,
        /// What [`crate::rt::derive`] gives for the image's other words.
        derived: u64,
    },
}

/// Checks that an image's derived words (`protocol::scene`, "Derived words") are the
/// ones its other words imply, as `jobs::scene::to_regs` writes them; the first that is
/// not is named. The golden model derives these numbers itself and ignores the words, so
/// this is what a target whose core reads them (the RTL ray-casting core) runs before a
/// frame: without it a stale word would make the core and the model trace different rays
/// and disagree silently.
pub fn check_derived(r: &Regs) -> Result<(), SceneRegsError> {
    let held = from_regs(r)?;
    let fmt = r.value_format();
    let word = |offset: usize| u64::from(r.word(offset).unwrap_or(0));
    let check = |field: &dyn Fn() -> String, offset: usize, derived: u64| {
        let held = word(offset);
        if held == derived {
            Ok(())
        } else {
            Err(SceneRegsError::Derived {
                field: field(),
                offset,
                held,
                derived,
            })
        }
    };
    let basis = derive::basis(&held.camera);
    for (name, at, v) in [
        ("u", regs::cam::U, basis[0]),
        ("v", regs::cam::V, basis[1]),
        ("w", regs::cam::W, basis[2]),
    ] {
        for (k, x) in v.iter().enumerate() {
            let offset = regs::cam::OFFSET + at + k;
            check(
                &|| format!("camera.{name}[{k}]"),
                offset,
                u64::from(fmt.encode_saturating(*x)),
            )?;
        }
    }
    let pitch = derive::pitch(held.camera.fov_y, held.height, held.spp);
    let at = regs::cam::OFFSET + regs::cam::PITCH;
    check(
        &|| "camera.pitch (low word)".into(),
        at,
        pitch & 0xffff_ffff,
    )?;
    check(&|| "camera.pitch (high word)".into(), at + 1, pitch >> 32)?;
    for (i, o) in held.objects.iter().enumerate() {
        let m = derive::inverse_linear(o.rotate, o.scale);
        for (rr, row) in m.iter().enumerate() {
            for (c, x) in row.iter().enumerate() {
                let offset = Regs::object_offset(i) + regs::obj::MINV + 3 * rr + c;
                check(
                    &|| format!("object {i} minv[{rr}][{c}]"),
                    offset,
                    u64::from(fmt.encode_saturating(*x)),
                )?;
            }
        }
    }
    Ok(())
}

fn some_term(t: TermRegs) -> Option<Term> {
    (t.k != 0.0).then_some(Term {
        k: t.k,
        color: t.color,
    })
}

/// Reads the scene a register image describes, in whichever value format the image says
/// (what the device renders).
pub fn from_regs(r: &Regs) -> Result<Scene, SceneRegsError> {
    let render = r.render_checked()?;
    let cam = r.camera();
    let ambient = r.light(0)?.color;
    let mut lights = Vec::new();
    for i in 1..r.light_count() as usize {
        let l = r.light(i)?;
        lights.push(Light {
            position: l.position,
            color: l.color,
            spot: (l.kind == regs::LightKind::Spot).then_some(Spot {
                direction: l.direction,
                cos_outer: l.cos_outer,
                cos_inner: l.cos_inner,
            }),
        });
    }
    let mut materials = Vec::new();
    let mut objects = Vec::new();
    for i in 0..r.object_count() as usize {
        let o = r.object(i)?;
        let m = o.material;
        let texture = match m.texture.kind {
            regs::TextureKind::None => None,
            regs::TextureKind::Image => return Err(SceneRegsError::ImageTexture(i)),
            kind => Some(Texture {
                kind: match kind {
                    regs::TextureKind::Xor => TextureKind::Xor,
                    regs::TextureKind::Checkerboard => TextureKind::Checkerboard {
                        cell: m.texture.seed.max(1),
                    },
                    regs::TextureKind::RgbDots => TextureKind::RgbDots,
                    regs::TextureKind::Marble => TextureKind::Marble {
                        seed: m.texture.seed,
                    },
                    _ => TextureKind::Wood {
                        seed: m.texture.seed,
                    },
                },
                mapping: m.texture.mapping,
                scale: m.texture.scale,
                offset: m.texture.offset,
                color2: m.texture.color2,
                filter: m.texture.filter,
            }),
        };
        materials.push(Material {
            name: format!("object{i}"),
            ambient: some_term(m.ambient),
            diffuse: Term {
                k: m.diffuse.k,
                color: m.diffuse.color,
            },
            diffuse_model: match m.diffuse_model {
                regs::DiffuseModel::Lambert => DiffuseModel::Lambert,
                regs::DiffuseModel::OrenNayar => DiffuseModel::OrenNayar { sigma2: m.sigma2 },
            },
            specular: some_term(m.specular).map(|t| Specular {
                k: t.k,
                color: t.color,
                model: match m.specular_model {
                    regs::SpecularModel::BlinnPhong => SpecularModel::BlinnPhong,
                    regs::SpecularModel::TorranceSparrow => SpecularModel::TorranceSparrow {
                        eta: m.spec_eta,
                        k: m.spec_kappa,
                    },
                },
                exponent: m.exponent,
            }),
            reflection: match m.reflection {
                regs::ReflectionMode::None => Reflection::None,
                regs::ReflectionMode::Constant => Reflection::Constant(m.reflectance),
                regs::ReflectionMode::Fresnel => Reflection::Fresnel {
                    eta: m.eta,
                    k: m.kappa,
                },
                regs::ReflectionMode::Glass => Reflection::Glass { eta: m.eta },
            },
            texture,
        });
        objects.push(Object {
            shape: o.shape,
            translate: o.translate,
            scale: o.scale,
            rotate: o.rotate,
            material: i,
        });
    }
    Ok(Scene {
        width: render.width,
        height: render.height,
        depth: render.depth,
        bias: render.bias,
        max_distance: render.max_distance,
        background: render.background,
        spp: render.spp,
        shadows: render.flags & regs::FLAG_SHADOWS != 0,
        camera: Camera {
            position: cam.position,
            look_at: cam.look_at,
            up: cam.up,
            fov_y: cam.fov_y,
        },
        ambient,
        lights,
        materials,
        objects,
    })
}
