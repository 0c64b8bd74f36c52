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
// object block: ambient k (real)
`define RT_OBJ_AMBIENT_K 10
// object block: ambient colour (real x 3)
`define RT_OBJ_AMBIENT_COLOR 11
// object block: diffuse k (real)
`define RT_OBJ_DIFFUSE_K 14
// object block: diffuse colour (real x 3)
`define RT_OBJ_DIFFUSE_COLOR 15
// object block: diffuse model code
`define RT_OBJ_DIFFUSE_MODEL 18
// object block: specular k (real)
`define RT_OBJ_SPECULAR_K 20
// object block: specular colour (real x 3)
`define RT_OBJ_SPECULAR_COLOR 21
// object block: specular model code
`define RT_OBJ_SPECULAR_MODEL 24
// object block: specular exponent (u32)
`define RT_OBJ_EXPONENT 25
// object block: reflection mode code
`define RT_OBJ_REFLECTION_MODE 26
// object block: texture kind code
`define RT_OBJ_TEX_KIND 29
// first word of light 0 (the ambient light)
`define RT_LIGHTS_OFFSET 38
// words per light block
`define RT_LIGHT_WORDS 12
// light block: kind code
`define RT_LIGHT_KIND 0
// light block: position (real x 3)
`define RT_LIGHT_POSITION 1
// light block: colour (real x 3)
`define RT_LIGHT_COLOR 4
// light kind code of a point light
`define RT_LIGHT_POINT 1
// header flags: shadows
`define RT_FLAG_SHADOWS 1
// model codes the core builds: Lambert, Blinn-Phong, no reflection, no texture
`define RT_DIFFUSE_LAMBERT 0
`define RT_SPECULAR_BLINN_PHONG 0
`define RT_REFLECTION_NONE 0
`define RT_TEXTURE_NONE 0
// value format codes
`define RT_FORMAT_Q16_16 0
`define RT_FORMAT_BINARY32 1
// register-map version
`define RT_MAP_VERSION 2
// fraction bits of the pixel pitch
`define RT_PITCH_FRAC_BITS 40
`endif
