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

/// Clocks after `start` before the first ray enters the generator: the products
/// (W − 1)·K and (H − 1)·K, 16 clocks, and one to negate.
pub const SETUP: u64 = 17;
/// The primary-ray generator's latency (`rt_raygen`).
pub const RAYGEN: u64 = 93;
/// From a pair entering the transform to its nearest-hit result: transform 5,
/// intersection 82, the reduction's register 1 (`rt_xform`, `rt_isect`).
pub const TO_REDUCED: u64 = 5 + 82 + 1;
/// The normal (`rt_normal`).
pub const NORMAL: u64 = 102;
/// From the colour stage's input to its shadow rays: k_d·c_d 4, the light lanes' ω_i 93.
pub const SHADOW_RAYS: u64 = 97;
/// From the colour stage's input to its light terms entering the join queue: k_d·c_d 4,
/// the lanes 243.
pub const TERMS: u64 = 247;
/// A shadow pair's way from the unit's input to its pixel's occlusion word: transform 5,
/// intersection 82, the word's register 1.
pub const TO_OCCLUSION: u64 = 5 + 82 + 1;
/// After the join: the sum, the choice of hit or background, the packing.
pub const AFTER_JOIN: u64 = 3;

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
    fn without_shadows_a_pixel_leaves_441_clocks_after_its_last_pair() {
        let f = CoreFrame {
            width: 160,
            height: 90,
            objects: 8,
            shadow_lights: 0,
        };
        assert_eq!(f.cycles(), 1 + 17 + 93 + 14_400 * 8 + 441);
    }
}
