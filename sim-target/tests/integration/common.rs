//! Helpers shared by the ray-trace tests that compare two renders bit for bit (planned
//! vs general kernel, culled vs unculled, golden hashes), and their deterministic RNG.
// The psnr_budget example includes this file by path and uses a subset of it.
#![allow(dead_code)]

use sim_target::rt::{self, Numeric, RenderOptions, Scene};

/// The gallery's ray-traced scenes (name, TOML): the reference scene and the four of
/// `examples/rt/`.
pub const GALLERY: &[(&str, &str)] = &[
    (
        "reference",
        include_str!("../../../examples/reference.toml"),
    ),
    ("fresnel", include_str!("../../../examples/rt/fresnel.toml")),
    ("shapes", include_str!("../../../examples/rt/shapes.toml")),
    (
        "textures",
        include_str!("../../../examples/rt/textures.toml"),
    ),
    ("brdf", include_str!("../../../examples/rt/brdf.toml")),
];

/// RGB, depth and normal AOVs bit for bit, and the ray counts; a failure says how many
/// values differ instead of printing the buffers.
pub fn assert_same_frame(a: &rt::Frame, b: &rt::Frame, what: &str) {
    let differ = |x: &[u32], y: &[u32]| x.len() != y.len() || x.iter().zip(y).any(|(p, q)| p != q);
    let rgb = a.rgb8.iter().zip(&b.rgb8).filter(|(x, y)| x != y).count();
    assert!(
        rgb == 0 && a.rgb8.len() == b.rgb8.len(),
        "{what}: {rgb} of {} bytes differ",
        a.rgb8.len()
    );
    let bits = |v: &Option<Vec<f32>>| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert!(
        !differ(&bits(&a.depth), &bits(&b.depth)),
        "{what}: depth differs"
    );
    assert!(
        !differ(&bits(&a.normal), &bits(&b.normal)),
        "{what}: normal differs"
    );
    assert_eq!(a.stats.rays(), b.stats.rays(), "{what}: ray count");
}

/// A render with AOVs at `size` (None: the scene's own), culled or not.
pub fn render_culled(
    scene: &Scene,
    numeric: Numeric,
    cull: bool,
    size: Option<(u32, u32)>,
) -> rt::Frame {
    rt::render(
        scene,
        &RenderOptions {
            numeric,
            aovs: true,
            size,
            cull,
            ..Default::default()
        },
    )
    .expect("renders")
}

/// The plan's culling must be invisible: culled and unculled renders are the same frame.
pub fn assert_cull_invisible(
    scene: &Scene,
    numeric: Numeric,
    size: Option<(u32, u32)>,
    what: &str,
) {
    let (c, n) = (
        render_culled(scene, numeric, true, size),
        render_culled(scene, numeric, false, size),
    );
    assert_same_frame(&c, &n, &format!("{what} {numeric:?} culled/unculled"));
}

/// FNV-1a of a byte stream: the golden tests' image hash.
pub fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// [`fnv1a`] of a frame's RGB888 bytes, then its depth and normal AOVs (little-endian f32;
/// absent AOVs hash as empty).
pub fn frame_hash(f: &rt::Frame) -> u64 {
    let depth = f.depth.as_deref().unwrap_or_default();
    let normal = f.normal.as_deref().unwrap_or_default();
    fnv1a(
        f.rgb8
            .iter()
            .copied()
            .chain(depth.iter().flat_map(|v| v.to_le_bytes()))
            .chain(normal.iter().flat_map(|v| v.to_le_bytes())),
    )
}

/// SplitMix64: a seeded, portable stream of uniform f64 in [0, 1) for the probe tests.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    pub fn sign(&mut self) -> f64 {
        if self.next() < 0.5 {
            -1.0
        } else {
            1.0
        }
    }
}
