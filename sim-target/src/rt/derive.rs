//! The frame constants a scene implies, computed in f64: the camera basis, the pixel
//! pitch and each object's inverse transform. The golden model prepares a frame with these
//! functions, and the host writes their results into the register image as derived words
//! (`protocol::scene`, "Derived words"), so that a core without sines, tangents or f64
//! computes with exactly the numbers the model rounds. One home for each: a second copy
//! that evaluated in another order would differ in the last bit and move a hit.

use super::f;
use super::Camera;

/// Fraction bits of [`pitch`]: the pixel pitch is an integer number of 2⁻⁴⁰.
///
/// Why 40: a sample's coordinate n·K must be exact in f64 (53 bits) for the model's
/// rounding to Q16.16 to be the core's integer rounding, with |n| < 2¹³ (8192 sample
/// columns); 2⁻⁴⁰ leaves K < 1 for that, and the error of K itself (≤ 2⁻⁴¹) moves x by
/// at most 2⁻²⁸ at the frame's edge, far below Q16.16's 2⁻¹⁶.
pub const PITCH_FRAC_BITS: u32 = protocol::scene::PITCH_FRAC_BITS;

/// The camera's axes u (right), v (up), w (backwards, away from `look_at`), each a unit
/// vector; a degenerate camera (the eye on `look_at`, or `up` along the view) gives zero
/// vectors, which the host refuses before it gets here.
pub fn basis(c: &Camera) -> [[f64; 3]; 3] {
    let w = f::normalize(f::sub(c.position, c.look_at));
    let u = f::normalize(f::cross(c.up, w));
    let v = f::cross(w, u);
    [u, v, w]
}

/// Side of the sub-pixel grid for `spp` samples per pixel: ⌈√spp⌉.
pub fn grid(spp: u32) -> u32 {
    (f64::from(spp)).sqrt().ceil() as u32
}

/// The pixel pitch K = tan(fov_y / 2) / (height · ⌈√spp⌉) in units of 2⁻⁴⁰, rounded to
/// nearest (saturating: a field of view of 180° or more gives the largest pitch).
pub fn pitch(fov_y: f64, height: u32, spp: u32) -> u64 {
    let s = (fov_y.to_radians() / 2.0).tan();
    let k = s / (f64::from(height) * f64::from(grid(spp)));
    (k * (1u64 << PITCH_FRAC_BITS) as f64).round() as u64
}

/// The image-plane coordinate n·K of the sample line n (x: n = 2c + 1 − width·g for
/// sample column c; y: n = height·g − 2r − 1 for sample row r): exact whenever
/// |n|·pitch < 2⁵³, so that rounding it to a fixed-point format is the integer rounding
/// a core does on the product n·pitch.
pub fn coordinate(n: i64, pitch: u64) -> f64 {
    n as f64 * (pitch as f64 / (1u64 << PITCH_FRAC_BITS) as f64)
}

/// An object's inverse linear transform M⁻¹ = S⁻¹·Rᵀ (M = T·R·S, R = Rz·Ry·Rx in
/// degrees), row-major: what takes a ray into object space; its transpose takes a normal
/// back out.
pub fn inverse_linear(rotate: [f64; 3], scale: [f64; 3]) -> [[f64; 3]; 3] {
    let r = f::rotation(rotate);
    let sinv = f::diag(scale.map(|s| 1.0 / s));
    f::mul(sinv, f::transpose(r))
}
