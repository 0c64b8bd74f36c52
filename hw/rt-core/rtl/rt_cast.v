// rt_cast -- the ray-casting core's frame: every pixel's primary ray, each object tested
// in object order, the nearest hit, its object, depth and shading normal (the golden
// model's AOV planes, `--numeric q16.16 --aovs`; sim-target/src/rt/kernel.rs `row`,
// `trace`, `closest`, `occluded`) and its colour (ambient, Lambert, Blinn-Phong and hard
// shadows for point lights, RGB888), bit for bit; seed 002 §3.2-3.5.
//
// Why this shape: the intersection unit takes one (ray, object) pair per clock, so a ray
// of a scene with N objects occupies it N clocks. The ray generator runs one pixel ahead
// under its own clock enable: it is held while its ray is paired with objects 0 .. N-1
// and advances with the last pair, so no FIFO sits between them. Every pair is tested
// with tmax = max_distance and the reduction keeps, in object order, each hit with
// t <= best (why that is the model's nearest hit: rt_isect).
//
// Shadows share the intersection unit on a fixed schedule, so that a frame's clock count
// stays a formula: each pixel has a slot of S = N (1 + L) clocks (L point lights; S = N
// without shadows, and 1 with no object): its N primary pairs first, then L N shadow
// pairs (light l with objects 0 .. N-1, in light order) of the oldest pixel whose shadow
// rays are queued when the shadow part begins, or none. The colour stage sends every
// pixel's L shadow rays (origin p + n.scale(bias), direction wi, tmin = bias, tmax =
// dist: the model's `occluded`) about 289 clocks after its primary pairs, into a queue
// of 2^SQA pixels; a shadow pair that hits anything marks its light blocked (an any(),
// so the object order does not matter), and after the pixel's last shadow pair its
// occlusion word goes back to the colour stage, which joins it with the pixel's light
// terms (rt_shade). A miss sends rays too, whose answer nothing reads: the slots stay
// fixed. The queues' depths are bounded by the schedule (rt-core.md derives the bounds).
//
// Each object's inverse
// transform, translation and shape are read from the scene image's words, written
// through the cfg port at their register-map offsets (rt_map.vh, generated from
// protocol::scene): the core keeps only the words it reads.
//
// What it refuses (err, sticky until the next start; the frame still runs to its end):
// bit 0 an image in another value format than Q16.16, bit 1 more samples per pixel than
// one, bit 2 more objects than OBJ, bit 3 a pair whose shape this instance does not build,
// bit 4 a frame of zero width or height (no pixel is produced; done follows the setup) or
// a pitch of 2^52 or more (the host keeps |n*K| < 2^52, which a pitch that wide breaks),
// bit 5 shadows on in an instance built without them (SHADOWS = 0), bit 6 more point
// lights than LIGHTS or a light that is not a point light, bit 7 a material the core
// does not build (Oren-Nayar, Torrance-Sparrow, a texture, a reflection with depth > 1).
//
// Ports
//   cfg_we, cfg_addr, cfg_data: a write of scene-image word cfg_addr (ignored while busy).
//   start: a pulse begins a frame from the words written; busy until done pulses.
//   hold: high stalls every stage and the pixel sequencer (the output's back-pressure).
//   pix_*: one result per pixel in raster order: x, y, hit, obj (the nearest object's
//   index), t (its distance, Q16.16), n (world-space unit normal facing the ray; 0 for a
//   miss), rgb (R in bits 23:16), kcu116 (G << 8 | B at even x, G << 8 | R at odd x),
//   pix_valid.
//   refuse: the err bits a start would raise now, from the words written (bit 3: an
//   object's shape is not built), so a bus can refuse the start before it happens.
//   rays: the rays the frame tested so far (a pixel's primary ray, L shadow rays per
//   pixel with shadows), cleared by start.
//   width, height: the frame size words as written (a bus keeps the frame's at start, for
//   its read-back).
// Timing: after start, SETUP = 17 clocks, then the generator's latency 96, then one
// slot per pixel. Without shadows a pixel's result leaves 443 clocks after its ray's
// last pair (xform 5, isect 82, the reduction 1, the normal 103, the colour 252); with
// them, when both its terms and its occlusion word have arrived (rt-core.md gives the
// frame's count). hold adds one clock per held clock. (The units' schedules are written
// in q16_lat.vh's latencies; these figures are for Q_DOT_LAT = 4, Q_DIV_LAT = 35.)
// Parameters: OBJ 1..`RT_OBJ_CAPACITY` objects held; LIGHTS 1..`RT_LIGHT_CAPACITY` - 1
// point-light lanes; SHAPES as rt_isect; SHADOWS 1 builds shadows; SQA >= 8, OQA >= 6,
// TQA >= 2 the address bits of the queues of shadow rays, occlusion words and light
// terms (the schedule's bounds: 145, 32 and 3 entries, rt-core.md).
`default_nettype none
`include "rt_map.vh"
module rt_cast #(
    parameter integer OBJ = `RT_OBJ_CAPACITY,
    parameter integer LIGHTS = `RT_LIGHT_CAPACITY - 1,
    parameter [6:0] SHAPES = 7'b111_1111,
    parameter integer SHADOWS = 1,
    parameter integer SQA = 8,
    parameter integer OQA = 6,
    parameter integer TQA = 2
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        cfg_we,
    input  wire [8:0]  cfg_addr,
    input  wire [31:0] cfg_data,
    input  wire        start,
    input  wire        hold,
    output reg         busy,
    output reg         done,
    output reg  [7:0]  err,
    output wire        pix_valid,
    output wire [15:0] pix_x,
    output wire [15:0] pix_y,
    output wire        pix_hit,
    output wire [7:0]  pix_obj,
    output wire [31:0] pix_t,
    output wire [95:0] pix_n,
    output wire [23:0] pix_rgb,
    output wire [15:0] pix_kcu116,
    output wire [7:0]  refuse,
    output reg  [31:0] rays,
    output reg  [15:0] width,
    output reg  [15:0] height
);
    generate
        if (OBJ < 1 || OBJ > `RT_OBJ_CAPACITY || OBJ > 255 || LIGHTS < 1 ||
            LIGHTS > `RT_LIGHT_CAPACITY - 1 || LIGHTS > 8 || (SHADOWS != 0 && SHADOWS != 1) ||
            SQA < 8 || OQA < 6 || TQA < 2) begin : bad_parameter
            rt_cast_parameter_out_of_range unsupported();
        end
    endgenerate

    localparam integer SB = `RT_SHAPE_BITS;
    localparam integer PB = 54;             // n*K, 2^-40 units: |n*K| < 2^52
    localparam integer KB = 8;              // object index bits
    // setup after start: 16 clocks of the two products (W-1)*K and (H-1)*K, 1 to negate
    localparam integer SETUP = 17;
    localparam integer IB = OBJ > 1 ? $clog2(OBJ) : 1;  // bits that index the table
    localparam integer LB = LIGHTS > 1 ? $clog2(LIGHTS) : 1;  // bits that index a lane

    wire ce = !hold;

    // ---- the scene words the core reads --------------------------------------------
    reg [31:0]  spp, value_format, obj_count, bias, max_f32;
    reg [63:0]  pitch;
    reg [95:0]  eye, cu, cv, cw;
    reg [SB-1:0] shape_k [0:OBJ-1];
    reg [95:0]  trans_k [0:OBJ-1];
    reg [287:0] minv_k  [0:OBJ-1];
    // materials: k and colour of the ambient, diffuse and specular terms, the exponent,
    // and the codes the core refuses unless they name what it builds
    reg [31:0]  ka_k [0:OBJ-1], kd_k [0:OBJ-1], ks_k [0:OBJ-1];
    reg [95:0]  ca_k [0:OBJ-1], cd_k [0:OBJ-1], cs_k [0:OBJ-1];
    reg [9:0]   e_k [0:OBJ-1];
    reg [31:0]  dmodel_k [0:OBJ-1], smodel_k [0:OBJ-1], refl_k [0:OBJ-1], tex_k [0:OBJ-1];
    // lights: 0 is the ambient light (its colour), 1 .. the point lights
    reg [31:0]  lkind [0:`RT_LIGHT_CAPACITY-1];
    reg [95:0]  lpos [0:`RT_LIGHT_CAPACITY-1], lcol [0:`RT_LIGHT_CAPACITY-1];
    reg [95:0]  background;
    reg [31:0]  flags, light_count, depth;

    integer k, w;
    wire [31:0] addr = {23'd0, cfg_addr};
    // the image offset of field f of object o, of light l
    function [31:0] obj_at(input integer o, input integer f);
        obj_at = `RT_OBJECTS_OFFSET + o * `RT_OBJ_WORDS + f;
    endfunction
    function [31:0] light_at(input integer l, input integer f);
        light_at = `RT_LIGHTS_OFFSET + l * `RT_LIGHT_WORDS + f;
    endfunction
    always @(posedge clk) begin
        if (cfg_we && !busy) begin
            case (cfg_addr)
                `RT_HDR_WIDTH: width <= cfg_data[15:0];
                `RT_HDR_HEIGHT: height <= cfg_data[15:0];
                `RT_HDR_SPP: spp <= cfg_data;
                `RT_HDR_VALUE_FORMAT: value_format <= cfg_data;
                `RT_HDR_OBJECT_COUNT: obj_count <= cfg_data;
                `RT_HDR_BIAS: bias <= cfg_data;
                `RT_HDR_BACKGROUND: background[31:0] <= cfg_data;
                `RT_HDR_BACKGROUND + 1: background[63:32] <= cfg_data;
                `RT_HDR_BACKGROUND + 2: background[95:64] <= cfg_data;
                `RT_HDR_FLAGS: flags <= cfg_data;
                `RT_HDR_LIGHT_COUNT: light_count <= cfg_data;
                `RT_HDR_DEPTH: depth <= cfg_data;
                `RT_HDR_MAX_DISTANCE: max_f32 <= cfg_data;
                `RT_CAM_PITCH: pitch[31:0] <= cfg_data;
                `RT_CAM_PITCH + 1: pitch[63:32] <= cfg_data;
                `RT_CAM_POSITION: eye[31:0] <= cfg_data;
                `RT_CAM_POSITION + 1: eye[63:32] <= cfg_data;
                `RT_CAM_POSITION + 2: eye[95:64] <= cfg_data;
                `RT_CAM_U: cu[31:0] <= cfg_data;
                `RT_CAM_U + 1: cu[63:32] <= cfg_data;
                `RT_CAM_U + 2: cu[95:64] <= cfg_data;
                `RT_CAM_V: cv[31:0] <= cfg_data;
                `RT_CAM_V + 1: cv[63:32] <= cfg_data;
                `RT_CAM_V + 2: cv[95:64] <= cfg_data;
                `RT_CAM_W: cw[31:0] <= cfg_data;
                `RT_CAM_W + 1: cw[63:32] <= cfg_data;
                `RT_CAM_W + 2: cw[95:64] <= cfg_data;
                default: ;
            endcase
            // every word at a constant place: a word index computed from the address
            // would be a barrel shifter per field and object (tens of thousands of LUTs)
            for (k = 0; k < OBJ; k = k + 1) begin
                if (addr == obj_at(k, `RT_OBJ_SHAPE)) shape_k[k] <= cfg_data[SB-1:0];
                for (w = 0; w < 3; w = w + 1) begin
                    if (addr == obj_at(k, `RT_OBJ_TRANSLATE) + w)
                        trans_k[k][32 * w +: 32] <= cfg_data;
                    if (addr == obj_at(k, `RT_OBJ_AMBIENT_COLOR) + w)
                        ca_k[k][32 * w +: 32] <= cfg_data;
                    if (addr == obj_at(k, `RT_OBJ_DIFFUSE_COLOR) + w)
                        cd_k[k][32 * w +: 32] <= cfg_data;
                    if (addr == obj_at(k, `RT_OBJ_SPECULAR_COLOR) + w)
                        cs_k[k][32 * w +: 32] <= cfg_data;
                end
                for (w = 0; w < 9; w = w + 1) begin
                    if (addr == obj_at(k, `RT_OBJ_MINV) + w) minv_k[k][32 * w +: 32] <= cfg_data;
                end
                if (addr == obj_at(k, `RT_OBJ_AMBIENT_K)) ka_k[k] <= cfg_data;
                if (addr == obj_at(k, `RT_OBJ_DIFFUSE_K)) kd_k[k] <= cfg_data;
                if (addr == obj_at(k, `RT_OBJ_SPECULAR_K)) ks_k[k] <= cfg_data;
                if (addr == obj_at(k, `RT_OBJ_EXPONENT)) e_k[k] <= cfg_data[9:0];
                if (addr == obj_at(k, `RT_OBJ_DIFFUSE_MODEL)) dmodel_k[k] <= cfg_data;
                if (addr == obj_at(k, `RT_OBJ_SPECULAR_MODEL)) smodel_k[k] <= cfg_data;
                if (addr == obj_at(k, `RT_OBJ_REFLECTION_MODE)) refl_k[k] <= cfg_data;
                if (addr == obj_at(k, `RT_OBJ_TEX_KIND)) tex_k[k] <= cfg_data;
            end
            for (k = 0; k < `RT_LIGHT_CAPACITY; k = k + 1) begin
                if (addr == light_at(k, `RT_LIGHT_KIND)) lkind[k] <= cfg_data;
                for (w = 0; w < 3; w = w + 1) begin
                    if (addr == light_at(k, `RT_LIGHT_POSITION) + w)
                        lpos[k][32 * w +: 32] <= cfg_data;
                    if (addr == light_at(k, `RT_LIGHT_COLOR) + w)
                        lcol[k][32 * w +: 32] <= cfg_data;
                end
            end
        end
    end

    // ---- MAX_DISTANCE: binary32 bits to Q16.16 as the model converts it ----------------
    // min(value, Q16.16's largest), rounded half away from zero, clipped; NaN gives the
    // largest (f64::min ignores NaN)
    function [31:0] f32_to_q16(input [31:0] f);
        reg [7:0]  e;
        reg [23:0] m;
        reg [63:0] mag;
        integer sh;
        begin
            e = f[30:23];
            m = {e != 0, f[22:0]};
            sh = {24'd0, e} - 134;  // value * 2^16 = m * 2^(e - 127 - 23 + 16)
            if (e == 8'hff) mag = f[22:0] != 0 ? 64'h7fff_ffff : 64'hffff_ffff_ffff_ffff;
            else if (sh > 8) mag = 64'hffff_ffff_ffff_ffff;
            else if (sh >= 0) mag = {40'd0, m} << sh;
            else if (sh < -25) mag = 64'd0;
            else mag = ({40'd0, m} + (64'd1 << (-sh - 1))) >> (-sh);
            if (e == 8'hff && f[22:0] != 0) f32_to_q16 = 32'h7fff_ffff;
            else if (!f[31]) f32_to_q16 = mag > 64'h7fff_ffff ? 32'h7fff_ffff : mag[31:0];
            else f32_to_q16 = mag >= 64'h8000_0000 ? 32'h8000_0000 : 32'd0 - mag[31:0];
        end
    endfunction

    // ---- what the core refuses ------------------------------------------------------
    reg bad_material, bad_lights;
    integer j;
    always @(*) begin
        bad_material = 1'b0;
        for (j = 0; j < OBJ; j = j + 1) begin
            if (j < obj_count && (dmodel_k[j] != `RT_DIFFUSE_LAMBERT ||
                (ks_k[j] != 0 && smodel_k[j] != `RT_SPECULAR_BLINN_PHONG) ||
                (refl_k[j] != `RT_REFLECTION_NONE && depth > 1) ||
                tex_k[j] != `RT_TEXTURE_NONE))
                bad_material = 1'b1;
        end
        bad_lights = light_count == 0 || light_count - 1 > LIGHTS;
        for (j = 1; j < `RT_LIGHT_CAPACITY; j = j + 1) begin
            if (j < light_count && lkind[j] != `RT_LIGHT_POINT) bad_lights = 1'b1;
        end
    end

    reg bad_shape;
    wire [7:0] built = {1'b0, SHAPES};
    always @(*) begin
        bad_shape = 1'b0;
        for (j = 0; j < OBJ; j = j + 1) begin
            if (j < obj_count && !built[shape_k[j]]) bad_shape = 1'b1;
        end
    end
    wire [7:0] start_err = {bad_material, bad_lights,
                            SHADOWS == 0 && (flags & `RT_FLAG_SHADOWS) != 0,
                            width == 0 || height == 0 || pitch[63:PB-2] != 0, 1'b0,
                            obj_count > OBJ, spp != 1, value_format != `RT_FORMAT_Q16_16};
    assign refuse = start_err | {4'd0, bad_shape, 3'd0};

    // ---- frame sequencer ------------------------------------------------------------
    reg [31:0]          tmax;
    reg [KB-1:0]        n_obj;    // objects tested per ray (0: every ray misses)
    reg [3:0]           n_l;      // point lights (lanes in use)
    reg                 sh_on;    // shadow rays this frame
    reg [4:0]           setup;    // counts the setup clocks down
    reg signed [PB-1:0] xm, acc_x, acc_y, k2;
    reg [15:0]          wm1, hm1; // shifted out during setup, most significant bit first
    reg [15:0]          col, row;
    reg                 feeding;  // pixels remain to be generated
    reg [31:0]          pixels_out;
    wire [31:0]         pixels = {16'd0, width} * {16'd0, height};
    wire signed [PB-1:0] kp = pitch[PB-1:0];

    // the slot: phase ph, the primary part first (np clocks), then the shadow part; the
    // phase waits at 0 for the first ray, then runs every clock to the frame's end
    wire              rg_out_valid;
    reg               running;
    reg  [15:0]       ph;
    wire [15:0]       np = n_obj == 0 ? 16'd1 : {8'd0, n_obj};
    wire [15:0]       s_len = np + (sh_on ? {12'd0, n_l} * {8'd0, n_obj} : 16'd0);
    wire              in_primary = ph < np;
    wire              advance = ce && busy && (running || rg_out_valid);
    wire [KB-1:0]     pair_k = ph[KB-1:0];  // the primary part's object
    wire              last_pair = ph == np - 16'd1;
    // the generator's output is paired with objects; it advances with the last pair
    wire              rg_ce = ce && (!rg_out_valid || (advance && last_pair));
    wire              rg_in_valid = feeding && setup == 0;
    wire              isect_valid, isect_unsupported;
    wire              pix_valid_w;

    always @(posedge clk) begin
        if (rst) begin
            busy <= 1'b0;
            done <= 1'b0;
            err <= 8'd0;
            feeding <= 1'b0;
            setup <= 5'd0;
        end else begin
            done <= 1'b0;
            if (start && !busy) begin
                busy <= 1'b1;
                err <= start_err;
                n_obj <= obj_count > OBJ ? OBJ[KB-1:0] : obj_count[KB-1:0];
                n_l <= light_count == 0 ? 4'd0 :
                       light_count - 1 > LIGHTS ? LIGHTS[3:0] : light_count[3:0] - 4'd1;
                sh_on <= SHADOWS != 0 && (flags & `RT_FLAG_SHADOWS) != 0 && light_count > 1 &&
                         obj_count != 0;
                tmax <= f32_to_q16(max_f32);
                wm1 <= width - 16'd1;
                hm1 <= height - 16'd1;
                k2 <= kp <<< 1;
                xm <= 0;
                acc_y <= 0;
                col <= 16'd0;
                row <= 16'd0;
                pixels_out <= 32'd0;
                feeding <= width != 0 && height != 0;
                setup <= SETUP[4:0];
            end else if (busy && ce) begin
                if (setup > 5'd1) begin
                    // Horner: (W - 1) K and (H - 1) K, one bit of each per clock
                    xm <= (xm <<< 1) + (wm1[15] ? kp : 0);
                    acc_y <= (acc_y <<< 1) + (hm1[15] ? kp : 0);
                    wm1 <= wm1 << 1;
                    hm1 <= hm1 << 1;
                    setup <= setup - 5'd1;
                end else if (setup == 5'd1) begin
                    // column 0 lies at (1 - W) K
                    xm <= 0 - xm;
                    acc_x <= 0 - xm;
                    setup <= 5'd0;
                end else if (rg_ce && rg_in_valid) begin
                    if (col == width - 16'd1) begin
                        col <= 16'd0;
                        acc_x <= xm;
                        acc_y <= acc_y - k2;
                        if (row == height - 16'd1) feeding <= 1'b0;
                        else row <= row + 16'd1;
                    end else begin
                        col <= col + 16'd1;
                        acc_x <= acc_x + k2;
                    end
                end
                if (pix_valid_w) begin
                    pixels_out <= pixels_out + 32'd1;
                    if (pixels_out + 32'd1 == pixels) begin
                        busy <= 1'b0;
                        done <= 1'b1;
                    end
                end
                if (setup == 0 && pixels == 0) begin
                    busy <= 1'b0;
                    done <= 1'b1;
                end
                if (isect_valid && isect_unsupported) err[3] <= 1'b1;
            end
        end
    end

    // ---- primary rays ---------------------------------------------------------------
    wire [95:0] rd;
    wire [31:0] rg_tag;
    rt_raygen #(.PB(PB), .TB(32)) u_raygen (.clk(clk), .rst(rst), .ce(rg_ce),
        .in_valid(rg_in_valid), .px(acc_x), .py(acc_y),
        .ux(cu[31:0]), .uy(cu[63:32]), .uz(cu[95:64]),
        .vx(cv[31:0]), .vy(cv[63:32]), .vz(cv[95:64]),
        .wx(cw[31:0]), .wy(cw[63:32]), .wz(cw[95:64]),
        .tag({row, col}), .out_valid(rg_out_valid),
        .dx(rd[31:0]), .dy(rd[63:32]), .dz(rd[95:64]), .tag_out(rg_tag));

    // ---- pairs: the ray with objects 0 .. N-1, then a queued pixel's shadow rays -------------
    reg               sh_go;         // this slot's shadow part tests the queue's head
    reg  [KB-1:0]     sh_k;          // its object
    reg  [LB-1:0]     sh_l;          // and lane
    wire              shq_empty;
    wire [96*LIGHTS-1:0] shq_d;
    wire [32*LIGHTS-1:0] shq_tmax;
    wire [95:0]       shq_o;
    wire              sh_go_now = ph == np ? !shq_empty : sh_go;
    wire              is_sh = !in_primary && sh_go_now;
    wire              last_sh = {{(4 - LB){1'b0}}, sh_l} == n_l - 4'd1 && sh_k == n_obj - 1'b1;
    always @(posedge clk) begin
        if (rst || (start && !busy)) begin
            running <= 1'b0;
            ph <= 16'd0;
            sh_go <= 1'b0;
            sh_k <= {KB{1'b0}};
            sh_l <= {LB{1'b0}};
        end else if (advance) begin
            running <= 1'b1;
            ph <= ph == s_len - 16'd1 ? 16'd0 : ph + 16'd1;
            sh_go <= sh_go_now;
            if (in_primary || sh_k == n_obj - 1'b1) sh_k <= {KB{1'b0}};
            else sh_k <= sh_k + 1'b1;
            if (in_primary) sh_l <= {LB{1'b0}};
            else if (sh_k == n_obj - 1'b1) sh_l <= sh_l + 1'b1;
        end
    end
    always @(posedge clk) begin
        if (rst || (start && !busy)) rays <= 32'd0;
        else if (advance)
            rays <= rays + {31'd0, in_primary && last_pair && rg_out_valid} +
                    (is_sh && last_sh ? {28'd0, n_l} : 32'd0);
    end
    wire [KB-1:0] obj_k = is_sh ? sh_k : pair_k;
    wire [IB-1:0] obj_sel = obj_k[IB-1:0];  // < n_obj <= OBJ
    // pair tag: shadow pair, its lane, last pair of its ray (or of its pixel's shadow
    // rays), no object at all, object, pixel, world direction
    localparam integer PT = 1 + LB + 1 + 1 + KB + 32 + 96;
    wire [PT-1:0] pair_tag = {is_sh, sh_l, is_sh ? last_sh : last_pair, n_obj == 0, obj_k,
                              rg_tag, rd};
    wire [31:0]   pair_tmax = is_sh ? shq_tmax[32*sh_l +: 32] : tmax;
    wire          pair_valid = busy && (in_primary ? rg_out_valid : is_sh);
    wire          xf_valid;
    wire [95:0]   lo, ld;
    wire [PT+SB+31:0] xf_tag;
    rt_xform #(.TB(PT + SB + 32)) u_xform (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(pair_valid), .o(is_sh ? shq_o : eye), .d(is_sh ? shq_d[96*sh_l +: 96] : rd),
        .m(minv_k[obj_sel]), .t(trans_k[obj_sel]),
        .tag({pair_tmax, shape_k[obj_sel], pair_tag}), .out_valid(xf_valid), .lo(lo),
        .ld(ld), .tag_out(xf_tag));

    // ---- intersection -----------------------------------------------------------------
    localparam integer IT = PT + 192;
    wire          isect_hit;
    wire [31:0]   isect_t;
    wire [IT-1:0] it;
    rt_isect #(.SHAPES(SHAPES), .TB(IT)) u_isect (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(xf_valid), .shape(xf_tag[PT +: SB]),
        .ox(lo[31:0]), .oy(lo[63:32]), .oz(lo[95:64]),
        .dx(ld[31:0]), .dy(ld[63:32]), .dz(ld[95:64]),
        .tmin(bias), .tmax(xf_tag[PT + SB +: 32]), .tag({ld, lo, xf_tag[PT-1:0]}),
        .out_valid(isect_valid), .hit(isect_hit), .t(isect_t),
        .unsupported(isect_unsupported), .tag_out(it));
    wire          i_sh = it[PT-1];
    wire [LB-1:0] i_l = it[PT-2 -: LB];
    wire          i_last = it[PT-2-LB];
    wire          i_none = it[PT-3-LB];
    wire [KB-1:0] i_k = it[PT-4-LB -: KB];
    wire          i_prim = isect_valid && !i_sh;
    wire [31:0]   i_pix = it[127:96];
    wire [95:0]   i_d = it[95:0];
    wire [95:0]   i_lo = it[PT +: 96];
    wire [95:0]   i_ld = it[PT + 96 +: 96];

    // ---- nearest hit, in object order --------------------------------------------------
    reg           first = 1'b1;        // the next pair is its ray's first
    reg           found;
    reg [KB-1:0]  best_k;
    reg [31:0]    best_t;
    reg [95:0]    best_lo, best_ld;
    wire cand = isect_hit && !i_none && !isect_unsupported;
    wire take = cand && (first || !found || $signed(isect_t) <= $signed(best_t));
    wire          now_found = take || (!first && found);
    always @(posedge clk) begin
        if (rst) first <= 1'b1;
        else if (ce && i_prim) first <= i_last;
        if (ce && i_prim) begin
            found <= now_found;
            if (take) begin
                best_k <= i_k;
                best_t <= isect_t;
                best_lo <= i_lo;
                best_ld <= i_ld;
            end
        end
    end
    // the ray's result, one clock after its last pair
    reg           r_valid;
    reg [31:0]    r_pix;
    reg [95:0]    r_d;
    always @(posedge clk) begin
        if (rst) r_valid <= 1'b0;
        else if (ce) r_valid <= i_prim && i_last;
        if (ce) begin
            r_pix <= i_pix;
            r_d <= i_d;
        end
    end
    wire [IB-1:0] best_sel = best_k[IB-1:0];

    // ---- occlusion: a shadow pair that hits anything blocks its light ------------------------
    reg  [LIGHTS-1:0] occ_acc, occ_word;
    reg               occ_valid;
    wire [LIGHTS-1:0] occ_now = occ_acc |
        ({{(LIGHTS - 1){1'b0}}, isect_hit && !isect_unsupported} << i_l);
    always @(posedge clk) begin
        if (rst) begin
            occ_valid <= 1'b0;
            occ_acc <= {LIGHTS{1'b0}};
        end else if (ce) begin
            occ_valid <= isect_valid && i_sh && i_last;
            if (isect_valid && i_sh) occ_acc <= i_last ? {LIGHTS{1'b0}} : occ_now;
        end
        if (ce) occ_word <= occ_now;
    end

    // ---- the normal -------------------------------------------------------------------
    localparam integer NT = KB + 1 + 32 + 32 + 96;
    wire [NT-1:0] nt;
    wire [95:0]   nrm;
    wire          n_valid;
    rt_normal #(.TB(NT)) u_normal (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(r_valid), .shape(shape_k[best_sel]), .lo(best_lo), .ld(best_ld),
        .t(best_t), .m(minv_k[best_sel]), .d(r_d), .tag({best_k, found, best_t, r_pix, r_d}),
        .out_valid(n_valid), .n(nrm), .tag_out(nt));
    wire [95:0]   n_d = nt[95:0];
    wire [31:0]   n_t = nt[159:128];
    wire          n_hit = nt[160];
    wire [IB-1:0] n_sel = nt[161 +: IB];

    // ---- the colour, and the pixel ---------------------------------------------------------
    reg [96*LIGHTS-1:0] lane_pos, lane_col;
    reg [LIGHTS-1:0]    lane_lit;
    always @(*) begin
        for (j = 0; j < LIGHTS; j = j + 1) begin
            lane_pos[96*j +: 96] = lpos[j + 1];
            lane_col[96*j +: 96] = lcol[j + 1];
            lane_lit[j] = j + 1 < light_count;
        end
    end
    localparam integer ST = KB + 1 + 32 + 32 + 96;
    wire [ST-1:0] st;
    wire [23:0]   rgb;
    /* verilator lint_off PINCONNECTEMPTY */
    wire          sh_valid;
    wire [95:0]   sh_o;
    wire [96*LIGHTS-1:0] sh_d;
    wire [32*LIGHTS-1:0] sh_tmax;
    rt_shade #(.LIGHTS(LIGHTS), .TB(ST), .TQA(TQA), .OQA(OQA)) u_shade (.clk(clk), .rst(rst),
        .ce(ce),
        .in_valid(n_valid), .hit(n_hit), .eye(eye), .d(n_d), .t(n_t), .n(nrm),
        .ka(ka_k[n_sel]), .ca(ca_k[n_sel]), .kd(kd_k[n_sel]), .cd(cd_k[n_sel]),
        .ks(ks_k[n_sel]), .cs(cs_k[n_sel]), .e(e_k[n_sel]), .la(lcol[0]),
        .background(background), .lit(lane_lit), .lights(lane_pos), .colours(lane_col),
        .bias(bias), .shadows(sh_on), .tag({nt[NT-1:96], nrm}), .sh_valid(sh_valid),
        .sh_o(sh_o), .sh_d(sh_d), .sh_tmax(sh_tmax), .occ_valid(occ_valid), .occ(occ_word),
        .out_valid(pix_valid_w), .colour(), .rgb(rgb), .tag_out(st));

    // the shadow rays wait for their slot
    /* verilator lint_off PINCONNECTEMPTY */
    rt_fifo #(.W(96 + 128 * LIGHTS), .AW(SQA)) u_shq (.clk(clk), .rst(rst),
        .push(ce && sh_valid), .din({sh_o, sh_d, sh_tmax}), .pop(advance && is_sh && last_sh),
        .dout({shq_o, shq_d, shq_tmax}), .empty(shq_empty), .count(), .ovf(), .unf());
    /* verilator lint_on PINCONNECTEMPTY */
    assign pix_valid = pix_valid_w;
    assign pix_x = st[111:96];
    assign pix_y = st[127:112];
    assign pix_t = st[159:128];
    assign pix_hit = st[160];
    assign pix_obj = st[161 +: KB];
    assign pix_n = pix_hit ? st[95:0] : 96'd0;
    assign pix_rgb = rgb;
    // ViRAY's 16-bit mode on the KCU116 (sim-target's `pack_kcu116`): G and B at even x,
    // G and R at odd x
    assign pix_kcu116 = {rgb[15:8], pix_x[0] ? rgb[23:16] : rgb[7:0]};
endmodule
`default_nettype wire
