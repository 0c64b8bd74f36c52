// rt_light -- one point light's term at a hit, as the golden model's light loop in
// `trace` computes it for a Lambert material with an optional Blinn-Phong highlight
// (sim-target/src/rt/kernel.rs, shade.rs; seed 002 §3.5, eq. 3.2.8-3.2.10), bit for bit:
//
//   p = eye + d.scale(t)                 to_l = light - p        dist2 = to_l.to_l
//   wi = to_l.scale(rsqrt(dist2))        ndl = n.wi              g = ndl / dist2
//   h = (wi + wo).normalize()  (wo = -d) nh = max(n.h, 0)        fs = norm * nh^e
//   brdf = kdcd.scale(1/pi) + kscs.scale(fs)
//   term = brdf.hadamard(colour).scale(g), or 0 when dist2 <= 0 or ndl <= 0
//
// `.` is `dot3`, `scale` and `hadamard` are `mul_rn` per component, `*` the floored
// product, sums saturating. The model skips a light whose dist2 or ndl is not positive;
// adding a zero term instead is the same (a saturating sum with 0 is the identity), so
// every lane always produces a term. With no highlight the material's kscs is 0, and
// kscs.scale(fs) = 0 likewise. norm = (e + 2) / (2 pi) rounded to Q16.16 is formed from
// the exponent as ((e + 2) * C + 2^39) >> 40 with C = round(2^56 / (2 pi)), which equals
// the model's f64 value for every e in 0..1023 (sim-target's test
// `blinn_phong_norm_is_an_integer_formula` enumerates them).
//
// The shadow ray towards the light is a by-product: its direction is wi and its extent
// dist = dist2 * (1/sqrt(dist2)) (the model's `dist2 * inv_dist`, floored), both out at
// stage 87 for the caller to test against every object (rt_cast); the hit point p is out
// at stage 3 (its origin is p + n.scale(bias), which every lane shares: rt_shade).
//
// Ports: eye, d, t (the primary ray and its hit distance), n (the shading normal), light
// (position), colour, kdcd (k_d c_d), kscs (k_s c_s), e (exponent); tag (TB bits
// alongside); in_valid / out_valid; term; p (stage 3), wi and extent = dist (stage 87). ce low
// holds every stage.
// Timing: latency 203 (p 3, to_l 1, dist2 2, rsqrt 79, wi 2, then the highlight's
// normalise 1 + 83, n.h 2 + 1, power 20, norm 2, kscs 2, sum 1, colour 2, g 2), one hit
// per clock.
// Parameters: TB >= 1.
`default_nettype none
module rt_light #(
    parameter integer TB = 1
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          ce,
    input  wire          in_valid,
    input  wire [95:0]   eye,
    input  wire [95:0]   d,
    input  wire [31:0]   t,
    input  wire [95:0]   n,
    input  wire [95:0]   light,
    input  wire [95:0]   colour,
    input  wire [95:0]   kdcd,
    input  wire [95:0]   kscs,
    input  wire [9:0]    e,
    input  wire [TB-1:0] tag,
    output wire          out_valid,
    output wire [95:0]   term,
    output wire [TB-1:0] tag_out,
    output wire [95:0]   p,
    output wire [95:0]   wi,
    output wire [31:0]   extent
);
    generate
        if (TB < 1) begin : bad_parameter
            rt_light_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "q16_ops.vh"

    localparam integer LATENCY = 203;
    // 1/pi rounded to Q16.16 (the model's S::from_f64(FRAC_1_PI))
    localparam [31:0] INV_PI = 32'd20861;
    // round(2^56 / (2 pi)): norm = ((e + 2) * C + 2^39) >> 40
    localparam [53:0] NORM_C = 54'h28be60db939105;

    // what the later stages read, carried from the input: n, -d, the material and the
    // light's colour (the same words for the whole pass, but a pipeline takes them along)
    localparam integer CW = 96 + 96 + 96 + 96 + 96 + 10;
    wire [CW-1:0] ctx_in = {n, q_neg(d[95:64]), q_neg(d[63:32]), q_neg(d[31:0]), kdcd, kscs,
                            colour, e};

    // ---- 0-3: p = eye + d * t ------------------------------------------------------------
    wire [95:0] dt;
    genvar c;
    generate
        for (c = 0; c < 3; c = c + 1) begin : hit_point
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_dt (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(d[32*c +: 32]), .b(t), .out_valid(), .y(dt[32*c +: 32]),
                .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    wire [191:0] el2;  // eye and light at stage 2
    dly #(.W(192), .N(2)) u_el2 (.clk(clk), .rst(rst), .ce(ce), .d({light, eye}), .q(el2));
    reg [95:0] p3, light3;
    always @(posedge clk) begin
        if (ce) begin
            p3 <= {q_add(el2[95:64], dt[95:64]), q_add(el2[63:32], dt[63:32]),
                   q_add(el2[31:0], dt[31:0])};
            light3 <= el2[191:96];
        end
    end

    assign p = p3;

    // ---- 4: to_l = light - p; 5-6: dist2 ---------------------------------------------------
    reg [95:0] tl4;
    always @(posedge clk) begin
        if (ce) begin
            tl4 <= {q_sub(light3[95:64], p3[95:64]), q_sub(light3[63:32], p3[63:32]),
                    q_sub(light3[31:0], p3[31:0])};
        end
    end
    wire [31:0] dist2;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(3), .ROUND(1)) u_dist2 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(tl4), .b(tl4), .out_valid(), .y(dist2), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [95:0] tl6;
    dly #(.W(96), .N(2)) u_tl6 (.clk(clk), .rst(rst), .ce(ce), .d(tl4), .q(tl6));

    // ---- 7-85: 1/sqrt(dist2); 86-87: wi ------------------------------------------------------
    wire [31:0] inv;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_rsqrt u_inv (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .x(dist2),
        .out_valid(), .y(inv), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [127:0] td85;  // to_l and dist2 at stage 85
    dly #(.W(128), .N(79)) u_td85 (.clk(clk), .rst(rst), .ce(ce), .d({dist2, tl6}),
        .q(td85));
    generate
        for (c = 0; c < 3; c = c + 1) begin : direction
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_wi (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(td85[32*c +: 32]), .b(inv), .out_valid(),
                .y(wi[32*c +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    // the shadow ray's extent
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(1), .ROUND(0)) u_dist (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(td85[127:96]), .b(inv), .out_valid(), .y(extent), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [31:0] dist2_87;
    dly #(.W(32), .N(2)) u_d87 (.clk(clk), .rst(rst), .ce(ce), .d(td85[127:96]),
        .q(dist2_87));
    wire [CW-1:0] ctx87;
    dly #(.W(CW), .N(87)) u_ctx87 (.clk(clk), .rst(rst), .ce(ce), .d(ctx_in), .q(ctx87));
    wire [95:0] n87 = ctx87[CW-1 -: 96];
    wire [95:0] wo87 = ctx87[CW-97 -: 96];

    // ---- 88-89: ndl = n.wi; 90-123: g = ndl / dist2 --------------------------------------
    wire [31:0] ndl;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(3), .ROUND(1)) u_ndl (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(n87), .b(wi), .out_valid(), .y(ndl), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [31:0] dist2_89;
    dly #(.W(32), .N(2)) u_d89 (.clk(clk), .rst(rst), .ce(ce), .d(dist2_87), .q(dist2_89));
    wire [31:0] g;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_div u_g (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .a(ndl), .b(dist2_89),
        .out_valid(), .y(g), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    // the light counts when dist2 > 0 and ndl > 0
    wire lit89 = $signed(dist2_89) > 0 && $signed(ndl) > 0;

    // ---- 88: wi + wo; 89-171: h; 172-173: n.h; 174: max(., 0) ------------------------------
    reg [95:0] hs88;
    always @(posedge clk) begin
        if (ce) begin
            hs88 <= {q_add(wi[95:64], wo87[95:64]), q_add(wi[63:32], wo87[63:32]),
                     q_add(wi[31:0], wo87[31:0])};
        end
    end
    wire [95:0] h;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_norm3 #(.TB(1)) u_h (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .x(hs88[31:0]), .y(hs88[63:32]), .z(hs88[95:64]), .tag(1'b0), .out_valid(),
        .nx(h[31:0]), .ny(h[63:32]), .nz(h[95:64]), .tag_out());
    /* verilator lint_on PINCONNECTEMPTY */
    // n, the material, the colour and e at 171 (wo is used up)
    wire [393:0] ctx171;
    dly #(.W(394), .N(84)) u_ctx171 (.clk(clk), .rst(rst), .ce(ce),
        .d({n87, ctx87[297:0]}), .q(ctx171));
    wire [31:0] nh;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(3), .ROUND(1)) u_nh (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(ctx171[393 -: 96]), .b(h), .out_valid(), .y(nh), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    reg [31:0] nh174;
    always @(posedge clk) if (ce) nh174 <= nh[31] ? 32'd0 : nh;
    // the material, the colour and e at 174 (n and wo are used up)
    wire [297:0] ctx174;
    dly #(.W(298), .N(3)) u_ctx174 (.clk(clk), .rst(rst), .ce(ce), .d(ctx171[297:0]),
        .q(ctx174));

    // ---- 175-194: nh^e; 195-196: fs = norm * nh^e ------------------------------------------
    wire [31:0] pw;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_powi #(.TB(1)) u_pow (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .x(nh174),
        .e(ctx174[9:0]), .tag(1'b0), .out_valid(), .y(pw), .tag_out());
    /* verilator lint_on PINCONNECTEMPTY */
    // norm from the exponent, formed beside the power and waiting for it
    wire [66:0] norm_wide = ({57'd0, ctx174[9:0]} + 67'd2) * {13'd0, NORM_C} + (67'd1 << 39);
    /* verilator lint_off UNUSEDSIGNAL */
    wire [66:0] norm_bits = norm_wide;  // (1025 C) >> 40 < 2^24: bits 40 .. 63 suffice
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] norm194;
    dly #(.W(32), .N(20)) u_norm (.clk(clk), .rst(rst), .ce(ce),
        .d({8'd0, norm_bits[63:40]}), .q(norm194));
    wire [31:0] fs;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(1), .ROUND(0)) u_fs (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(norm194), .b(pw), .out_valid(), .y(fs), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    // the material and the colour at 196 (n, wo and e are used up)
    wire [287:0] mc196;
    dly #(.W(288), .N(22)) u_mc196 (.clk(clk), .rst(rst), .ce(ce), .d(ctx174[297:10]),
        .q(mc196));
    wire [95:0] kdcd196 = mc196[287 -: 96];
    wire [95:0] kscs196 = mc196[191 -: 96];
    wire [95:0] col196 = mc196[95 -: 96];

    // ---- 197-198: kdcd / pi and kscs * fs; 199: brdf ---------------------------------------
    wire [95:0] dterm, sterm;
    generate
        for (c = 0; c < 3; c = c + 1) begin : brdf_terms
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_d (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(kdcd196[32*c +: 32]), .b(INV_PI), .out_valid(),
                .y(dterm[32*c +: 32]), .sat());
            q16_dot #(.TERMS(1), .ROUND(1)) u_s (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(kscs196[32*c +: 32]), .b(fs), .out_valid(),
                .y(sterm[32*c +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    reg [95:0] brdf199;
    always @(posedge clk) begin
        if (ce) begin
            brdf199 <= {q_add(dterm[95:64], sterm[95:64]), q_add(dterm[63:32], sterm[63:32]),
                        q_add(dterm[31:0], sterm[31:0])};
        end
    end
    wire [95:0] col199;
    dly #(.W(96), .N(3)) u_col199 (.clk(clk), .rst(rst), .ce(ce), .d(col196), .q(col199));

    // ---- 200-201: brdf * colour; 202-203: * g --------------------------------------------
    wire [95:0] bc;
    wire [32:0] gl201;  // g and "lit" at stage 201
    dly #(.W(33), .N(201 - 123)) u_gl (.clk(clk), .rst(rst), .ce(ce), .d({lit123, g}),
        .q(gl201));
    wire [95:0] raw;
    generate
        for (c = 0; c < 3; c = c + 1) begin : colour_terms
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_c (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(brdf199[32*c +: 32]), .b(col199[32*c +: 32]),
                .out_valid(), .y(bc[32*c +: 32]), .sat());
            q16_dot #(.TERMS(1), .ROUND(1)) u_g (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(bc[32*c +: 32]), .b(gl201[31:0]), .out_valid(),
                .y(raw[32*c +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    wire lit203;
    dly #(.W(1), .N(2)) u_lit203 (.clk(clk), .rst(rst), .ce(ce), .d(gl201[32]), .q(lit203));
    assign term = lit203 ? raw : 96'd0;

    wire lit123;
    dly #(.W(1), .N(34)) u_lit123 (.clk(clk), .rst(rst), .ce(ce), .d(lit89), .q(lit123));

    dly #(.W(1), .N(LATENCY), .RESET(1)) u_valid (.clk(clk), .rst(rst), .ce(ce),
        .d(in_valid), .q(out_valid));
    dly #(.W(TB), .N(LATENCY)) u_tag (.clk(clk), .rst(rst), .ce(ce), .d(tag), .q(tag_out));
endmodule
`default_nettype wire
