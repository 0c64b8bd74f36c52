// rt_xform -- a ray into an object's space: the golden model's `PObj::to_object`
// (sim-target/src/rt/prepare.rs), lo = M^-1 (o - t) and ld = M^-1 d, each row one `dot3`
// (exact sum, one rounding), o - t saturating per component; seed 002 §3.4 intersects
// every object in its own space.
//
// Why no diagonal path: the model multiplies an unrotated object's ray by M^-1's diagonal
// (`hadamard`, one `mul_rn` per component), which is the same word as the row's `dot3`
// with two zero terms (the exact sum gains nothing from them and is rounded once), so the
// full matrix serves both. The camera position's image, which the model computes once per
// object and frame, is this same computation with o = eye.
//
// Ports: o, d (world space, Q16.16), m (M^-1 row-major, m00 in bits [31:0], then m01 ...
// m22), t (the object's translation); tag (TB bits carried alongside); in_valid /
// out_valid; lo, ld (object space). ce low holds every stage.
// Timing: latency LAT = 1 + Q_DOT_LAT = 5 (o - t, then dot3), one pair per clock.
// Parameters: TB >= 1.
`default_nettype none
module rt_xform #(
    parameter integer TB = 1
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          ce,
    input  wire          in_valid,
    input  wire [95:0]   o,
    input  wire [95:0]   d,
    input  wire [287:0]  m,
    input  wire [95:0]   t,
    input  wire [TB-1:0] tag,
    output wire          out_valid,
    output wire [95:0]   lo,
    output wire [95:0]   ld,
    output wire [TB-1:0] tag_out
);
    generate
        if (TB < 1) begin : bad_parameter
            rt_xform_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "q16_ops.vh"

    // stage 1: o - t; the matrix and d wait beside it
    reg  [95:0]  rel1;
    wire [95:0]  d1;
    wire [287:0] m1;
    always @(posedge clk) begin
        if (ce) begin
            rel1 <= {q_sub(o[95:64], t[95:64]), q_sub(o[63:32], t[63:32]),
                     q_sub(o[31:0], t[31:0])};
        end
    end
    dly #(.W(96), .N(1)) u_d1 (.clk(clk), .rst(rst), .ce(ce), .d(d), .q(d1));
    dly #(.W(288), .N(1)) u_m1 (.clk(clk), .rst(rst), .ce(ce), .d(m), .q(m1));

    // the way out: o - t, then the products
    localparam integer LAT = 1 + Q_DOT_LAT;

    // stages 2 to LAT: each row of M^-1 against o - t and against d
    genvar r;
    generate
        for (r = 0; r < 3; r = r + 1) begin : row
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(3), .ROUND(1)) u_lo (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(m1[96*r +: 96]), .b(rel1), .out_valid(),
                .y(lo[32*r +: 32]), .sat());
            q16_dot #(.TERMS(3), .ROUND(1)) u_ld (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(m1[96*r +: 96]), .b(d1), .out_valid(),
                .y(ld[32*r +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate

    dly #(.W(1), .N(LAT), .RESET(1)) u_valid (.clk(clk), .rst(rst), .ce(ce), .d(in_valid),
        .q(out_valid));
    dly #(.W(TB), .N(LAT)) u_tag (.clk(clk), .rst(rst), .ce(ce), .d(tag), .q(tag_out));
endmodule
`default_nettype wire
