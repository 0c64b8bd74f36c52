// isect_flat -- the flat shapes' ray intersection (plane y = 0, unit disk and square
// |x|, |z| <= 1 in it) in object space, one (ray, object) pair per clock: the golden
// model's `shapes::plane`, `disk` and `square` (sim-target/src/rt/shapes.rs), bit for bit.
//
// Why together: the three share the hit distance t = -oy / dy and differ only in the test
// of the hit point (x, z) = (ox + dx t, oz + dz t) that follows. Seed 002 §3.4 has the
// plane; the disk and the square are the model's bounded variants of it.
//
// The model's steps: dy = 0: no hit; t = -oy / dy (q16_div); t in [tmin, tmax]; disk:
// x*x + z*z <= 1 (products floored, sum saturated); square: |x| <= 1 and |z| <= 1.
//
// Ports: shape (rt_map.vh codes; a code this module does not build gives no hit),
// o, d (object-space ray, Q16.16), tmin, tmax; hit and t at LAT_FLAT.
// Timing: latency LAT_FLAT = Q_DIV_LAT + 2 Q_DOT_LAT + 3 = 46 (isect.vh: quotient 35,
// hit point Q_DOT_LAT + 1, disk test Q_DOT_LAT + 2), one pair per clock;
// ce low holds everything.
// Parameters: PLANE, DISK, SQUARE: 1 builds the shape.
`default_nettype none
`include "rt_map.vh"
module isect_flat #(
    parameter integer PLANE = 1,
    parameter integer DISK = 1,
    parameter integer SQUARE = 1
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
        if ((PLANE != 0 && PLANE != 1) || (DISK != 0 && DISK != 1)
                || (SQUARE != 0 && SQUARE != 1)) begin : bad_parameter
            isect_flat_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "isect.vh"
    localparam integer SB = `RT_SHAPE_BITS;
    localparam integer D = Q_DOT_LAT;
    // the schedule: the quotient, the hit point (the result at T_X + D + 2)
    localparam integer T_Q = Q_DIV_LAT;
    localparam integer T_X = T_Q + D + 1;
    generate
        if (T_X + D + 2 != LAT_FLAT) begin : bad_schedule
            isect_flat_schedule_differs_from_isect_vh unsupported();
        end
    endgenerate

    /* verilator lint_off PINCONNECTEMPTY */
    wire [31:0] t_q;
    q16_div u_div (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .a(q_neg(oy)), .b(dy),
        .out_valid(), .y(t_q), .sat());

    wire [31:0] ox_q, oz_q, dx_q, dz_q, tmin_q, tmax_q;
    wire        dy0_q;
    wire [SB-1:0] shape_q;
    dly #(.W(193 + SB), .N(T_Q)) d_ray_q (.clk(clk), .rst(rst), .ce(ce),
        .d({dy == 32'd0, shape, ox, oz, dx, dz, tmin, tmax}),
        .q({dy0_q, shape_q, ox_q, oz_q, dx_q, dz_q, tmin_q, tmax_q}));

    // the hit point's x and z at T_X
    wire [31:0] mx, mz, ox_m, oz_m;
    q16_dot #(.TERMS(1), .ROUND(0)) u_mx (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(dx_q), .b(t_q), .out_valid(), .y(mx), .sat());
    q16_dot #(.TERMS(1), .ROUND(0)) u_mz (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(dz_q), .b(t_q), .out_valid(), .y(mz), .sat());
    dly #(.W(64), .N(D)) d_o_m (.clk(clk), .rst(rst), .ce(ce), .d({ox_q, oz_q}),
        .q({ox_m, oz_m}));
    reg [31:0] x, z;
    always @(posedge clk) if (ce) begin
        x <= q_add(ox_m, mx);
        z <= q_add(oz_m, mz);
    end

    // the disk's test at LAT_FLAT
    wire [31:0] xx, zz;
    q16_dot #(.TERMS(1), .ROUND(0)) u_xx (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(x), .b(x), .out_valid(), .y(xx), .sat());
    q16_dot #(.TERMS(1), .ROUND(0)) u_zz (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(z), .b(z), .out_valid(), .y(zz), .sat());
    /* verilator lint_on PINCONNECTEMPTY */

    // the plane's verdict at T_Q + 1, the square's at T_X + 2 (|x|, |z| first), both
    // carried to LAT_FLAT - 1
    reg        plane_q;
    reg  [31:0] t_q1;
    always @(posedge clk) if (ce) begin
        plane_q <= !dy0_q && q_le(tmin_q, t_q) && q_le(t_q, tmax_q);
        t_q1 <= t_q;
    end
    wire        plane_x;
    dly #(.W(1), .N(D + 1)) d_plane_x (.clk(clk), .rst(rst), .ce(ce), .d(plane_q), .q(plane_x));
    reg [31:0] ax, az;
    reg        square_x;
    always @(posedge clk) if (ce) begin
        ax <= q_abs(x);
        az <= q_abs(z);
        square_x <= plane_x && q_le(ax, Q_ONE) && q_le(az, Q_ONE);
    end
    // the disk's x*x + z*z, then its test
    reg [31:0] r2;
    always @(posedge clk) if (ce) r2 <= q_add(xx, zz);

    wire        plane_l, square_l;
    wire [31:0] t_l;
    wire [SB-1:0] shape_l;
    dly #(.W(1), .N(2 * D + 1)) d_plane_l (.clk(clk), .rst(rst), .ce(ce), .d(plane_q), .q(plane_l));
    dly #(.W(1), .N(D - 1)) d_square_l (.clk(clk), .rst(rst), .ce(ce), .d(square_x), .q(square_l));
    dly #(.W(32), .N(2 * D + 1)) d_t_l (.clk(clk), .rst(rst), .ce(ce), .d(t_q1), .q(t_l));
    dly #(.W(SB), .N(2 * D + 2)) d_shape_l (.clk(clk), .rst(rst), .ce(ce),
        .d(shape_q), .q(shape_l));

    always @(posedge clk) if (ce) begin
        case (shape_l)
            `RT_SHAPE_PLANE: hit <= PLANE != 0 && plane_l;
            `RT_SHAPE_DISK: hit <= DISK != 0 && plane_l && q_le(r2, Q_ONE);
            `RT_SHAPE_SQUARE: hit <= SQUARE != 0 && square_l;
            default: hit <= 1'b0;
        endcase
        t <= t_l;
    end
endmodule
`default_nettype wire
