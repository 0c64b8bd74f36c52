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
// Timing: latency LAT = 72 (front 5, rejection and root 27, quotients 35, height 4),
// one pair per clock; ce low holds everything.
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

    localparam integer SB = `RT_SHAPE_BITS;

    // The shape code at the stages that decide by it.
    wire [SB-1:0] shape3, shape5, shape71;
    dly #(.W(SB), .N(3)) d_shape3 (.clk(clk), .rst(rst), .ce(ce), .d(shape), .q(shape3));
    dly #(.W(SB), .N(2)) d_shape5 (.clk(clk), .rst(rst), .ce(ce), .d(shape3), .q(shape5));
    dly #(.W(SB), .N(66)) d_shape71 (.clk(clk), .rst(rst), .ce(ce), .d(shape5), .q(shape71));

    // ---- fronts: a, h, c and "no hit" at T3, disc at T5 ------------------------------
    /* verilator lint_off PINCONNECTEMPTY */
    wire [31:0] a_s3, h_s3, c_s3, disc_s5;
    wire [31:0] a_c3, h_c3, c_c3, disc_c5;
    wire [31:0] a_k3, h_k3, c_k3, disc_k5;
    wire        none_c3;

    generate
        if (SPHERE != 0) begin : sphere
            wire [31:0] a2, h2, oo2, x0, x1, x2, xx4;
            q16_dot #(.TERMS(3), .ROUND(1)) u_a (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({dz, dy, dx}), .b({dz, dy, dx}), .out_valid(), .y(a2), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_h (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({dz, dy, dx}), .b({oz, oy, ox}), .out_valid(), .y(h2), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_oo (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({oz, oy, ox}), .b({oz, oy, ox}), .out_valid(), .y(oo2), .sat());
            // d x o, each component one rounding (cross2)
            q16_dot #(.TERMS(2), .ROUND(1)) u_x0 (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(dz), dy}), .b({oy, oz}), .out_valid(), .y(x0), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_x1 (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(dx), dz}), .b({oz, ox}), .out_valid(), .y(x1), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_x2 (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(dy), dx}), .b({ox, oy}), .out_valid(), .y(x2), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_xx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({x2, x1, x0}), .b({x2, x1, x0}), .out_valid(), .y(xx4), .sat());
            reg [31:0] a3, h3, c3, a4, disc5;
            always @(posedge clk) if (ce) begin
                a3 <= a2;
                h3 <= h2;
                c3 <= q_sub(oo2, Q_ONE);
                a4 <= a3;
                disc5 <= q_sub(a4, xx4);
            end
            assign a_s3 = a3;
            assign h_s3 = h3;
            assign c_s3 = c3;
            assign disc_s5 = disc5;
        end else begin : no_sphere
            assign a_s3 = 32'd0;
            assign h_s3 = 32'd0;
            assign c_s3 = 32'd0;
            assign disc_s5 = 32'd0;
        end

        if (CYLINDER != 0) begin : cylinder
            wire [31:0] dxx2, dzz2, oxx2, ozz2, h2, x2, xx4;
            q16_dot #(.TERMS(1), .ROUND(0)) u_dxx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dx), .b(dx), .out_valid(), .y(dxx2), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_dzz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dz), .b(dz), .out_valid(), .y(dzz2), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_oxx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(ox), .b(ox), .out_valid(), .y(oxx2), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_ozz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(oz), .b(oz), .out_valid(), .y(ozz2), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_h (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({dz, dx}), .b({oz, ox}), .out_valid(), .y(h2), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_x (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(dz), dx}), .b({ox, oz}), .out_valid(), .y(x2), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_xx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(x2), .b(x2), .out_valid(), .y(xx4), .sat());
            reg [31:0] a3, h3, c3, a4, disc5;
            always @(posedge clk) if (ce) begin
                a3 <= q_add(dxx2, dzz2);
                h3 <= h2;
                c3 <= q_sub(q_add(oxx2, ozz2), Q_ONE);
                a4 <= a3;
                disc5 <= q_sub(a4, xx4);
            end
            assign a_c3 = a3;
            assign h_c3 = h3;
            assign c_c3 = c3;
            assign disc_c5 = disc5;
            // parallel to the axis: the open tube is never crossed
            assign none_c3 = a3 == 32'd0;
        end else begin : no_cylinder
            assign a_c3 = 32'd0;
            assign h_c3 = 32'd0;
            assign c_c3 = 32'd0;
            assign disc_c5 = 32'd0;
            assign none_c3 = 1'b1;
        end

        if (CONE != 0) begin : cone
            // from the apex: p = o - (0, 1, 0)
            wire [31:0] py = q_sub(oy, Q_ONE);
            wire [31:0] ndy = q_neg(dy);
            wire [31:0] ndz = q_neg(dz);
            wire [31:0] dxx2, dyy2, dzz2, h2, c2, xy2, yz2, xz2, disc4;
            q16_dot #(.TERMS(1), .ROUND(0)) u_dxx (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dx), .b(dx), .out_valid(), .y(dxx2), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_dyy (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dy), .b(dy), .out_valid(), .y(dyy2), .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_dzz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(dz), .b(dz), .out_valid(), .y(dzz2), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_h (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({dz, ndy, dx}), .b({oz, py, ox}), .out_valid(), .y(h2), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_c (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({oz, q_neg(py), ox}), .b({oz, py, ox}), .out_valid(),
                .y(c2), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_xy (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({ndy, dx}), .b({ox, py}), .out_valid(), .y(xy2), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_yz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({ndz, dy}), .b({py, oz}), .out_valid(), .y(yz2), .sat());
            q16_dot #(.TERMS(2), .ROUND(1)) u_xz (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({ndz, dx}), .b({ox, oz}), .out_valid(), .y(xz2), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_disc (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({q_neg(xz2), yz2, xy2}), .b({xz2, yz2, xy2}), .out_valid(),
                .y(disc4), .sat());
            reg [31:0] a3, h3, c3, disc5;
            always @(posedge clk) if (ce) begin
                a3 <= q_add(q_sub(dxx2, dyy2), dzz2);
                h3 <= h2;
                c3 <= c2;
                disc5 <= disc4;
            end
            assign a_k3 = a3;
            assign h_k3 = h3;
            assign c_k3 = c3;
            assign disc_k5 = disc5;
        end else begin : no_cone
            assign a_k3 = 32'd0;
            assign h_k3 = 32'd0;
            assign c_k3 = 32'd0;
            assign disc_k5 = 32'd0;
        end
    endgenerate

    // the pair's shape, built or not
    wire is_sphere3 = SPHERE != 0 && shape3 == `RT_SHAPE_SPHERE;
    wire is_cyl3 = CYLINDER != 0 && shape3 == `RT_SHAPE_CYLINDER;
    wire is_cone3 = CONE != 0 && shape3 == `RT_SHAPE_CONE;
    wire [31:0] a3 = is_cyl3 ? a_c3 : is_cone3 ? a_k3 : a_s3;
    wire [31:0] h3 = is_cyl3 ? h_c3 : is_cone3 ? h_k3 : h_s3;
    wire [31:0] c3 = is_cyl3 ? c_c3 : is_cone3 ? c_k3 : c_s3;
    wire        none3 = !(is_sphere3 || is_cyl3 || is_cone3) || (is_cyl3 && none_c3);
    wire [31:0] disc5 = shape5 == `RT_SHAPE_CYLINDER ? disc_c5
                      : shape5 == `RT_SHAPE_CONE ? disc_k5 : disc_s5;

    // ---- early rejection (clearly_misses): miss at T9 ---------------------------------
    wire [31:0] hh5, ac5, m8;
    q16_dot #(.TERMS(1), .ROUND(0)) u_hh (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(h3), .b(h3), .out_valid(), .y(hh5), .sat());
    q16_dot #(.TERMS(1), .ROUND(0)) u_ac (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(a3), .b(c3), .out_valid(), .y(ac5), .sat());
    reg [31:0] lhs6, sum6, lhs7, lhs8;
    reg        miss9;
    // S::from_f64(1/256) and S::from_f64(1/64)
    q16_dot #(.TERMS(1), .ROUND(0)) u_m (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(sum6), .b(32'h0000_0100), .out_valid(), .y(m8), .sat());
    always @(posedge clk) if (ce) begin
        lhs6 <= q_sub(hh5, ac5);
        sum6 <= q_add(hh5, q_abs(ac5));
        lhs7 <= lhs6;
        lhs8 <= lhs7;
        miss9 <= q_lt(lhs8, q_neg(q_add(m8, 32'h0000_0400)));
    end

    // ---- the root: sqrt(disc) at T32 ---------------------------------------------------
    wire [31:0] sq32;
    q16_sqrt u_sqrt (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .x(disc5),
        .out_valid(), .y(sq32));
    wire [31:0] a32, h32, c32;
    dly #(.W(96), .N(29)) d_ahc32 (.clk(clk), .rst(rst), .ce(ce), .d({a3, h3, c3}),
        .q({a32, h32, c32}));

    // ---- the quotients: operands at T33, results at T67 -------------------------------
    wire [31:0] q32 = h32[31] ? q_sub(sq32, h32) : q_neg(q_add(h32, sq32));
    reg  [31:0] n1_33, d1_33, n2_33, d2_33;
    reg         a0_33, h0_33, q0_33;
    always @(posedge clk) if (ce) begin
        // a = 0: the linear root -c / (h + h), through the first divider
        n1_33 <= a32 == 32'd0 ? q_neg(c32) : q32;
        d1_33 <= a32 == 32'd0 ? q_add(h32, h32) : a32;
        n2_33 <= c32;
        d2_33 <= q32;
        a0_33 <= a32 == 32'd0;
        h0_33 <= h32 == 32'd0;
        q0_33 <= q32 == 32'd0;
    end
    wire [31:0] t1_67, t2_67;
    q16_div u_div1 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .a(n1_33), .b(d1_33),
        .out_valid(), .y(t1_67), .sat());
    q16_div u_div2 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .a(n2_33), .b(d2_33),
        .out_valid(), .y(t2_67), .sat());
    /* verilator lint_on PINCONNECTEMPTY */

    // every reason for no roots, carried to T67
    wire none67, miss67, dneg67, a0_67, h0_67, q0_67;
    dly #(.W(1), .N(64)) d_none (.clk(clk), .rst(rst), .ce(ce), .d(none3), .q(none67));
    dly #(.W(1), .N(58)) d_miss (.clk(clk), .rst(rst), .ce(ce), .d(miss9), .q(miss67));
    dly #(.W(1), .N(62)) d_dneg (.clk(clk), .rst(rst), .ce(ce), .d(disc5[31]), .q(dneg67));
    dly #(.W(3), .N(34)) d_flags (.clk(clk), .rst(rst), .ce(ce), .d({a0_33, h0_33, q0_33}),
        .q({a0_67, h0_67, q0_67}));

    // ---- roots in ascending order at T68 ------------------------------------------------
    wire [31:0] r1 = a0_67 ? t1_67 : q0_67 ? 32'd0 : t1_67;
    wire [31:0] r2 = a0_67 ? t1_67 : q0_67 ? 32'd0 : t2_67;
    reg         ok68;
    reg  [31:0] lo68, hi68;
    always @(posedge clk) if (ce) begin
        ok68 <= !none67 && !miss67 && !(a0_67 && h0_67) && (a0_67 || !dneg67);
        lo68 <= q_le(r1, r2) ? r1 : r2;
        hi68 <= q_le(r1, r2) ? r2 : r1;
    end

    // ---- the pick: the first root in range (and, for the cylinder and the cone, in
    // height) at T72 -------------------------------------------------------------------
    wire [31:0] tmin68, tmax68, oy68, dy68;
    dly #(.W(128), .N(68)) d_ray68 (.clk(clk), .rst(rst), .ce(ce),
        .d({tmin, tmax, oy, dy}), .q({tmin68, tmax68, oy68, dy68}));
    wire in_lo68 = q_le(tmin68, lo68) && q_le(lo68, tmax68);
    wire in_hi68 = q_le(tmin68, hi68) && q_le(hi68, tmax68);

    wire [31:0] mlo70, mhi70;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(1), .ROUND(0)) u_ylo (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(dy68), .b(lo68), .out_valid(), .y(mlo70), .sat());
    q16_dot #(.TERMS(1), .ROUND(0)) u_yhi (.clk(clk), .rst(rst), .ce(ce),
        .in_valid(1'b1), .a(dy68), .b(hi68), .out_valid(), .y(mhi70), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [31:0] oy70, lo71, hi71;
    wire        ok71, in_lo71, in_hi71;
    dly #(.W(32), .N(2)) d_oy70 (.clk(clk), .rst(rst), .ce(ce), .d(oy68), .q(oy70));
    dly #(.W(67), .N(3)) d_roots71 (.clk(clk), .rst(rst), .ce(ce),
        .d({ok68, in_lo68, in_hi68, lo68, hi68}), .q({ok71, in_lo71, in_hi71, lo71, hi71}));
    reg [31:0] ylo71, yhi71;
    always @(posedge clk) if (ce) begin
        ylo71 <= q_add(oy70, mlo70);
        yhi71 <= q_add(oy70, mhi70);
    end

    // cylinder y in [-1, 1], cone y in [0, 1]
    wire        cone71 = shape71 == `RT_SHAPE_CONE;
    wire        curved71 = shape71 == `RT_SHAPE_CYLINDER || cone71;
    wire [31:0] y_lo_bound = cone71 ? 32'd0 : q_neg(Q_ONE);
    wire        tall_lo = q_le(y_lo_bound, ylo71) && q_le(ylo71, Q_ONE);
    wire        tall_hi = q_le(y_lo_bound, yhi71) && q_le(yhi71, Q_ONE);
    wire        take_lo = in_lo71 && (!curved71 || tall_lo);
    wire        take_hi = in_hi71 && (!curved71 || tall_hi);
    always @(posedge clk) if (ce) begin
        hit <= ok71 && (take_lo || take_hi);
        t <= take_lo ? lo71 : hi71;
    end
endmodule
`default_nettype wire
