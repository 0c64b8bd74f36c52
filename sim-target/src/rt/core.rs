//! The clock count of a frame on the RTL ray-casting core (`hw/rt-core/rtl/rt_cast.v`):
//! the model's estimate for that design, which its differential tests hold equal to the
//! Verilated core's count for every frame (the RTL is the truth for timing; this module
//! follows it).
//!
//! Why a formula and not a simulation: the core runs on a fixed schedule. Each pixel owns
//! a slot of S = N·(1 + L) clocks in its intersection unit (N objects, L point lights
//! when shadows are on, else L = 0; S = 1 with no object): N pairs of its primary ray,
//! then L·N pairs of the shadow rays of a pixel D slots older. Every latency on the way is
//! fixed, so the last pixel's arrival, and with it the frame's count, is a closed form.
//! The constants are the RTL's stage counts, named after the units.

/// The arithmetic units' latencies (`hw/rt-core/rtl/q16_lat.vh`): a product
/// (`q16_dot`), a quotient (`q16_div`), a square root and a reciprocal square root. The
/// units' schedules are sums of these, and so are the constants below.
const DOT: u64 = 4;
const DIV: u64 = 35;
const SQRT: u64 = 27;
const RSQRT: u64 = 79;
/// A vector normalised (`q16_norm3`): v·v, 1/√, the scaling product.
const NORM3: u64 = 2 * DOT + RSQRT;

/// Clocks after `start` before the first ray enters the generator: the products
/// (W − 1)·K and (H − 1)·K, 16 clocks, and one to negate.
pub const SETUP: u64 = 17;
/// The primary-ray generator's latency (`rt_raygen`): the position words (magnitude,
/// rounding, sign), u·x and v·y, their sum, less w, the normalisation.
pub const RAYGEN: u64 = 3 + DOT + 1 + 1 + NORM3;
/// The intersection unit's latency (`rt_isect`, `isect.vh`): the quadrics' datapath
/// (front, discriminant, root, the quotients' operands, quotients, roots in order,
/// height), the longest, then the choice of datapath.
pub const ISECT: u64 = 3 * DOT + SQRT + DIV + 7 + 1;
/// From a pair entering the transform to its nearest-hit result: the transform (o − t,
/// then a product), the intersection, the reduction's register (`rt_xform`, `rt_isect`).
pub const TO_REDUCED: u64 = 1 + DOT + ISECT + 1;
/// The normal (`rt_normal`): the hit point, its components' magnitudes, the shape's
/// normal, to world space, normalised, the facing test and the flip.
pub const NORMAL: u64 = DOT + 1 + 1 + 1 + DOT + NORM3 + DOT + 1;
/// A light lane's shadow ray (`rt_light.vh`'s `L_WI`): p, to_l, d², 1/√d², ω_i.
const LANE_WI: u64 = DOT + 1 + 1 + DOT + RSQRT + DOT;
/// A light lane's term (`L_LAT`): after ω_i, the half vector normalised, n·h and its
/// clamp, the power (ten products), the norm's product, the BRDF's products and sum, the
/// colour and g.
const LANE_TERM: u64 = LANE_WI + 1 + NORM3 + DOT + 1 + 10 * DOT + DOT + DOT + 1 + 2 * DOT;
/// From the colour stage's input to its shadow rays: k_d·c_d, then the lanes' ω_i.
pub const SHADOW_RAYS: u64 = DOT + LANE_WI;
/// From the colour stage's input to its light terms entering the join queue: k_d·c_d,
/// then the lanes.
pub const TERMS: u64 = DOT + LANE_TERM;
/// A shadow pair's way from the unit's input to its pixel's occlusion word: the
/// transform, the intersection, the word's register.
pub const TO_OCCLUSION: u64 = 1 + DOT + ISECT + 1;
/// After the join: the sum, the choice of hit or background, the clamp, the packing.
pub const AFTER_JOIN: u64 = 4;

/// What the core builds with its default parameters (`rt_device`'s: every shape, one
/// point-light lane beside the ambient light, one sample per pixel, hard shadows): the
/// `Caps::rt_build` a target on the core advertises, so the host refuses or reduces a
/// scene asking for more before anything is sent.
pub const BUILD: protocol::frame::RtBuild = protocol::frame::RtBuild {
    shapes: 0x7f,
    lights: (<protocol::scene::SceneRegs>::LIGHT_CAPACITY - 1) as u8,
    max_spp: 1,
    features: protocol::frame::RtBuild::SHADOWS,
};

/// A frame's shape as the core schedules it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoreFrame {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Objects tested per ray (the scene's object count).
    pub objects: u32,
    /// Point lights whose shadow rays are traced: the scene's point lights when shadows
    /// are on and there is at least one object, else 0.
    pub shadow_lights: u32,
}

impl CoreFrame {
    /// The frame a scene asks the core for.
    pub fn of(scene: &crate::rt::Scene) -> Self {
        let objects = u32::try_from(scene.objects.len()).unwrap_or(u32::MAX);
        let lights = u32::try_from(scene.lights.len()).unwrap_or(u32::MAX);
        Self {
            width: scene.width,
            height: scene.height,
            objects,
            shadow_lights: if scene.shadows && objects > 0 {
                lights
            } else {
                0
            },
        }
    }

    /// Clocks of the primary part of a slot: one per object, at least one.
    pub fn primary_clocks(&self) -> u64 {
        u64::from(self.objects.max(1))
    }

    /// Clocks per pixel: the primary part and the shadow part.
    pub fn slot(&self) -> u64 {
        self.primary_clocks() + u64::from(self.shadow_lights) * u64::from(self.objects)
    }

    /// Slots between a pixel's own and the one whose shadow part tests its shadow rays:
    /// the smallest D with D·S clocks covering the way from the pixel's last primary pair
    /// to its shadow rays standing in the queue (one clock after they leave the colour
    /// stage), less the one clock from that pair to its slot's shadow part.
    pub fn shadow_delay(&self) -> u64 {
        let way = TO_REDUCED + NORMAL + SHADOW_RAYS + 1;
        (way - 1).div_ceil(self.slot())
    }

    /// Clock edges from the `start` edge to the one that raises `done`, both counted:
    /// the setup, the generator, one slot per pixel, and the last pixel's way out, which
    /// is the later of its light terms and (with shadows) its occlusion word.
    pub fn cycles(&self) -> u64 {
        let pixels = u64::from(self.width) * u64::from(self.height);
        if pixels == 0 {
            return 1 + SETUP;
        }
        let s = self.slot();
        let np = self.primary_clocks();
        // clocks from the last pixel's slot to its join, by the terms and by the word
        let terms = np - 1 + TO_REDUCED + NORMAL + TERMS + 1;
        let join = if self.shadow_lights > 0 && self.objects > 0 {
            terms.max((self.shadow_delay() + 1) * s - 1 + TO_OCCLUSION + 1)
        } else {
            terms
        };
        1 + SETUP + RAYGEN + (pixels - 1) * s + join + AFTER_JOIN + 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_units_latencies_are_the_rtls() {
        // the figures the RTL's headers state for Q_DOT_LAT = 4, Q_DIV_LAT = 35
        assert_eq!(
            [RAYGEN, ISECT, NORMAL, SHADOW_RAYS, TERMS],
            [96, 82, 103, 97, 247]
        );
    }

    #[test]
    fn without_shadows_a_pixel_leaves_443_clocks_after_its_last_pair() {
        let f = CoreFrame {
            width: 160,
            height: 90,
            objects: 8,
            shadow_lights: 0,
        };
        assert_eq!(f.cycles(), 1 + 17 + 96 + 14_400 * 8 + 443);
    }
}
