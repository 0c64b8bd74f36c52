//! 3-vectors and 3×3 matrices in any [`Scalar`].

use crate::num::{self, Scalar, SqrtKind};
use core::ops::{Add, Mul, Neg, Sub};

/// A 3-vector in the kernel's format: points, directions, normals and colours alike.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct V3<S> {
    /// First component (x, or red for a colour).
    pub x: S,
    /// Second component (y, or green).
    pub y: S,
    /// Third component (z, or blue).
    pub z: S,
}

impl<S: Scalar> V3<S> {
    /// The vector (x, y, z), components already in the format.
    #[inline(always)]
    pub fn new(x: S, y: S, z: S) -> Self {
        Self { x, y, z }
    }
    /// From f64 components (converted once, at scene preparation).
    pub fn from_f64(a: [f64; 3]) -> Self {
        Self::new(S::from_f64(a[0]), S::from_f64(a[1]), S::from_f64(a[2]))
    }
    /// Back to f64 (exact: every format widens to f64 exactly), for references and AOVs.
    pub fn to_f64(self) -> [f64; 3] {
        [self.x.to_f64(), self.y.to_f64(), self.z.to_f64()]
    }
    /// (0, 0, 0): the start of a colour sum, and what a zero-length normalise returns.
    #[inline(always)]
    pub fn zero() -> Self {
        Self::new(S::zero(), S::zero(), S::zero())
    }
    /// v·o through [`Scalar::dot3`]: one rounding in the fixed formats, not five.
    #[inline(always)]
    pub fn dot(self, o: Self) -> S {
        S::dot3(self.x, o.x, self.y, o.y, self.z, o.z)
    }
    /// v × o with each product and difference rounded by the format; [`V3::cross2`] is
    /// the variant for where the result must be exact.
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    /// Cross product with each component one fused two-term sum ([`Scalar::dot2`]): the
    /// components of d × o are differences of products near |d||o| whose result is small
    /// for rays near an object, where the kernel needs them exact to the last bit.
    #[inline(always)]
    pub fn cross2(self, o: Self) -> Self {
        Self::new(
            S::dot2(self.y, o.z, -self.z, o.y),
            S::dot2(self.z, o.x, -self.x, o.z),
            S::dot2(self.x, o.y, -self.y, o.x),
        )
    }
    /// Per-component product, each rounded to nearest: a colour times a colour.
    #[inline(always)]
    pub fn hadamard(self, o: Self) -> Self {
        Self::new(self.x.mul_rn(o.x), self.y.mul_rn(o.y), self.z.mul_rn(o.z))
    }
    /// Scale by a scalar.
    #[inline(always)]
    pub fn scale(self, s: S) -> Self {
        Self::new(self.x.mul_rn(s), self.y.mul_rn(s), self.z.mul_rn(s))
    }
    /// Unit vector by 1/√(v·v) with the chosen square root (zero stays zero).
    #[inline(always)]
    pub fn normalize(self, sq: SqrtKind) -> Self {
        let l2 = self.dot(self);
        if l2 <= S::zero() {
            return self;
        }
        self.scale(num::rsqrt(l2, sq))
    }
    /// |v| = √(v·v) with the chosen square root.
    #[inline(always)]
    pub fn length(self, sq: SqrtKind) -> S {
        num::sqrt(self.dot(self), sq)
    }
}

impl<S: Scalar> Add for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl<S: Scalar> Sub for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl<S: Scalar> Neg for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}
impl<S: Scalar> Mul<S> for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: S) -> Self {
        self.scale(s)
    }
}

/// Row-major 3×3 matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct M3<S>(pub [[S; 3]; 3]);

impl<S: Scalar> M3<S> {
    /// From f64 rows.
    pub fn from_f64(m: [[f64; 3]; 3]) -> Self {
        Self(m.map(|r| r.map(S::from_f64)))
    }
    /// M·v.
    #[inline(always)]
    pub fn mul_v(&self, v: V3<S>) -> V3<S> {
        let m = &self.0;
        V3::new(
            S::dot3(m[0][0], v.x, m[0][1], v.y, m[0][2], v.z),
            S::dot3(m[1][0], v.x, m[1][1], v.y, m[1][2], v.z),
            S::dot3(m[2][0], v.x, m[2][1], v.y, m[2][2], v.z),
        )
    }
}

/// f64 3-vectors and 3×3 matrices as plain arrays: the scene's own numbers, before the
/// kernel converts them to its format (camera basis, object transforms, culling bounds,
/// register images) and in the tools that build or check scenes. One module so that every
/// such computation rounds the same way: golden images depend on these bits (each
/// function's evaluation order is part of its contract).
pub mod f {
    /// The matrix product a·b, each entry summed over k = 0, 1, 2 with `Iterator::sum`.
    pub fn mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut r = [[0.0; 3]; 3];
        for (i, row) in r.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        r
    }
    /// The transpose: the inverse of a rotation.
    pub fn transpose(a: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut r = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                r[i][j] = a[j][i];
            }
        }
        r
    }
    /// R = Rz·Ry·Rx (degrees).
    pub fn rotation(deg: [f64; 3]) -> [[f64; 3]; 3] {
        let [ax, ay, az] = deg.map(f64::to_radians);
        let (sx, cx) = ax.sin_cos();
        let (sy, cy) = ay.sin_cos();
        let (sz, cz) = az.sin_cos();
        let rx = [[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]];
        let ry = [[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]];
        let rz = [[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]];
        mul(rz, mul(ry, rx))
    }
    /// The diagonal matrix of `d`: a scale.
    pub fn diag(d: [f64; 3]) -> [[f64; 3]; 3] {
        [[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]]
    }
    /// a + b, one rounding per component.
    pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
    }
    /// a − b, one rounding per component (a direction between two points).
    pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
    /// a·k, one rounding per component.
    pub fn scale(a: [f64; 3], k: f64) -> [f64; 3] {
        [a[0] * k, a[1] * k, a[2] * k]
    }
    /// a·b, summed x, y, z from the left.
    pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }
    /// |a| = √(a·a).
    pub fn length(a: [f64; 3]) -> f64 {
        dot(a, a).sqrt()
    }
    /// a × b (right-handed).
    pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
    /// v/|v|, each component divided by the length; the zero vector is returned as is
    /// (a degenerate direction stays visibly zero instead of becoming NaN).
    pub fn normalize(v: [f64; 3]) -> [f64; 3] {
        let l = length(v);
        if l > 0.0 {
            [v[0] / l, v[1] / l, v[2] / l]
        } else {
            v
        }
    }
}
