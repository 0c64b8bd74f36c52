//! The planned kernel skips an unrotated plane, disk or square for a secondary ray that
//! leaves it on its own side (`pretest::Flat`). That must never change a bit: scenes with
//! flat objects above, below and level with the camera and the lights (a light exactly in a
//! plane makes its shadow rays parallel to it), mirrors, tiny and large y scales, and a
//! near-zero CORE_BIAS, rendered with and without culling in every format.

use sim_target::rt::{Numeric, Scene};

use crate::common;

/// A room of flat objects: floor square (mirror), a disk hovering at `disk_y`, a ceiling
/// plane, a sphere, the light at `light_y` (−1 puts it in the
/// floor's plane), camera at `eye_y`.
fn room(eye_y: f64, light_y: f64, disk_y: f64, disk_sy: f64, bias: f64) -> Scene {
    let text = format!(
        r#"
[render]
size = [40, 24]
depth = 3
bias = {bias}
background = [0.1, 0.1, 0.2]
[camera]
position = [0.5, {eye_y}, 7.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov_y = 60.0
[ambient]
color = [0.1, 0.1, 0.1]
[[light]]
position = [1.0, {light_y}, 2.0]
color = [30.0, 30.0, 30.0]
[material.mirror]
diffuse = {{ k = 0.5, color = [0.8, 0.8, 0.8] }}
reflection = {{ mode = "constant", r = 0.5 }}
[material.matte]
diffuse = {{ k = 0.9, color = [0.9, 0.4, 0.3] }}
reflection = {{ mode = "constant", r = 0.2 }}
[[object]]
shape = "square"
translate = [0.0, -1.0, 0.0]
scale = [4.0, 1.0, 4.0]
material = "mirror"
[[object]]
shape = "disk"
translate = [0.3, {disk_y}, 0.5]
scale = [1.2, {disk_sy}, 1.2]
material = "matte"
[[object]]
shape = "plane"
translate = [0.0, 3.0, 0.0]
material = "matte"
[[object]]
shape = "sphere"
translate = [-0.8, 0.0, 0.0]
scale = [0.7, 0.7, 0.7]
material = "mirror"
"#
    );
    jobs::scene::parse(&text, "room").expect("room parses")
}

#[test]
fn skipping_flat_objects_changes_no_bit_in_any_format() {
    let mut cases = 0;
    for eye_y in [2.0, -1.0, -2.5, 0.4] {
        for light_y in [2.5, -1.0, -0.2, 3.0] {
            for (disk_y, disk_sy) in [(0.2, 1.0), (-1.0, 1.0), (1.5, 1e-3), (-0.5, 3.0)] {
                for bias in [1e-3, 1e-9] {
                    let scene = room(eye_y, light_y, disk_y, disk_sy, bias);
                    for numeric in Numeric::ALL {
                        let what = format!(
                            "eye {eye_y}, light {light_y}, disk {disk_y}/{disk_sy}, bias {bias}"
                        );
                        common::assert_cull_invisible(&scene, numeric, None, &what);
                        cases += 1;
                    }
                }
            }
        }
    }
    assert_eq!(cases, 4 * 4 * 4 * 2 * Numeric::ALL.len());
}
