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
// stage L_WI for the caller to test against every object (rt_cast); the hit point p is
// out at stage L_P (its origin is p + n.scale(bias), which every lane shares: rt_shade).
//
// Ports: eye, d, t (the primary ray and its hit distance), n (the shading normal), light
// (position), colour, kdcd (k_d c_d), kscs (k_s c_s), e (exponent); tag (TB bits
// alongside); in_valid / out_valid; term; p (stage L_P), wi and extent = dist (stage
// L_WI). ce low holds every stage.
// Timing, with D = Q_DOT_LAT = 4 (q16_lat.vh): p at L_P = D + 1 = 5, wi at
// L_WI = 2 + 3 D + 79 = 93 (to_l 1, dist2 D, rsqrt 79, wi D), the term at
// LATENCY = 243 (then the highlight's normalise 1 + Q_NORM3_LAT, n.h D + 1, power 10 D,
// norm D, kscs D, sum 1, colour D, g D); one hit per clock.
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

    `include "rt_light.vh"
    localparam integer D = Q_DOT_LAT;
    localparam integer LATENCY = L_LAT;
    // 1/pi rounded to Q16.16 (the model's S::from_f64(FRAC_1_PI))
    localparam [31:0] INV_PI = 32'd20861;
    // round(2^56 / (2 pi)): norm = ((e + 2) * C + 2^39) >> 40
    localparam [53:0] NORM_C = 54'h28be60db939105;

    // what the later stages read, carried from the input: n, -d, the material and the
    // light's colour (the same words for the whole pass, but a pipeline takes them along)
    localparam integer CW = 96 + 96 + 96 + 96 + 96 + 10;
    wire [CW-1:0] ctx_in = {n, q_neg(d[95:64]), q_neg(d[63:32]), q_neg(d[31:0]), kdcd, kscs,
                            colour, e};

    // ---- L_P: p = eye + d * t ---------------------------------------------------------
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
    wire [191:0] el_dt;  // eye and light beside d * t
    dly #(.W(192), .N(D)) u_el_dt (.clk(clk), .rst(rst), .ce(ce), .d({light, eye}), .q(el_dt));
    reg [95:0] p_p, light_p;
    always @(posedge clk) begin
        if (ce) begin
            p_p <= {q_add(el_dt[95:64], dt[95:64]), q_add(el_dt[63:32], dt[63:32]),
                   q_add(el_dt[31:0], dt[31:0])};
            light_p <= el_dt[191:96];
        end
    end

    assign p = p_p;

    // ---- L_TL: to_l = light - p; L_D2: dist2 ------------------------------------------------
    reg [95:0] tl;
    always @(posedge clk) begin
        if (ce) begin
            tl <= {q_sub(light_p[95:64], p_p[95:64]), q_sub(light_p[63:32], p_p[63:32]),
                    q_sub(light_p[31:0], p_p[31:0])};
        end
    end
    wire [31:0] dist2;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(3), .ROUND(1)) u_dist2 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(tl), .b(tl), .out_valid(), .y(dist2), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [95:0] tl_d2;
    dly #(.W(96), .N(D)) u_tl_d2 (.clk(clk), .rst(rst), .ce(ce), .d(tl), .q(tl_d2));

    // ---- L_INV: 1/sqrt(dist2); L_WI: wi ---------------------------------------------------
    wire [31:0] inv;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_rsqrt u_inv (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .x(dist2),
        .out_valid(), .y(inv), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [127:0] td_inv;  // to_l and dist2 at L_INV
    dly #(.W(128), .N(Q_RSQRT_LAT)) u_td_inv (.clk(clk), .rst(rst), .ce(ce), .d({dist2, tl_d2}),
        .q(td_inv));
    generate
        for (c = 0; c < 3; c = c + 1) begin : direction
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_wi (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(td_inv[32*c +: 32]), .b(inv), .out_valid(),
                .y(wi[32*c +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    // the shadow ray's extent
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(1), .ROUND(0)) u_dist (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(td_inv[127:96]), .b(inv), .out_valid(), .y(extent), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [31:0] dist2_wi;
    dly #(.W(32), .N(D)) u_d_wi (.clk(clk), .rst(rst), .ce(ce), .d(td_inv[127:96]),
        .q(dist2_wi));
    wire [CW-1:0] ctx_wi;
    dly #(.W(CW), .N(L_WI)) u_ctx_wi (.clk(clk), .rst(rst), .ce(ce), .d(ctx_in), .q(ctx_wi));
    wire [95:0] n_wi = ctx_wi[CW-1 -: 96];
    wire [95:0] wo_wi = ctx_wi[CW-97 -: 96];

    // ---- L_NDL: ndl = n.wi; L_G: g = ndl / dist2 -----------------------------------
    wire [31:0] ndl;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(3), .ROUND(1)) u_ndl (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(n_wi), .b(wi), .out_valid(), .y(ndl), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [31:0] dist2_ndl;
    dly #(.W(32), .N(D)) u_d_ndl (.clk(clk), .rst(rst), .ce(ce), .d(dist2_wi), .q(dist2_ndl));
    wire [31:0] g;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_div u_g (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .a(ndl), .b(dist2_ndl),
        .out_valid(), .y(g), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    // the light counts when dist2 > 0 and ndl > 0
    wire lit_ndl = $signed(dist2_ndl) > 0 && $signed(ndl) > 0;

    // ---- L_WI + 1: wi + wo; L_H: h; L_NH: max(n.h, 0) ---------------------------
    reg [95:0] hs;
    always @(posedge clk) begin
        if (ce) begin
            hs <= {q_add(wi[95:64], wo_wi[95:64]), q_add(wi[63:32], wo_wi[63:32]),
                     q_add(wi[31:0], wo_wi[31:0])};
        end
    end
    wire [95:0] h;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_norm3 #(.TB(1)) u_h (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .x(hs[31:0]), .y(hs[63:32]), .z(hs[95:64]), .tag(1'b0), .out_valid(),
        .nx(h[31:0]), .ny(h[63:32]), .nz(h[95:64]), .tag_out());
    /* verilator lint_on PINCONNECTEMPTY */
    // n, the material, the colour and e at L_H (wo is used up)
    wire [393:0] ctx_h;
    dly #(.W(394), .N(L_H - L_WI)) u_ctx_h (.clk(clk), .rst(rst), .ce(ce),
        .d({n_wi, ctx_wi[297:0]}), .q(ctx_h));
    wire [31:0] nh;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(3), .ROUND(1)) u_nh (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(ctx_h[393 -: 96]), .b(h), .out_valid(), .y(nh), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    reg [31:0] nh_pos;
    always @(posedge clk) if (ce) nh_pos <= nh[31] ? 32'd0 : nh;
    // the material, the colour and e at L_NH (n and wo are used up)
    wire [297:0] ctx_nh;
    dly #(.W(298), .N(L_NH - L_H)) u_ctx_nh (.clk(clk), .rst(rst), .ce(ce), .d(ctx_h[297:0]),
        .q(ctx_nh));

    // ---- nh^e; L_FS: fs = norm * nh^e ---------------------------------------
    wire [31:0] pw;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_powi #(.TB(1)) u_pow (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .x(nh_pos),
        .e(ctx_nh[9:0]), .tag(1'b0), .out_valid(), .y(pw), .tag_out());
    /* verilator lint_on PINCONNECTEMPTY */
    // norm from the exponent, formed beside the power and waiting for it
    wire [66:0] norm_wide = ({57'd0, ctx_nh[9:0]} + 67'd2) * {13'd0, NORM_C} + (67'd1 << 39);
    /* verilator lint_off UNUSEDSIGNAL */
    wire [66:0] norm_bits = norm_wide;  // (1025 C) >> 40 < 2^24: bits 40 .. 63 suffice
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] norm_pw;
    dly #(.W(32), .N(Q_POWI_LAT)) u_norm (.clk(clk), .rst(rst), .ce(ce),
        .d({8'd0, norm_bits[63:40]}), .q(norm_pw));
    wire [31:0] fs;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(1), .ROUND(0)) u_fs (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(norm_pw), .b(pw), .out_valid(), .y(fs), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    // the material and the colour at L_FS (n, wo and e are used up)
    wire [287:0] mc_fs;
    dly #(.W(288), .N(L_FS - L_NH)) u_mc_fs (.clk(clk), .rst(rst), .ce(ce), .d(ctx_nh[297:10]),
        .q(mc_fs));
    wire [95:0] kdcd_fs = mc_fs[287 -: 96];
    wire [95:0] kscs_fs = mc_fs[191 -: 96];
    wire [95:0] col_fs = mc_fs[95 -: 96];

    // ---- kdcd / pi and kscs * fs; L_BRDF: brdf ------------------------------------
    wire [95:0] dterm, sterm;
    generate
        for (c = 0; c < 3; c = c + 1) begin : brdf_terms
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_d (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(kdcd_fs[32*c +: 32]), .b(INV_PI), .out_valid(),
                .y(dterm[32*c +: 32]), .sat());
            q16_dot #(.TERMS(1), .ROUND(1)) u_s (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(kscs_fs[32*c +: 32]), .b(fs), .out_valid(),
                .y(sterm[32*c +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    reg [95:0] brdf;
    always @(posedge clk) begin
        if (ce) begin
            brdf <= {q_add(dterm[95:64], sterm[95:64]), q_add(dterm[63:32], sterm[63:32]),
                        q_add(dterm[31:0], sterm[31:0])};
        end
    end
    wire [95:0] col_brdf;
    dly #(.W(96), .N(L_BRDF - L_FS)) u_col_brdf (.clk(clk), .rst(rst), .ce(ce),
        .d(col_fs), .q(col_brdf));

    // ---- brdf * colour; LATENCY: * g -----------------------------------------
    wire [95:0] bc;
    wire [32:0] gl_bc;  // g and "lit" beside brdf * colour
    dly #(.W(33), .N(L_BRDF + D - L_G)) u_gl (.clk(clk), .rst(rst), .ce(ce), .d({lit_g, g}),
        .q(gl_bc));
    wire [95:0] raw;
    generate
        for (c = 0; c < 3; c = c + 1) begin : colour_terms
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_c (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(brdf[32*c +: 32]), .b(col_brdf[32*c +: 32]),
                .out_valid(), .y(bc[32*c +: 32]), .sat());
            q16_dot #(.TERMS(1), .ROUND(1)) u_g (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(bc[32*c +: 32]), .b(gl_bc[31:0]), .out_valid(),
                .y(raw[32*c +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    wire lit_term;
    dly #(.W(1), .N(D)) u_lit_term (.clk(clk), .rst(rst), .ce(ce), .d(gl_bc[32]), .q(lit_term));
    assign term = lit_term ? raw : 96'd0;

    wire lit_g;
    dly #(.W(1), .N(Q_DIV_LAT)) u_lit_g (.clk(clk), .rst(rst), .ce(ce), .d(lit_ndl), .q(lit_g));

    dly #(.W(1), .N(LATENCY), .RESET(1)) u_valid (.clk(clk), .rst(rst), .ce(ce),
        .d(in_valid), .q(out_valid));
    dly #(.W(TB), .N(LATENCY)) u_tag (.clk(clk), .rst(rst), .ce(ce), .d(tag), .q(tag_out));
endmodule
`default_nettype wire
