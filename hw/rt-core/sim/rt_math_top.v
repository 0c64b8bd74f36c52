// rt_math_top -- simulation top that puts every Q16.16 arithmetic unit of the core side by
// side on one set of operands, so the bridge crate (rt-core-rtl-sim) can hold each to the
// golden model's arithmetic with one operand set per clock.
//
// Not synthesised: the core instantiates the units where its datapath needs them.
// Ports: a0..a2, b0..b2 feed every unit (the products use a0 * b0 first, then a1 * b1 and
// a2 * b2; the divider a0 / b0; the roots a0); each unit has its own valid and, where it
// can clip, saturation flag. ce low holds every unit (operands offered then are not
// taken).
// Timing: the units' own (q16_dot 4, q16_div 35, q16_sqrt 27, q16_rsqrt 79,
// q16_to_f32 2); q16_to_f32 converts a0 and has no saturation flag (every word fits).
`default_nettype none
module rt_math_top (
    input  wire        clk,
    input  wire        rst,
    input  wire        ce,
    input  wire        in_valid,
    input  wire [31:0] a0,
    input  wire [31:0] a1,
    input  wire [31:0] a2,
    input  wire [31:0] b0,
    input  wire [31:0] b1,
    input  wire [31:0] b2,
    output wire        mul_v,
    output wire [31:0] mul_y,
    output wire        mul_sat,
    output wire        mul_rn_v,
    output wire [31:0] mul_rn_y,
    output wire        mul_rn_sat,
    output wire        dot2_v,
    output wire [31:0] dot2_y,
    output wire        dot2_sat,
    output wire        dot3_v,
    output wire [31:0] dot3_y,
    output wire        dot3_sat,
    output wire        div_v,
    output wire [31:0] div_y,
    output wire        div_sat,
    output wire        sqrt_v,
    output wire [31:0] sqrt_y,
    output wire        rsqrt_v,
    output wire [31:0] rsqrt_y,
    output wire        rsqrt_sat,
    output wire        tof32_v,
    output wire [31:0] tof32_y
);
    q16_dot #(.TERMS(1), .ROUND(0)) mul (
        .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .a(a0), .b(b0),
        .out_valid(mul_v), .y(mul_y), .sat(mul_sat)
    );
    q16_dot #(.TERMS(1), .ROUND(1)) mul_rn (
        .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .a(a0), .b(b0),
        .out_valid(mul_rn_v), .y(mul_rn_y), .sat(mul_rn_sat)
    );
    q16_dot #(.TERMS(2), .ROUND(1)) dot2 (
        .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .a({a1, a0}), .b({b1, b0}),
        .out_valid(dot2_v), .y(dot2_y), .sat(dot2_sat)
    );
    q16_dot #(.TERMS(3), .ROUND(1)) dot3 (
        .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .a({a2, a1, a0}),
        .b({b2, b1, b0}), .out_valid(dot3_v), .y(dot3_y), .sat(dot3_sat)
    );
    q16_div div (
        .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .a(a0), .b(b0),
        .out_valid(div_v), .y(div_y), .sat(div_sat)
    );
    q16_sqrt sqrt (
        .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .x(a0),
        .out_valid(sqrt_v), .y(sqrt_y)
    );
    q16_rsqrt rsqrt (
        .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .x(a0),
        .out_valid(rsqrt_v), .y(rsqrt_y), .sat(rsqrt_sat)
    );
    q16_to_f32 tof32 (
        .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid), .q(a0),
        .out_valid(tof32_v), .y(tof32_y)
    );
endmodule
`default_nettype wire
