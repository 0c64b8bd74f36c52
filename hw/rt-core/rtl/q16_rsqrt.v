// q16_rsqrt -- Q16.16 reciprocal square root, correctly rounded: the golden model's
// Q16.16 `rsqrt` (sim-target/src/num/formats.rs) bit for bit; x <= 0 gives 2^31 - 1.
//
// Why: normalising a vector takes one 1/sqrt and three products in the model (V3::normalize),
// and its core rounds 2^24 / sqrt(x) to nearest. That integer is
// (floor(sqrt(floor(2^50 / x))) + 1) >> 1: floor(sqrt(floor(n))) = floor(sqrt(n)), and
// (2r - 1)^2 * x <= 2^50 < (2r + 1)^2 * x brackets the nearest r (never a tie). The
// model's f64 form and this one agree on all 2^31 positive inputs (sim-target's
// num_approx test `q16_cores_are_integer_formulas`). One exact quotient and one exact root
// instead of a table seed and Newton-Raphson steps, which would be off by an LSB in places.
//
// Ports: x signed Q16.16; in_valid / out_valid; ce low holds the pipeline. `sat` is high
// for x <= 0 (the model's format counts that result as a saturation).
// Timing: latency 79 (operand, 51 quotient bits, 26 root bits, rounding), one operand
// per clock.
`default_nettype none
module q16_rsqrt (
    input  wire               clk,
    input  wire               rst,
    input  wire               ce,
    input  wire               in_valid,
    input  wire signed [31:0] x,
    output reg                out_valid,
    output reg  signed [31:0] y,
    output reg                sat
);
    reg        v0;
    reg [30:0] d0;
    reg        z0;
    always @(posedge clk) begin
        if (rst) v0 <= 1'b0;
        else if (ce) v0 <= in_valid;
        if (ce) begin
            // x <= 0 divides by 1 instead (the result is replaced)
            d0 <= x <= 32'sd0 ? 31'd1 : x[30:0];
            z0 <= x <= 32'sd0;
        end
    end

    wire        v1;
    wire [50:0] q1;
    wire        z1;
    udiv_pipe #(.DB(31), .QB(51), .UB(1)) reciprocal (
        .clk(clk), .rst(rst), .ce(ce),
        .in_valid(v0),
        .n_hi(31'd0),
        .n_lo(51'h4000000000000),
        .d(d0),
        .user_in(z0),
        .out_valid(v1),
        .q(q1),
        .user_out(z1)
    );

    wire        v2;
    wire [25:0] root;
    wire        z2;
    usqrt_pipe #(.NB(52), .UB(1)) isqrt (
        .clk(clk), .rst(rst), .ce(ce),
        .in_valid(v1), .x({1'b0, q1}), .user_in(z1),
        .out_valid(v2), .root(root), .user_out(z2)
    );

    // (root + 1) >> 1
    wire [25:0] rounded = {1'b0, root[25:1]} + {25'd0, root[0]};
    always @(posedge clk) begin
        if (rst) out_valid <= 1'b0;
        else if (ce) out_valid <= v2;
        if (ce) begin
            y <= z2 ? 32'sh7fffffff : {6'd0, rounded};
            sat <= z2;
        end
    end
endmodule
`default_nettype wire
