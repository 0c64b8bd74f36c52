//! The kernel: a prepared scene traced row by row. The plan's feature set picks one of 32
//! kernels, monomorphised over const generics (shadows, textures, specular, reflection,
//! spheres only), so that a kernel's hot loop contains no test of a feature the scene does
//! not use; the general kernel (`Features::ALL`: everything compiled in, tested at run
//! time) is one of them. Here are the dispatch, `trace` (nearest hit, shading, shadow rays,
//! reflection and refraction), `row` (the pixel loop, sampling, tone map, quantisation),
//! the shadow rays' occlusion test, and the ray counts.
//!
//! Only the two formats the block is built in, f32 and Q16.16, get all 32 kernels. Each
//! kernel is a whole inlined ray tracer, and 32 of them for each of seven formats (and
//! again for every instrumented wrapper type) was most of a cold build. The other formats
//! and the wrappers get four (`Prepared::compact_kernel`: reflection and spheres-only
//! specialised, which change the operations that run; shadows, textures and specular
//! tested at run time, which changes no arithmetic), so their images and operation counts
//! are the same bits as the full set's.

use super::prepare::{Cam, PObj, PRefl, Prepared};
use super::pretest::{self, RayF32};
use super::{cull, derive, shade, shapes, texture, Features, RenderOptions, ToneMap, V3};
use crate::num::{Scalar, SqrtKind};

/// One monomorphised kernel: a row of the frame (see `Prepared::row`).
///
/// Why a row and not a ray: behind a function pointer, `trace` returned its colour and
/// hit through the stack, and the per-pixel loop's wide reload of fields stored one by
/// one stalled on store forwarding (perf: ≈ 2.5 % of an f32 frame). With the pixel loop
/// inside the kernel, `trace` inlines into it and the result stays in registers.
pub(super) type RowFn<S> = fn(&Prepared<S>, &FrameCtx<S>, u32) -> Rendered<Vec<f32>, Vec<u16>>;

/// A row function monomorphised over the five features: the scalar rows
/// ([`ScalarRows`]) or f32's packet rows (`packet::PacketRows`).
pub(super) trait Rows<S> {
    fn row<const SH: bool, const TX: bool, const SP: bool, const RF: bool, const SO: bool>(
    ) -> RowFn<S>;
}

/// [`Prepared::row`]: one ray at a time.
pub(super) struct ScalarRows;

impl<S: Scalar> Rows<S> for ScalarRows {
    fn row<const SH: bool, const TX: bool, const SP: bool, const RF: bool, const SO: bool>(
    ) -> RowFn<S> {
        Prepared::<S>::row::<SH, TX, SP, RF, SO>
    }
}

/// The row of family `R` for a feature set: one of 32 monomorphisations.
pub(super) fn rows_for<S, R: Rows<S>>(f: Features) -> RowFn<S> {
    fn so<S, R: Rows<S>, const SH: bool, const TX: bool, const SP: bool, const RF: bool>(
        f: Features,
    ) -> RowFn<S> {
        if f.spheres_only {
            R::row::<SH, TX, SP, RF, true>()
        } else {
            R::row::<SH, TX, SP, RF, false>()
        }
    }
    fn rf<S, R: Rows<S>, const SH: bool, const TX: bool, const SP: bool>(f: Features) -> RowFn<S> {
        if f.reflect {
            so::<S, R, SH, TX, SP, true>(f)
        } else {
            so::<S, R, SH, TX, SP, false>(f)
        }
    }
    fn sp<S, R: Rows<S>, const SH: bool, const TX: bool>(f: Features) -> RowFn<S> {
        if f.specular {
            rf::<S, R, SH, TX, true>(f)
        } else {
            rf::<S, R, SH, TX, false>(f)
        }
    }
    fn tx<S, R: Rows<S>, const SH: bool>(f: Features) -> RowFn<S> {
        if f.textures {
            sp::<S, R, SH, true>(f)
        } else {
            sp::<S, R, SH, false>(f)
        }
    }
    if f.shadows {
        tx::<S, R, true>(f)
    } else {
        tx::<S, R, false>(f)
    }
}

/// What every row of a frame shares, computed once per frame.
pub(super) struct FrameCtx<S> {
    /// u·x of every column and sub-pixel column.
    pub(super) cols: Vec<V3<S>>,
    pub(super) cv: V3<S>,
    pub(super) cw: V3<S>,
    pub(super) eye: V3<S>,
    /// The plan's per-tile candidates of primary rays (None: every object, `all`).
    pub(super) tiles: Option<cull::Tiles>,
    pub(super) all: Vec<u16>,
    pub(super) width: u32,
    /// Sub-pixel grid side, samples per pixel and 1/spp.
    pub(super) grid: u32,
    pub(super) spp: u32,
    pub(super) inv_spp: S,
    /// Sample rows in the frame (height · grid).
    pub(super) sample_rows: i64,
    /// The pixel pitch in 2⁻⁴⁰ units ([`derive::pitch`]).
    pub(super) pitch: u64,
    pub(super) aovs: bool,
    pub(super) tone_map: ToneMap,
    pub(super) sqrt: SqrtKind,
}

impl<S: Scalar> FrameCtx<S> {
    /// The frame's shared values for a `width`×`height` frame at `spp` samples seen by
    /// `cam`; `tiles` are the plan's candidates per tile (None: each of the `objects`).
    pub(super) fn new(
        cam: &Cam,
        tiles: Option<cull::Tiles>,
        objects: usize,
        (width, height, spp): (u32, u32, u32),
        opts: &RenderOptions,
    ) -> Self {
        let (cu, cv, cw) = (
            V3::<S>::from_f64(cam.u),
            V3::<S>::from_f64(cam.v),
            V3::<S>::from_f64(cam.w),
        );
        let grid = derive::grid(spp);
        let mut ctx = FrameCtx {
            cols: Vec::new(),
            cv,
            cw,
            eye: V3::<S>::from_f64(cam.eye),
            tiles,
            all: (0..objects.min(u16::MAX as usize) as u16).collect(),
            width,
            grid,
            spp,
            inv_spp: S::from_f64(1.0 / spp as f64),
            sample_rows: i64::from(height) * i64::from(grid),
            pitch: cam.pitch,
            aovs: opts.aovs,
            tone_map: opts.tone_map,
            sqrt: opts.math.sqrt,
        };
        // u·x of every column and sub-pixel column, computed once per frame instead of once
        // per pixel (same operations, same bits); sample column c = i·grid + k lies at
        // x = (2c + 1 − width·grid)·K, an exact f64 that rounds as a core's integer
        // product does (`derive::coordinate`)
        let sample_cols = i64::from(width) * i64::from(grid);
        let pitch = cam.pitch;
        ctx.cols = (0..width)
            .flat_map(|i| {
                (0..grid).map(move |k| {
                    let c = i64::from(i) * i64::from(grid) + i64::from(k);
                    let x = derive::coordinate(2 * c + 1 - sample_cols, pitch);
                    cu.scale(S::from_f64(x))
                })
            })
            .collect();
        ctx
    }
}

/// Rays a row (or a frame) traced, by kind, and the results it clipped.
#[derive(Default, Clone, Copy)]
pub(super) struct Counts {
    pub(super) primary: u64,
    pub(super) shadow: u64,
    pub(super) reflected: u64,
    pub(super) refracted: u64,
    /// Results clipped while rendering the row (set by `render_generic` around the row).
    pub(super) saturations: u64,
    /// Index of the object that blocked the last shadow ray of this row: tried first by
    /// the next one (neighbouring pixels share occluders). `occluded` is an any(), so the
    /// order cannot change the result.
    occluder: usize,
}

/// What a ray from the eye may hit: the plan's candidates (in object order), and the
/// nearest hit when the packet search has found it already (`Some(None)`: nothing).
#[derive(Clone, Copy)]
pub(super) struct Primary<'a, S> {
    pub(super) objs: &'a [u16],
    pub(super) found: Option<Option<(S, usize)>>,
}

/// A ray's first hit: distance, the shading normal and the object's index.
pub(super) struct Hit<S> {
    t: S,
    n: V3<S>,
    obj: usize,
}

impl<S> Hit<S> {
    /// A hit at distance `t` on object `obj`, shading normal `n` (after the side flip).
    pub(super) fn new(t: S, n: V3<S>, obj: usize) -> Self {
        Hit { t, n, obj }
    }
}

impl<S: Scalar> Prepared<S> {
    #[inline(always)]
    fn hit_object(&self, ob: &PObj<S>, o: V3<S>, d: V3<S>, tmax: S) -> Option<S> {
        if self.by_match {
            shapes::intersect(ob.shape, o, d, self.bias, tmax, &self.m)
        } else {
            (ob.intersect)(o, d, self.bias, tmax, &self.m)
        }
    }

    /// One object's intersection: the sphere directly in the spheres-only kernel (`c` is
    /// |o′|² − 1 when the caller has it precomputed), otherwise the shape dispatch.
    #[inline(always)]
    fn hit<const SO: bool>(
        &self,
        ob: &PObj<S>,
        o: V3<S>,
        d: V3<S>,
        c: Option<S>,
        tmax: S,
    ) -> Option<S> {
        if SO {
            let c = match c {
                Some(c) => c,
                None => o.dot(o) - S::one(),
            };
            shapes::sphere_c(o, d, c, self.bias, tmax, &self.m)
        } else {
            self.hit_object(ob, o, d, tmax)
        }
    }

    /// Nearest hit and the ray in that object's space. `eye_objs` is Some for a ray from
    /// the camera position (whose object-space image each object has precomputed) and
    /// lists, in object order, the only objects it can hit (the plan's culling, or all).
    /// Inlined into `trace`: as a call, its result (t, index, the object-space ray) went
    /// back through the stack, and `trace`'s wide reload of fields stored one by one
    /// stalled on store forwarding (perf: 4.6 % of an f32 frame on that one load).
    #[inline(always)]
    fn closest<const SO: bool>(
        &self,
        o: V3<S>,
        d: V3<S>,
        eye_objs: Option<&[u16]>,
    ) -> Option<(S, usize, V3<S>, V3<S>)> {
        let mut best = self.maxd;
        let mut found = None;
        match eye_objs {
            Some(list) => {
                for &k in list {
                    let i = k as usize;
                    let Some(ob) = self.objs.get(i) else { continue };
                    let (lo, ld) = (ob.eye, ob.to_object(V3::zero(), d).1);
                    if let Some(t) = self.hit::<SO>(ob, lo, ld, Some(ob.eye_c), best) {
                        best = t;
                        found = Some((i, lo, ld));
                    }
                }
            }
            None => {
                let rf = RayF32::new(o, d);
                for c in 0..self.spheres.chunks() {
                    let mut may = self.spheres.may_hit(c, &rf);
                    while may != 0 {
                        let i = c * pretest::CHUNK + may.trailing_zeros() as usize;
                        may &= may - 1;
                        let Some(ob) = self.objs.get(i) else { break };
                        let (lo, ld) = ob.to_object(o, d);
                        if let Some(t) = self.hit::<SO>(ob, lo, ld, None, best) {
                            best = t;
                            found = Some((i, lo, ld));
                        }
                    }
                }
            }
        }
        found.map(|(i, lo, ld)| (best, i, lo, ld))
    }

    /// Whether object `i` blocks the shadow ray (inlined: it runs for nearly every
    /// candidate of every shadow ray).
    #[inline(always)]
    fn blocks<const SO: bool>(&self, i: usize, o: V3<S>, d: V3<S>, tmax: S) -> bool {
        self.objs.get(i).is_some_and(|ob| {
            let (lo, ld) = ob.to_object(o, d);
            self.hit::<SO>(ob, lo, ld, None, tmax).is_some()
        })
    }

    /// Whether a shadow ray o + t·d, t ∈ [bias, tmax], hits any object. The pretest's
    /// mask says which objects to test; the object that blocked this row's previous
    /// shadow ray (`cache`) goes first, since neighbouring pixels share occluders (an
    /// any(): the order cannot change the answer).
    /// Inlined for the same reason as `closest` (Q16.16: −1.4 % instructions).
    #[inline(always)]
    fn occluded<const SO: bool>(&self, o: V3<S>, d: V3<S>, tmax: S, cache: &mut usize) -> bool {
        let rf = RayF32::new(o, d);
        let blocks = |i: usize| self.blocks::<SO>(i, o, d, tmax);
        let first = *cache;
        for c in 0..self.spheres.chunks() {
            let mut may = self.spheres.may_hit(c, &rf);
            let base = c * pretest::CHUNK;
            if first >= base && first - base < pretest::CHUNK {
                let bit = 1u64 << (first - base);
                if may & bit != 0 {
                    if blocks(first) {
                        return true;
                    }
                    may &= !bit;
                }
            }
            while may != 0 {
                let i = base + may.trailing_zeros() as usize;
                may &= may - 1;
                if blocks(i) {
                    *cache = i;
                    return true;
                }
            }
        }
        false
    }

    /// The kernel for a feature set, picked once per frame.
    pub(super) fn kernel(f: Features) -> RowFn<S> {
        rows_for::<S, ScalarRows>(f)
    }

    /// The four kernels that the secondary formats and the instrumented number types
    /// render with: shadows, textures and specular compiled in and tested at run time
    /// (those tests do no arithmetic, so the operation stream and every bit equal the
    /// planned kernel's), reflection and spheres-only as the plan says (they change which
    /// operations run).
    ///
    /// Why not [`Self::kernel`]: each of its 32 kernels is a whole inlined ray tracer, and
    /// a wrapper type such as an operation counter instantiated all 32 again in the crate
    /// that names it. Four keep counts exact.
    pub(super) fn compact_kernel(f: Features) -> RowFn<S> {
        match (f.reflect, f.spheres_only) {
            (true, true) => Prepared::<S>::row::<true, true, true, true, true>,
            (true, false) => Prepared::<S>::row::<true, true, true, true, false>,
            (false, true) => Prepared::<S>::row::<true, true, true, false, true>,
            (false, false) => Prepared::<S>::row::<true, true, true, false, false>,
        }
    }

    /// Radiance along a ray (d unit) that starts at recursion level `start` (0 for a
    /// primary ray, which `refracted` = false counts as primary); returns colour and the
    /// first hit. `eye_objs` lists the objects a primary ray from the eye can hit. The const parameters are the kernel's [`Features`] (shadows, textures,
    /// specular, reflection, spheres only): a `false` removes the feature's code, a `true`
    /// keeps it together with the per-material/per-scene runtime test.
    #[allow(clippy::too_many_lines)]
    #[inline(always)]
    pub(super) fn trace<
        const SH: bool,
        const TX: bool,
        const SP: bool,
        const RF: bool,
        const SO: bool,
    >(
        &self,
        o: V3<S>,
        d: V3<S>,
        start: u32,
        refracted: bool,
        primary: Primary<'_, S>,
        cnt: &mut Counts,
    ) -> (V3<S>, Option<Hit<S>>) {
        let zero = S::zero();
        let one = S::one();
        let sq = self.m.sqrt;
        let mut color = V3::zero();
        let mut weight = one;
        let mut first = None;
        let (mut o, mut d) = (o, d);
        for level in start..self.depth {
            if level == start && refracted {
                cnt.refracted += 1;
            } else if level == 0 {
                cnt.primary += 1;
            } else {
                cnt.reflected += 1;
            }
            let from_eye = level == 0 && !refracted && o == self.eye;
            let near = match primary.found {
                // the packet's search found it (only ever for a ray from the eye): the
                // object-space ray as `closest` forms it
                Some(found) if level == start => found.and_then(|(t, i)| {
                    let ob = self.objs.get(i)?;
                    Some((t, i, ob.eye, ob.to_object(V3::zero(), d).1))
                }),
                _ => self.closest::<SO>(o, d, from_eye.then_some(primary.objs)),
            };
            let Some((t, i, lo, ld)) = near else {
                color = color + self.background.scale(weight);
                break;
            };
            let ob = &self.objs[i];
            let lp = lo + ld.scale(t);
            let p = o + d.scale(t);
            let on = if SO { lp } else { shapes::normal(ob.shape, lp) };
            let mut n = ob.nmat.mul_v(on).normalize(sq);
            let inside = n.dot(d) >= zero;
            if inside {
                n = -n; // INTERNAL_SHADING: both sides shade
            }
            if level == 0 {
                first = Some(Hit { t, n, obj: i });
            }
            let mat = &self.mats[ob.material];
            let wo = -d;
            // texture replaces the diffuse (and ambient) colour
            let (cd, ca) = match (TX, &mat.tex) {
                (true, Some((slot, c2))) => {
                    let (u, v) = texture::map_uv(slot.mapping, lp, &self.m);
                    let c = if slot.grey {
                        let mix = texture::sample_grey(&self.texmem, slot, u, v);
                        mat.cd.scale(mix) + c2.scale(one - mix)
                    } else {
                        texture::sample(&self.texmem, slot, u, v)
                    };
                    (c, mat.ambient.as_ref().map(|_| c))
                }
                _ => (mat.cd, mat.ambient.as_ref().map(|a| a.1)),
            };
            let mut lk = V3::zero();
            if let (Some((ka, _)), Some(ca)) = (&mat.ambient, ca) {
                lk = ca.hadamard(self.ambient).scale(*ka);
            }
            let kdcd = cd.scale(mat.kd);
            // Secondary rays start one CORE_BIAS off the surface along the shading normal:
            // the hit point carries the error of t·d (≈ 2⁻¹⁶·t per axis in Q16.16, 1.6·10⁻⁴
            // at t = 10), which tmin = CORE_BIAS alone does not cover (shadow acne).
            let p_off = p + n.scale(self.bias);
            for l in &self.lights {
                let to_l = l.pos - p;
                let dist2 = to_l.dot(to_l);
                if dist2 <= zero {
                    continue;
                }
                let inv_dist = crate::num::rsqrt(dist2, sq);
                let wi = to_l.scale(inv_dist);
                let ndl = n.dot(wi);
                if ndl <= zero {
                    continue;
                }
                let scf = match &l.spot {
                    None => one,
                    Some((dir, cos_o, inv_w)) => shade::spot_factor(*dir, wi, *cos_o, *inv_w),
                };
                if scf <= zero {
                    continue;
                }
                if SH && self.shadows {
                    cnt.shadow += 1;
                    let dist = dist2 * inv_dist;
                    if self.occluded::<SO>(p_off, wi, dist, &mut cnt.occluder) {
                        continue;
                    }
                }
                let g = ndl / dist2 * scf;
                let fd = if mat.oren_nayar {
                    shade::oren_nayar(n, wi, wo, &mat.dparams)
                } else {
                    shade::lambert(n, wi, wo, &mat.dparams)
                };
                let mut brdf = kdcd.scale(fd);
                if SP {
                    if let Some((kscs, ts, sp)) = &mat.spec {
                        let fs = if *ts {
                            shade::torrance_sparrow(n, wi, wo, sp)
                        } else {
                            shade::blinn_phong(n, wi, wo, sp)
                        };
                        brdf = brdf + kscs.scale(fs);
                    }
                }
                lk = lk + brdf.hadamard(l.color).scale(g);
            }
            color = color + lk.scale(weight);
            if !RF {
                break;
            }
            let r = match mat.refl {
                PRefl::None => break,
                PRefl::Constant(r) => r,
                PRefl::Fresnel(eta, k) => shade::fresnel(n.dot(wo), eta, k, sq),
                PRefl::Glass(eta) => {
                    // (beyond) refraction: relative index by the side the ray arrives from
                    let eta_rel = if inside { one / eta } else { eta };
                    let cos_i = n.dot(wo).clamp(zero, one);
                    let r = shade::fresnel(cos_i, eta_rel, zero, sq);
                    if r < one && level + 1 < self.depth {
                        let ratio = one / eta_rel;
                        let sin2_t = ratio * ratio * (one - cos_i * cos_i);
                        let cos_t = crate::num::sqrt(one - sin2_t, sq);
                        let t_dir = (d.scale(ratio) + n.scale(ratio * cos_i - cos_t)).normalize(sq);
                        let lt = self.trace_refracted::<SH, TX, SP, RF, SO>(
                            p - n.scale(self.bias),
                            t_dir,
                            level + 1,
                            cnt,
                        );
                        color = color + lt.scale(weight * (one - r));
                    }
                    r
                }
            };
            if r <= zero {
                break;
            }
            weight = weight * r;
            // mirror reflection of d about n
            let two = S::from_f64(2.0);
            d = (d - n.scale(two * d.dot(n))).normalize(sq);
            o = p_off;
        }
        (color, first)
    }

    /// The refracted ray's radiance (out of line: `trace` inlines everywhere else, and
    /// this is where it recurses).
    #[inline(never)]
    fn trace_refracted<
        const SH: bool,
        const TX: bool,
        const SP: bool,
        const RF: bool,
        const SO: bool,
    >(
        &self,
        o: V3<S>,
        d: V3<S>,
        level: u32,
        cnt: &mut Counts,
    ) -> V3<S> {
        let primary = Primary {
            objs: &[],
            found: None,
        };
        self.trace::<SH, TX, SP, RF, SO>(o, d, level, true, primary, cnt)
            .0
    }

    /// What `trace` returns for a ray from the eye that the plan proved hits nothing
    /// (its tile has no candidates), without the direction or the object loop.
    #[inline(always)]
    pub(super) fn miss_from_eye(&self, cnt: &mut Counts) -> V3<S> {
        cnt.primary += 1;
        V3::zero() + self.background.scale(S::one())
    }

    /// Row `j` of the frame: colour bytes, the AOVs when asked for, and the ray counts.
    pub(super) fn row<
        const SH: bool,
        const TX: bool,
        const SP: bool,
        const RF: bool,
        const SO: bool,
    >(
        &self,
        f: &FrameCtx<S>,
        j: u32,
    ) -> Rendered<Vec<f32>, Vec<u16>> {
        let vys = f.sample_row_offsets(j);
        let mut out = RowOut::new(f);
        for i in 0..f.width {
            let eye_objs = f.eye_objs(i, j);
            let mut acc = V3::<S>::zero();
            let mut first = None;
            for s in 0..f.spp {
                let (Some(ux), Some(&vy)) = (f.col(i, s), vys.get((s / f.grid) as usize)) else {
                    continue;
                };
                let (c, hit) = if eye_objs.is_empty() {
                    (self.miss_from_eye(&mut out.cnt), None)
                } else {
                    let d = (ux + vy - f.cw).normalize(f.sqrt);
                    let primary = Primary {
                        objs: eye_objs,
                        found: None,
                    };
                    self.trace::<SH, TX, SP, RF, SO>(f.eye, d, 0, false, primary, &mut out.cnt)
                };
                acc = acc + c;
                if s == 0 {
                    first = Some(hit);
                }
            }
            out.pixel(f, acc, first);
        }
        out.finish()
    }
}

impl<S: Scalar> FrameCtx<S> {
    /// v·y of each sub-pixel row of row `j`.
    pub(super) fn sample_row_offsets(&self, j: u32) -> Vec<V3<S>> {
        (0..self.grid)
            .map(|k| {
                let r = i64::from(j) * i64::from(self.grid) + i64::from(k);
                let y = derive::coordinate(self.sample_rows - 2 * r - 1, self.pitch);
                self.cv.scale(S::from_f64(y))
            })
            .collect()
    }

    /// u·x of sample `s`'s column in pixel column `i` (None only outside the frame).
    #[inline(always)]
    pub(super) fn col(&self, i: u32, s: u32) -> Option<V3<S>> {
        self.cols
            .get((i * self.grid + s % self.grid) as usize)
            .copied()
    }

    /// The objects a primary ray through pixel (i, j) can hit, in object order.
    #[inline(always)]
    pub(super) fn eye_objs(&self, i: u32, j: u32) -> &[u16] {
        match &self.tiles {
            Some(t) => t.at(i, j),
            None => &self.all,
        }
    }
}

/// A row's output as its pixels are finished: colour bytes, AOVs, ray counts.
pub(super) struct RowOut<S> {
    rgb: Vec<u8>,
    depth: Vec<f32>,
    normal: Vec<f32>,
    object: Vec<u16>,
    pub(super) cnt: Counts,
    _format: std::marker::PhantomData<S>,
}

impl<S: Scalar> RowOut<S> {
    pub(super) fn new(f: &FrameCtx<S>) -> Self {
        RowOut {
            rgb: Vec::with_capacity(f.width as usize * 3),
            depth: Vec::new(),
            normal: Vec::new(),
            object: Vec::new(),
            cnt: Counts::default(),
            _format: std::marker::PhantomData,
        }
    }

    /// The next pixel from the sum of its samples' radiance and its first sample's hit
    /// (None: the pixel had no first sample): mean, tone map, ⌊255·c⌋, and the AOVs.
    #[inline(always)]
    pub(super) fn pixel(&mut self, f: &FrameCtx<S>, acc: V3<S>, first: Option<Option<Hit<S>>>) {
        self.aovs(f, first);
        let c = if f.spp == 1 {
            acc
        } else {
            acc.scale(f.inv_spp)
        };
        let c = match f.tone_map {
            ToneMap::Clamp => c,
            ToneMap::Reinhard => {
                let one = S::one();
                let r = |v: S| {
                    let v = v.max(S::zero());
                    v / (one + v)
                };
                V3::new(r(c.x), r(c.y), r(c.z))
            }
        };
        // ⌊255·c⌋: the product is ≥ 0 (or NaN → 0), where `as` truncation is the
        // floor; cheaper than the format's floor and the same bits
        let q = |v: S| (v.clamp(S::zero(), S::one()) * S::from_f64(255.0)).to_f64() as u8;
        self.rgb.extend([q(c.x), q(c.y), q(c.z)]);
    }

    /// The next pixel's colour bytes, quantised by the caller as [`Self::pixel`] does.
    #[inline(always)]
    pub(super) fn push_rgb(&mut self, bytes: &[u8]) {
        self.rgb.extend_from_slice(bytes);
    }

    /// The next pixel's AOVs from its first sample's hit, when the frame has AOVs (None:
    /// the pixel had no first sample, and has no AOV entry).
    #[inline(always)]
    pub(super) fn aovs(&mut self, f: &FrameCtx<S>, first: Option<Option<Hit<S>>>) {
        if let (true, Some(hit)) = (f.aovs, first) {
            match hit {
                Some(h) => {
                    self.depth.push(h.t.to_f64() as f32);
                    self.normal.extend(h.n.to_f64().map(|v| v as f32));
                    self.object
                        .push(u16::try_from(h.obj).unwrap_or(super::NO_OBJECT));
                }
                None => {
                    self.depth.push(f32::INFINITY);
                    self.normal.extend([0.0f32; 3]);
                    self.object.push(super::NO_OBJECT);
                }
            }
        }
    }

    pub(super) fn finish(self) -> Rendered<Vec<f32>, Vec<u16>> {
        (self.rgb, self.depth, self.normal, self.object, self.cnt)
    }
}

/// rgb8, depth, normal, object index, ray counts of a frame or a row.
pub(super) type Rendered<A = Option<Vec<f32>>, B = Option<Vec<u16>>> = (Vec<u8>, A, A, B, Counts);
