//! The prepared scene: a scene compiled for one number format (object transforms, lights,
//! materials and texture memory converted once per frame, each object's intersector and
//! its primary rays' hoisted constants), and the camera the frame is seen through.

use super::derive;
use super::pretest;
use super::shade::{DiffuseParams, SpecParams};
use super::shapes::{self, IntersectFn};
use super::texture::{self, TexSlot};
use super::vec::M3;
use super::{
    cull, f, Camera, DiffuseModel, Dispatch, Kernel, Math, Plan, Reflection, Scene, Shape,
    SpecularModel, V3,
};
use crate::num::Scalar;

/// An object as the kernel tests it: its transform in format `S` and its intersector.
pub(super) struct PObj<S> {
    /// M⁻¹'s diagonal when the object is not rotated: 3 products instead of 9 + 6 sums.
    pub(super) diag: Option<V3<S>>,
    pub(super) shape: Shape,
    pub(super) intersect: IntersectFn<S>,
    pub(super) minv: M3<S>,
    pub(super) nmat: M3<S>,
    pub(super) translate: V3<S>,
    /// The camera position in object space: every primary ray starts there, so its
    /// transform is done once per object instead of once per pixel (same operations, same
    /// bits).
    pub(super) eye: V3<S>,
    /// |eye′|² − 1: a sphere's c for every primary ray (the spheres-only kernel's hoist).
    pub(super) eye_c: S,
    pub(super) material: usize,
    /// Its material's shading when that is Lambert's term alone ([`Plain`]): what f32's
    /// packet lanes shade without reading the material. None until
    /// [`Prepared::find_plain`].
    pub(super) plain: Option<Plain<S>>,
}

/// A material whose shading at one level is an ambient term plus, per light, Lambert's
/// term and maybe Blinn–Phong's (no texture, Oren–Nayar, Torrance–Sparrow or reflection
/// that would be traced), with its constants formed as `Prepared::trace` forms them.
#[derive(Clone, Copy)]
pub(super) struct Plain<S> {
    /// k_a·(c_a ⊙ the scene's ambient), or zero.
    pub(super) ambient: V3<S>,
    /// (c_d·k_d)·(1/π): the BRDF times the diffuse colour.
    pub(super) brdf: V3<S>,
    /// Blinn–Phong's k_s·c_s and constants, if the material has that highlight.
    pub(super) spec: Option<(V3<S>, SpecParams<S>)>,
}

impl<S: Scalar> PMat<S> {
    /// The material as [`Plain`] constants for a kernel of `depth` levels, if it is one.
    fn plain(&self, depth: u32, ambient: V3<S>) -> Option<Plain<S>> {
        // one level: whatever the material reflects is never traced
        let reflects = depth > 1 && !matches!(self.refl, PRefl::None);
        let torrance_sparrow = matches!(self.spec, Some((_, true, _)));
        if self.oren_nayar || self.tex.is_some() || torrance_sparrow || reflects {
            return None;
        }
        // `trace`'s n, wi, wo do not enter Lambert's term
        let z = V3::zero();
        Some(Plain {
            ambient: match &self.ambient {
                Some((ka, a)) => a.hadamard(ambient).scale(*ka),
                None => V3::zero(),
            },
            brdf: self
                .cd
                .scale(self.kd)
                .scale(super::shade::lambert(z, z, z, &self.dparams)),
            spec: self.spec.map(|(kc, _, p)| (kc, p)),
        })
    }
}

/// A point or spot light in format `S` (a spot's cone: direction, cos of the outer angle,
/// 1/(cos inner − cos outer)).
pub(super) struct PLight<S> {
    pub(super) pos: V3<S>,
    pub(super) color: V3<S>,
    pub(super) spot: Option<(V3<S>, S, S)>,
}

/// What a material reflects, with its constants in format `S`.
pub(super) enum PRefl<S> {
    None,
    Constant(S),
    Fresnel(S, S),
    Glass(S),
}

/// A material with its constants in format `S`.
pub(super) struct PMat<S> {
    pub(super) ambient: Option<(S, V3<S>)>,
    pub(super) kd: S,
    pub(super) cd: V3<S>,
    /// Oren–Nayar (else Lambert): a `match` at the call, so that the term is inlined
    /// into the light loop (a function pointer cost a call with three vectors by value
    /// and the spills around it, twice per light).
    pub(super) oren_nayar: bool,
    pub(super) dparams: DiffuseParams<S>,
    /// k_s·c_s, Torrance–Sparrow (else Blinn–Phong), constants.
    pub(super) spec: Option<(V3<S>, bool, SpecParams<S>)>,
    pub(super) refl: PRefl<S>,
    pub(super) tex: Option<(TexSlot<S>, V3<S>)>,
}

impl<S: Scalar> Prepared<S> {
    /// Marks the objects whose material is [`Plain`], with its constants. Only for a
    /// kernel that shades in lanes: the constants are products in the format, which a
    /// counting wrapper would count and a fixed format could clip.
    pub(super) fn find_plain(&mut self) {
        for ob in &mut self.objs {
            ob.plain = self
                .mats
                .get(ob.material)
                .and_then(|m| m.plain(self.depth, self.ambient));
        }
    }
}

/// A scene compiled for format `S`: what the kernel reads, converted once per frame.
pub(super) struct Prepared<S> {
    pub(super) objs: Vec<PObj<S>>,
    /// The objects' culling spheres, for the secondary rays' pretest.
    pub(super) spheres: pretest::Spheres,
    /// World-space camera position (primary rays' origin).
    pub(super) eye: V3<S>,
    pub(super) lights: Vec<PLight<S>>,
    pub(super) mats: Vec<PMat<S>>,
    pub(super) ambient: V3<S>,
    pub(super) background: V3<S>,
    pub(super) texmem: Vec<u32>,
    pub(super) bias: S,
    pub(super) maxd: S,
    pub(super) depth: u32,
    /// The scene's SHADOW_ENABLE, tested at run time by the general kernel only.
    pub(super) shadows: bool,
    pub(super) m: Math,
    pub(super) by_match: bool,
}

/// Compiles `scene` for format `S`: transforms, lights, materials and texture memory
/// converted once, the objects' culling spheres for the pretest.
pub(super) fn prepare<S: Scalar>(
    scene: &Scene,
    plan: &Plan,
    m: Math,
    dispatch: Dispatch,
    kernel: Kernel,
    bounds: &[Option<cull::Bound>],
    cull: bool,
) -> Prepared<S> {
    let eye = V3::<S>::from_f64(scene.camera.position);
    let objs: Vec<PObj<S>> = scene
        .objects
        .iter()
        .map(|o| {
            let minv = derive::inverse_linear(o.rotate, o.scale);
            let rotated = o.rotate.iter().any(|a| *a != 0.0);
            let mut ob = PObj {
                diag: (!rotated).then(|| V3::from_f64([minv[0][0], minv[1][1], minv[2][2]])),
                shape: o.shape,
                intersect: shapes::intersect_fn::<S>(o.shape),
                minv: M3::from_f64(minv),
                nmat: M3::from_f64(f::transpose(minv)),
                translate: V3::from_f64(o.translate),
                eye: V3::zero(),
                eye_c: S::zero(),
                material: o.material,
                plain: None,
            };
            ob.eye = ob.to_object(eye, V3::zero()).0;
            ob.eye_c = ob.eye.dot(ob.eye) - S::one();
            ob
        })
        .collect();
    let lights = scene
        .lights
        .iter()
        .map(|l| PLight {
            pos: V3::from_f64(l.position),
            color: V3::from_f64(l.color),
            spot: l.spot.as_ref().map(|s| {
                let w = s.cos_inner - s.cos_outer;
                let inv = if w > 1e-9 { 1.0 / w } else { 1e6 };
                (
                    V3::from_f64(f::normalize(s.direction)),
                    S::from_f64(s.cos_outer),
                    S::from_f64(inv),
                )
            }),
        })
        .collect();
    let side = plan.texture_side;
    let texmem = texture::memory(scene);
    let mut next_slot = 0usize;
    let mats: Vec<PMat<S>> = scene
        .materials
        .iter()
        .map(|mat| {
            let (oren_nayar, sigma2) = match mat.diffuse_model {
                DiffuseModel::Lambert => (false, 0.0),
                DiffuseModel::OrenNayar { sigma2 } => (true, sigma2),
            };
            let spec = mat.specular.as_ref().map(|s| {
                let kc = V3::from_f64(s.color).scale(S::from_f64(s.k));
                match s.model {
                    SpecularModel::BlinnPhong => {
                        (kc, false, SpecParams::new(s.exponent, 1.0, 0.0, m.sqrt))
                    }
                    SpecularModel::TorranceSparrow { eta, k } => {
                        (kc, true, SpecParams::new(s.exponent, eta, k, m.sqrt))
                    }
                }
            });
            let refl = match mat.reflection {
                Reflection::None => PRefl::None,
                Reflection::Constant(r) => PRefl::Constant(S::from_f64(r)),
                Reflection::Fresnel { eta, k } => PRefl::Fresnel(S::from_f64(eta), S::from_f64(k)),
                Reflection::Glass { eta } => PRefl::Glass(S::from_f64(eta)),
            };
            let tex = mat.texture.as_ref().map(|t| {
                let base = texture::slot_base(next_slot, side);
                next_slot += 1;
                (
                    TexSlot::new(
                        base,
                        side,
                        t.mapping,
                        t.filter,
                        (S::from_f64(t.scale[0]), S::from_f64(t.scale[1])),
                        (S::from_f64(t.offset[0]), S::from_f64(t.offset[1])),
                        texture::is_grey(t.kind),
                    ),
                    V3::from_f64(t.color2),
                )
            });
            PMat {
                ambient: mat
                    .ambient
                    .as_ref()
                    .map(|a| (S::from_f64(a.k), V3::from_f64(a.color))),
                kd: S::from_f64(mat.diffuse.k),
                cd: V3::from_f64(mat.diffuse.color),
                oren_nayar,
                dparams: DiffuseParams::oren_nayar(sigma2, m.sqrt),
                spec,
                refl,
                tex,
            }
        })
        .collect();
    // the general kernel does not use the plan's depth: a non-reflecting hit ends the
    // ray by its own test, with the same result
    let depth = match kernel {
        Kernel::Planned | Kernel::Scalar => plan.depth,
        Kernel::General => scene.depth,
    };
    let ambient = V3::from_f64(scene.ambient);
    // the flat objects' side test (`pretest::Flat`): only where culling is on (the planned
    // kernel with `RenderOptions::cull`; a count of every operation turns it off), for
    // formats that declare their rounding (all do; the instrumented wrappers declare their
    // format's), and only with a positive CORE_BIAS
    let bias = S::from_f64(scene.bias);
    let side_test = cull && S::rounding().is_some() && bias > S::zero();
    let flats: Vec<pretest::Flat> = objs
        .iter()
        .map(|ob| {
            let flat = matches!(ob.shape, Shape::Plane | Shape::Disk | Shape::Square);
            // unrotated: the object transforms rays by M⁻¹'s diagonal
            (side_test && flat && ob.diag.is_some()).then(|| ob.translate.y.to_f64() as f32)
        })
        .collect();
    Prepared {
        objs,
        spheres: pretest::Spheres::new(bounds, &flats),
        eye,
        lights,
        mats,
        ambient,
        background: V3::from_f64(scene.background),
        texmem,
        bias: S::from_f64(scene.bias),
        // MAX_DISTANCE is "infinity": in a format whose range ends below it (f16: 65504 <
        // 1e6) it would round to ∞ and let a root at t = ∞ count as a hit; the format's
        // largest finite value is the same "infinity" without that.
        maxd: S::from_f64(scene.max_distance.min(S::max_value().to_f64())),
        depth,
        shadows: scene.shadows,
        m,
        by_match: dispatch == Dispatch::Match,
    }
}

impl<S: Scalar> PObj<S> {
    /// The ray in object space.
    #[inline(always)]
    pub(super) fn to_object(&self, o: V3<S>, d: V3<S>) -> (V3<S>, V3<S>) {
        match self.diag {
            Some(g) => ((o - self.translate).hadamard(g), d.hadamard(g)),
            None => (self.minv.mul_v(o - self.translate), self.minv.mul_v(d)),
        }
    }
}

/// The camera's frame in f64: eye, the u, v, w axes, tan(fov/2), the aspect ratio and the
/// pixel pitch of the sample grid ([`derive::pitch`]).
pub(super) struct Cam {
    pub(super) eye: [f64; 3],
    pub(super) u: [f64; 3],
    pub(super) v: [f64; 3],
    pub(super) w: [f64; 3],
    pub(super) s: f64,
    pub(super) a: f64,
    pub(super) pitch: u64,
}

/// The camera of a `width`×`height` frame at `spp` samples per pixel.
pub(super) fn camera(c: &Camera, width: u32, height: u32, spp: u32) -> Cam {
    let [u, v, w] = derive::basis(c);
    Cam {
        eye: c.position,
        u,
        v,
        w,
        s: (c.fov_y.to_radians() / 2.0).tan(),
        a: width as f64 / height as f64,
        pitch: derive::pitch(c.fov_y, height, spp),
    }
}
