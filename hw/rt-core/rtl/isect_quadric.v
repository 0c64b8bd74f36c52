// isect_quadric -- the curved shapes' ray intersection (sphere, open cylinder, open
// cone) in object space, one (ray, object) pair per clock: the golden model's
// `shapes::sphere`, `cylinder` and `cone` with the stable root formula
// (sim-target/src/rt/shapes.rs), bit for bit.
//
// Why one module for three shapes: each forms a quadratic a t^2 + 2h t + c = 0 and its
// quarter discriminant by Lagrange's identity (a sum of squares of cross-product terms,
// not the difference h^2 - ac of two large numbers), then solves it the same way; only
// the front (a, h, c, disc) and the back (the cylinder's and cone's height test) differ.
// A pair is one shape, so the shared middle -- the early rejection, the root, the two
// quotients -- serves all three. Seed 002 §3.4 intersects in object space after the
// inverse transform, as here; its textbook root formula is the model's `Textbook`
// option, not built.
//
// The model's steps, in order, each rounded as the model rounds it (q16_dot, q16_ops.vh):
//   front     sphere:   a = d.d, h = d.o, c = o.o - 1, disc = a - |d x o|^2 (cross2)
//             cylinder: a = dx*dx + dz*dz (no hit when a = 0), h = dot2(d, o) in x-z,
//                       c = ox*ox + oz*oz - 1, disc = a - x*x, x = dot2(dx, oz, -dz, ox)
//             cone:     p = o - (0, 1, 0), metric (1, -1, 1): a = dx*dx - dy*dy + dz*dz,
//                       h = dot3(d, p), c = dot3(p, p), disc = xy^2 + yz^2 - xz^2
//   reject    h*h - a*c < -((h*h + |a*c|) * 2^-8 + 2^-6)   (`clearly_misses`)
//   solve     a = 0: none if h = 0, else t1 = t2 = -c / (h + h); disc < 0: none;
//             q = h < 0 ? sqrt(disc) - h : -(h + sqrt(disc)); q = 0: t1 = t2 = 0;
//             else t1 = q / a, t2 = c / q; then in ascending order
//   pick      the first of t1, t2 in [tmin, tmax] (cylinder y in [-1, 1], cone y in
//             [0, 1], y = oy + dy * t)
//
// Ports: shape (rt_map.vh codes; a code this module does not build gives no hit),
// o, d (object-space ray, Q16.16), tmin, tmax; hit and t at LAT.
// Timing: latency LAT_QUADRIC = 81 (isect.vh: front Q_DOT_LAT + 2, disc 2 Q_DOT_LAT + 1,
// root Q_SQRT_LAT, quotients 3 + Q_DIV_LAT, roots in order 1, height Q_DOT_LAT + 2), one
// pair per clock; ce low holds everything. The rejection runs beside the root. No clock
// holds more than one saturating operation (an adder and its clip) before a comparison
// or a register: two of them in series, each a carry chain and a multiplexer, are about
// 10 ns on an ECP5.
// Parameters: SPHERE, CYLINDER, CONE: 1 builds the shape's front (and the height test
// for the last two).
`default_nettype none
`include "rt_map.vh"
module isect_quadric #(
    parameter integer SPHERE = 1,
    parameter integer CYLINDER = 1,
    parameter integer CONE = 1
) (
    input  wire                      clk,
    input  wire                      rst,
    input  wire                      ce,
    input  wire [`RT_SHAPE_BITS-1:0] shape,
    input  wire [31:0]               ox,
    input  wire [31:0]               oy,
    input  wire [31:0]               oz,
    input  wire [31:0]               dx,
    input  wire [31:0]               dy,
    input  wire [31:0]               dz,
    input  wire [31:0]               tmin,
    input  wire [31:0]               tmax,
    output reg                       hit,
    output reg  [31:0]               t
);
    `include "q16_ops.vh"

    generate
        if ((SPHERE != 0 && SPHERE != 1) || (CYLINDER != 0 && CYLINDER != 1)
                || (CONE != 0 && CONE != 1)) begin : bad_parameter
            isect_quadric_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "isect.vh"
    localparam integer SB = `RT_SHAPE_BITS;
    localparam integer D = Q_DOT_LAT;
    // the schedule: the stage each value is registered at
    localparam integer T_F = D + 2;                 // a, h, c, "no hit"
    localparam integer T_DISC = 2 * D + 1;          // the quarter discriminant
    localparam integer T_MISS = T_F + 2 * D + 5;    // clearly_misses
    localparam integer T_SQ = T_DISC + Q_SQRT_LAT;  // sqrt(disc)
    localparam integer T_QIN = T_SQ + 3;            // the quotients' operands
    localparam integer T_T = T_QIN + Q_DIV_LAT;     // the quotients
    localparam integer T_R = T_T + 1;               // the roots in order
    localparam integer T_Y = T_R + D + 1;           // their heights
    generate
        if (T_Y + 1 != LAT_QUADRIC || T_MISS >= T_T) begin : bad_schedule
            isect_quadric_schedule_differs_from_isect_vh unsupported();
        end
    endgenerate

    // The shape code at the stages that decide by it.
    wire [SB-1:0] shape_f, shape_disc, shape_y;
    dly #(.W(SB), .N(T_F)) d_shape_f (.clk(clk), .rst(rst), .ce(ce), .d(shape), .q(shape_f));
    dly #(.W(SB), .N(T_DISC - T_F)) d_shape_disc (.clk(clk), .rst(rst), .ce(ce),
        .d(shape_f), .q(shape_disc));
    dly #(.W(SB), .N(T_Y - T_DISC)) d_shape_y (.clk(clk), .rst(rst), .ce(ce),
        .d(shape_disc), .q(shape_y));

    // ---- fronts: a, h, c and "no hit" at T_F (two clocks after the products: no clock
    // holds two saturating operations), disc at T_DISC -------------------------------
    /* verilator lint_off PINCONNECTEMPTY */
    wire [31:0] a_s, h_s, c_s, disc_s;
    wire [31:0] a_c, h_c, c_c, disc_c;
    wire [31:0] a_k, h_k, c_k, disc_k;
    wire        none_c;

    generate
        if (SPHERE != 0) begin : sphere
            wire [31:0] a_p, h_p, oo_p, x0, x1, x2, xx2;
            q16_dot #(.TERMS(3), .ROUND(1)) u_a (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({dz, dy, dx}), .b({dz, dy, dx}), .out_valid(), .y(a_p), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_h (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({dz, dy, dx}), .b({oz, oy, ox}), .out_valid(), .y(h_p), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_oo (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({oz, oy, ox}), .b({oz, oy, ox}),
                .out_valid(), .y(oo_p), .sat());
            // d x o, each component one rounding (cross2)
            q16_dot #(.TERMS(2), .ROUND(1)) u_x0 (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(dz), dy}), .b({oy, oz}), .out_valid(), .y(x0), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_x1 (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(dx), dz}), .b({oz, ox}), .out_valid(), .y(x1), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_x2 (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(dy), dx}), .b({ox, oy}), .out_valid(), .y(x2), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_xx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({x2, x1, x0}), .b({x2, x1, x0}), .out_valid(), .y(xx2), .sat());
            reg [31:0] a1, h1, c1, a_f, h_f, c_f, disc;
            // a beside |d x o|^2
            wire [31:0] a_disc;
            dly #(.W(32), .N(T_DISC - 1 - T_F)) d_a (.clk(clk), .rst(rst), .ce(ce), .d(a_f),
                .q(a_disc));
            always @(posedge clk) if (ce) begin
                a1 <= a_p;
                h1 <= h_p;
                c1 <= q_sub(oo_p, Q_ONE);
                a_f <= a1;
                h_f <= h1;
                c_f <= c1;
                disc <= q_sub(a_disc, xx2);
            end
            assign a_s = a_f;
            assign h_s = h_f;
            assign c_s = c_f;
            assign disc_s = disc;
        end else begin : no_sphere
            assign a_s = 32'd0;
            assign h_s = 32'd0;
            assign c_s = 32'd0;
            assign disc_s = 32'd0;
        end

        if (CYLINDER != 0) begin : cylinder
            wire [31:0] dxx_p, dzz_p, oxx_p, ozz_p, h_p, x_p, xx_p;
            q16_dot #(.TERMS(1), .ROUND(0)) u_dxx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dx), .b(dx), .out_valid(), .y(dxx_p), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_dzz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dz), .b(dz), .out_valid(), .y(dzz_p), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_oxx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(ox), .b(ox), .out_valid(), .y(oxx_p), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_ozz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(oz), .b(oz), .out_valid(), .y(ozz_p), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_h (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({dz, dx}), .b({oz, ox}), .out_valid(), .y(h_p), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_x (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(dz), dx}), .b({ox, oz}), .out_valid(), .y(x_p), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_xx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(x_p), .b(x_p), .out_valid(), .y(xx_p), .sat());
            reg [31:0] a1, h1, o1, a_f, h_f, c_f, disc;
            // a beside x*x
            wire [31:0] a_disc;
            dly #(.W(32), .N(T_DISC - 1 - T_F)) d_a (.clk(clk), .rst(rst), .ce(ce), .d(a_f),
                .q(a_disc));
            always @(posedge clk) if (ce) begin
                a1 <= q_add(dxx_p, dzz_p);
                h1 <= h_p;
                o1 <= q_add(oxx_p, ozz_p);
                a_f <= a1;
                h_f <= h1;
                c_f <= q_sub(o1, Q_ONE);
                disc <= q_sub(a_disc, xx_p);
            end
            assign a_c = a_f;
            assign h_c = h_f;
            assign c_c = c_f;
            assign disc_c = disc;
            // parallel to the axis: the open tube is never crossed
            assign none_c = a_f == 32'd0;
        end else begin : no_cylinder
            assign a_c = 32'd0;
            assign h_c = 32'd0;
            assign c_c = 32'd0;
            assign disc_c = 32'd0;
            assign none_c = 1'b1;
        end

        if (CONE != 0) begin : cone
            // from the apex: p = o - (0, 1, 0)
            wire [31:0] py = q_sub(oy, Q_ONE);
            wire [31:0] ndy = q_neg(dy);
            wire [31:0] ndz = q_neg(dz);
            wire [31:0] dxx_p, dyy_p, dzz_p, h_p, c_p, xy_p, yz_p, xz_p, disc_p;
            q16_dot #(.TERMS(1), .ROUND(0)) u_dxx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dx), .b(dx), .out_valid(), .y(dxx_p), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_dyy (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dy), .b(dy), .out_valid(), .y(dyy_p), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_dzz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dz), .b(dz), .out_valid(), .y(dzz_p), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_h (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({dz, ndy, dx}), .b({oz, py, ox}),
                .out_valid(), .y(h_p), .sat());
            // -p_y as 1 - o_y: the same word for every o_y (both clip only at o_y = -2^31,
            // to 2^31 - 1), one saturating operation instead of two
            q16_dot #(.TERMS(3), .ROUND(1)) u_c (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({oz, q_sub(Q_ONE, oy), ox}), .b({oz, py, ox}), .out_valid(),
                .y(c_p), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_xy (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({ndy, dx}), .b({ox, py}), .out_valid(), .y(xy_p), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_yz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({ndz, dy}), .b({py, oz}), .out_valid(), .y(yz_p), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_xz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({ndz, dx}), .b({ox, oz}), .out_valid(), .y(xz_p), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_disc (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(xz_p), yz_p, xy_p}), .b({xz_p, yz_p, xy_p}),
                .out_valid(),
                .y(disc_p), .sat());
            reg [31:0] s1, z1, h1, c1, a_f, h_f, c_f, disc;
            always @(posedge clk) if (ce) begin
                s1 <= q_sub(dxx_p, dyy_p);
                z1 <= dzz_p;
                h1 <= h_p;
                c1 <= c_p;
                a_f <= q_add(s1, z1);
                h_f <= h1;
                c_f <= c1;
                disc <= disc_p;
            end
            assign a_k = a_f;
            assign h_k = h_f;
            assign c_k = c_f;
            assign disc_k = disc;
        end else begin : no_cone
            assign a_k = 32'd0;
            assign h_k = 32'd0;
            assign c_k = 32'd0;
            assign disc_k = 32'd0;
        end
    endgenerate

    // the pair's shape, built or not
    wire is_sphere = SPHERE != 0 && shape_f == `RT_SHAPE_SPHERE;
    wire is_cyl = CYLINDER != 0 && shape_f == `RT_SHAPE_CYLINDER;
    wire is_cone = CONE != 0 && shape_f == `RT_SHAPE_CONE;
    wire [31:0] a_f = is_cyl ? a_c : is_cone ? a_k : a_s;
    wire [31:0] h_f = is_cyl ? h_c : is_cone ? h_k : h_s;
    wire [31:0] c_f = is_cyl ? c_c : is_cone ? c_k : c_s;
    wire        none_f = !(is_sphere || is_cyl || is_cone) || (is_cyl && none_c);
    wire [31:0] disc = shape_disc == `RT_SHAPE_CYLINDER ? disc_c
                      : shape_disc == `RT_SHAPE_CONE ? disc_k : disc_s;

    // ---- early rejection (clearly_misses): miss at T_MISS ------------------------------
    wire [31:0] hh, ac, margin;
    q16_dot #(.TERMS(1), .ROUND(0)) u_hh (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(h_f), .b(h_f), .out_valid(), .y(hh), .sat());
    q16_dot #(.TERMS(1), .ROUND(0)) u_ac (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(a_f), .b(c_f), .out_valid(), .y(ac), .sat());
    // one saturating operation per clock: h*h - a*c and |a*c|, their sum, the margin
    // (a product), + 2^-6, its negation, the comparison
    reg [31:0] lhs, hh_r, aac, sum_rj, thr, nthr;
    reg        miss;
    // S::from_f64(1/256) and S::from_f64(1/64)
    q16_dot #(.TERMS(1), .ROUND(0)) u_m (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(sum_rj), .b(32'h0000_0100), .out_valid(), .y(margin), .sat());
    // h*h - a*c beside -(margin + 2^-6)
    wire [31:0] lhs_m;
    dly #(.W(32), .N(D + 3)) d_lhs (.clk(clk), .rst(rst), .ce(ce), .d(lhs), .q(lhs_m));
    always @(posedge clk) if (ce) begin
        lhs <= q_sub(hh, ac);
        hh_r <= hh;
        aac <= q_abs(ac);
        sum_rj <= q_add(hh_r, aac);
        thr <= q_add(margin, 32'h0000_0400);
        nthr <= q_neg(thr);
        miss <= q_lt(lhs_m, nthr);
    end

    // ---- the root: sqrt(disc) at T_SQ ---------------------------------------------------
    wire [31:0] sq;
    q16_sqrt u_sqrt (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .x(disc),
        .out_valid(), .y(sq));
    wire [31:0] a_sq, h_sq, c_sq;
    dly #(.W(96), .N(T_SQ - T_F)) d_ahc_sq (.clk(clk), .rst(rst), .ce(ce), .d({a_f, h_f, c_f}),
        .q({a_sq, h_sq, c_sq}));

    // ---- the quotients: operands at T_QIN, results at T_T -----------------------------
    // one saturating operation per clock: sqrt(disc) - h and h + sqrt(disc); q, -c and
    // h + h; the operands (a = 0: the linear root -c / (h + h), through the first divider)
    reg [31:0] s_sub, s_add, a_s1, h_s1, c_s1;
    reg [31:0] q_r, a_s2, c_s2, lin_n, lin_d;
    reg        hz_s2;
    reg [31:0] n1, d1, n2, d2;
    reg        a0, h0, q0;
    always @(posedge clk) if (ce) begin
        s_sub <= q_sub(sq, h_sq);
        s_add <= q_add(h_sq, sq);
        a_s1 <= a_sq;
        h_s1 <= h_sq;
        c_s1 <= c_sq;
        q_r <= h_s1[31] ? s_sub : q_neg(s_add);
        a_s2 <= a_s1;
        c_s2 <= c_s1;
        lin_n <= q_neg(c_s1);
        lin_d <= q_add(h_s1, h_s1);
        hz_s2 <= h_s1 == 32'd0;
        n1 <= a_s2 == 32'd0 ? lin_n : q_r;
        d1 <= a_s2 == 32'd0 ? lin_d : a_s2;
        n2 <= c_s2;
        d2 <= q_r;
        a0 <= a_s2 == 32'd0;
        h0 <= hz_s2;
        q0 <= q_r == 32'd0;
    end
    wire [31:0] t1, t2;
    q16_div u_div1 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .a(n1), .b(d1),
        .out_valid(), .y(t1), .sat());
    q16_div u_div2 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .a(n2), .b(d2),
        .out_valid(), .y(t2), .sat());
    /* verilator lint_on PINCONNECTEMPTY */

    // every reason for no roots, carried to T_T
    wire none_t, miss_t, dneg_t, a0_t, h0_t, q0_t;
    dly #(.W(1), .N(T_T - T_F)) d_none (.clk(clk), .rst(rst), .ce(ce), .d(none_f), .q(none_t));
    dly #(.W(1), .N(T_T - T_MISS)) d_miss (.clk(clk), .rst(rst), .ce(ce), .d(miss), .q(miss_t));
    dly #(.W(1), .N(T_T - T_DISC)) d_dneg (.clk(clk), .rst(rst), .ce(ce), .d(disc[31]), .q(dneg_t));
    dly #(.W(3), .N(T_T - T_QIN)) d_flags (.clk(clk), .rst(rst), .ce(ce), .d({a0, h0, q0}),
        .q({a0_t, h0_t, q0_t}));

    // ---- roots in ascending order at T_R ----------------------------------------------
    wire [31:0] r1 = a0_t ? t1 : q0_t ? 32'd0 : t1;
    wire [31:0] r2 = a0_t ? t1 : q0_t ? 32'd0 : t2;
    reg         ok_r;
    reg  [31:0] lo_r, hi_r;
    always @(posedge clk) if (ce) begin
        ok_r <= !none_t && !miss_t && !(a0_t && h0_t) && (a0_t || !dneg_t);
        lo_r <= q_le(r1, r2) ? r1 : r2;
        hi_r <= q_le(r1, r2) ? r2 : r1;
    end

    // ---- the pick: the first root in range (and, for the cylinder and the cone, in
    // height) at LAT_QUADRIC----------------------------------------------------------------
    wire [31:0] tmin_r, tmax_r, oy_r, dy_r;
    dly #(.W(128), .N(T_R)) d_ray_r (.clk(clk), .rst(rst), .ce(ce),
        .d({tmin, tmax, oy, dy}), .q({tmin_r, tmax_r, oy_r, dy_r}));
    wire in_lo_r = q_le(tmin_r, lo_r) && q_le(lo_r, tmax_r);
    wire in_hi_r = q_le(tmin_r, hi_r) && q_le(hi_r, tmax_r);

    wire [31:0] mlo, mhi;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(1), .ROUND(0)) u_ylo (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(dy_r), .b(lo_r), .out_valid(), .y(mlo), .sat());
    q16_dot #(.TERMS(1), .ROUND(0)) u_yhi (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(dy_r), .b(hi_r), .out_valid(), .y(mhi), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [31:0] oy_m, lo_y, hi_y;
    wire        ok_y, in_lo_y, in_hi_y;
    dly #(.W(32), .N(D)) d_oy_m (.clk(clk), .rst(rst), .ce(ce), .d(oy_r), .q(oy_m));
    dly #(.W(67), .N(D + 1)) d_roots_y (.clk(clk), .rst(rst), .ce(ce),
        .d({ok_r, in_lo_r, in_hi_r, lo_r, hi_r}), .q({ok_y, in_lo_y, in_hi_y, lo_y, hi_y}));
    reg [31:0] ylo, yhi;
    always @(posedge clk) if (ce) begin
        ylo <= q_add(oy_m, mlo);
        yhi <= q_add(oy_m, mhi);
    end

    // cylinder y in [-1, 1], cone y in [0, 1]
    wire        cone_y = shape_y == `RT_SHAPE_CONE;
    wire        curved_y = shape_y == `RT_SHAPE_CYLINDER || cone_y;
    wire [31:0] y_lo_bound = cone_y ? 32'd0 : q_neg(Q_ONE);
    wire        tall_lo = q_le(y_lo_bound, ylo) && q_le(ylo, Q_ONE);
    wire        tall_hi = q_le(y_lo_bound, yhi) && q_le(yhi, Q_ONE);
    wire        take_lo = in_lo_y && (!curved_y || tall_lo);
    wire        take_hi = in_hi_y && (!curved_y || tall_hi);
    always @(posedge clk) if (ce) begin
        hit <= ok_y && (take_lo || take_hi);
        t <= take_lo ? lo_y : hi_y;
    end
endmodule
`default_nettype wire
