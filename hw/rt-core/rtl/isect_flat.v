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
// o, d (object-space ray, Q16.16), tmin, tmax; hit and t at LAT.
// Timing: latency LAT = 40 (quotient 34, hit point 3, disk test 3), one pair per clock;
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

    localparam integer SB = `RT_SHAPE_BITS;

    /* verilator lint_off PINCONNECTEMPTY */
    wire [31:0] t34;
    q16_div u_div (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .a(q_neg(oy)), .b(dy),
        .out_valid(), .y(t34), .sat());

    wire [31:0] ox34, oz34, dx34, dz34, tmin34, tmax34;
    wire        dy0_34;
    wire [SB-1:0] shape34;
    dly #(.W(193 + SB), .N(34)) d_ray34 (.clk(clk), .rst(rst), .ce(ce),
        .d({dy == 32'd0, shape, ox, oz, dx, dz, tmin, tmax}),
        .q({dy0_34, shape34, ox34, oz34, dx34, dz34, tmin34, tmax34}));

    // the hit point's x and z at T37
    wire [31:0] mx36, mz36, ox36, oz36;
    q16_dot #(.TERMS(1), .ROUND(0)) u_mx (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(dx34), .b(t34), .out_valid(), .y(mx36), .sat());
    q16_dot #(.TERMS(1), .ROUND(0)) u_mz (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(dz34), .b(t34), .out_valid(), .y(mz36), .sat());
    dly #(.W(64), .N(2)) d_o36 (.clk(clk), .rst(rst), .ce(ce), .d({ox34, oz34}),
        .q({ox36, oz36}));
    reg [31:0] x37, z37;
    always @(posedge clk) if (ce) begin
        x37 <= q_add(ox36, mx36);
        z37 <= q_add(oz36, mz36);
    end

    // the disk's test at T40
    wire [31:0] xx39, zz39;
    q16_dot #(.TERMS(1), .ROUND(0)) u_xx (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(x37), .b(x37), .out_valid(), .y(xx39), .sat());
    q16_dot #(.TERMS(1), .ROUND(0)) u_zz (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(z37), .b(z37), .out_valid(), .y(zz39), .sat());
    /* verilator lint_on PINCONNECTEMPTY */

    // the plane's verdict at T35, the square's at T38, both carried to T39
    reg        plane35;
    reg  [31:0] t35;
    always @(posedge clk) if (ce) begin
        plane35 <= !dy0_34 && q_le(tmin34, t34) && q_le(t34, tmax34);
        t35 <= t34;
    end
    wire        plane37;
    dly #(.W(1), .N(2)) d_plane37 (.clk(clk), .rst(rst), .ce(ce), .d(plane35), .q(plane37));
    reg square38;
    always @(posedge clk) if (ce)
        square38 <= plane37 && q_le(q_abs(x37), Q_ONE) && q_le(q_abs(z37), Q_ONE);

    wire        plane39, square39;
    wire [31:0] t39;
    wire [SB-1:0] shape39;
    dly #(.W(1), .N(4)) d_plane39 (.clk(clk), .rst(rst), .ce(ce), .d(plane35), .q(plane39));
    dly #(.W(1), .N(1)) d_square39 (.clk(clk), .rst(rst), .ce(ce), .d(square38), .q(square39));
    dly #(.W(32), .N(4)) d_t39 (.clk(clk), .rst(rst), .ce(ce), .d(t35), .q(t39));
    dly #(.W(SB), .N(5)) d_shape39 (.clk(clk), .rst(rst), .ce(ce), .d(shape34), .q(shape39));

    always @(posedge clk) if (ce) begin
        case (shape39)
            `RT_SHAPE_PLANE: hit <= PLANE != 0 && plane39;
            `RT_SHAPE_DISK: hit <= DISK != 0 && plane39 && q_le(q_add(xx39, zz39), Q_ONE);
            `RT_SHAPE_SQUARE: hit <= SQUARE != 0 && square39;
            default: hit <= 1'b0;
        endcase
        t <= t39;
    end
endmodule
`default_nettype wire
