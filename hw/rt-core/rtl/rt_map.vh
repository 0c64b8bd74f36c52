// rt_map.vh -- the ray-casting core's codes from the scene register image.
//
// GENERATED from protocol::scene (protocol/src/scene.rs); do not edit.
// `FPGFX_BLESS=1 cargo test -p protocol --test integration rt_map` rewrites it.
`ifndef RT_MAP_VH
`define RT_MAP_VH
// bits of a shape code
`define RT_SHAPE_BITS 3
// shape code: Sphere
`define RT_SHAPE_SPHERE 3'd0
// shape code: Plane
`define RT_SHAPE_PLANE 3'd1
// shape code: Disk
`define RT_SHAPE_DISK 3'd2
// shape code: Square
`define RT_SHAPE_SQUARE 3'd3
// shape code: Cylinder
`define RT_SHAPE_CYLINDER 3'd4
// shape code: Cone
`define RT_SHAPE_CONE 3'd5
// shape code: Cube
`define RT_SHAPE_CUBE 3'd6
`endif
