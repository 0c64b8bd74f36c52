//! Helpers shared by the ray-trace tests that compare two renders bit for bit (planned
//! vs general kernel, culled vs unculled).
// Each test binary compiles this module and uses a subset of it.
#![allow(dead_code)]

use sim_target::rt::{self, Numeric, RenderOptions, Scene};

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
