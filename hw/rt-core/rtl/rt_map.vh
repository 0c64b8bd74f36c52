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
// word offsets in the scene image
// words in the image (default capacities)
`define RT_SCENE_WORDS 494
// object blocks in the image
`define RT_OBJ_CAPACITY 8
// light blocks in the image
`define RT_LIGHT_CAPACITY 2
// header: version | OBJ << 16 | LIGHTS << 24
`define RT_HDR_VERSION 1
// header: object count
`define RT_HDR_OBJECT_COUNT 2
// header: light count (ambient included)
`define RT_HDR_LIGHT_COUNT 3
// header: frame width
`define RT_HDR_WIDTH 4
// header: frame height
`define RT_HDR_HEIGHT 5
// header: ray depth
`define RT_HDR_DEPTH 6
// header: CORE_BIAS (real)
`define RT_HDR_BIAS 7
// header: MAX_DISTANCE (binary32 bits)
`define RT_HDR_MAX_DISTANCE 8
// header: background colour (real x 3)
`define RT_HDR_BACKGROUND 9
// header: samples per pixel
`define RT_HDR_SPP 12
// header: flags
`define RT_HDR_FLAGS 13
// header: value format code
`define RT_HDR_VALUE_FORMAT 15
// camera position (real x 3)
`define RT_CAM_POSITION 16
// camera basis u (real x 3, derived)
`define RT_CAM_U 26
// camera basis v (real x 3, derived)
`define RT_CAM_V 29
// camera basis w (real x 3, derived)
`define RT_CAM_W 32
// pixel pitch, 2^-40 units, low then high word (derived)
`define RT_CAM_PITCH 36
// first word of object 0
`define RT_OBJECTS_OFFSET 62
// words per object block
`define RT_OBJ_WORDS 54
// object block: shape code
`define RT_OBJ_SHAPE 0
// object block: translate (real x 3)
`define RT_OBJ_TRANSLATE 1
// object block: inverse transform, row-major (real x 9, derived)
`define RT_OBJ_MINV 45
// value format codes
`define RT_FORMAT_Q16_16 0
`define RT_FORMAT_BINARY32 1
// register-map version
`define RT_MAP_VERSION 2
// fraction bits of the pixel pitch
`define RT_PITCH_FRAC_BITS 40
`endif
