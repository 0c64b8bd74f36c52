// q16_sqrt -- Q16.16 square root, correctly rounded: the golden model's Q16.16 `sqrt`
// (sim-target/src/num/formats.rs) bit for bit, 0 for x <= 0.
//
// Why exact: the quadratics' roots and every length go through it, and the model's core
// rounds to nearest; sqrt(x * 2^-16) * 2^16 = sqrt(x * 2^16), whose nearest integer is
// (floor(sqrt(x * 2^18)) + 1) >> 1 (no tie is possible: (k + 1/2)^2 is never an
// integer). The model's f64 form and this integer form agree on all 2^31 positive inputs
// (sim-target's num_approx test `q16_cores_are_integer_formulas`). Seed 002 takes the
// root from the HLS math library.
//
// Ports: x signed Q16.16; y = round(sqrt(x)) for x > 0, else 0; in_valid / out_valid;
// ce low holds the pipeline. Never saturates (sqrt(2^15) < 2^15).
// Timing: latency 27 (operand, 25 root bits, rounding), one operand per clock.
`default_nettype none
module q16_sqrt (
    input  wire               clk,
    input  wire               rst,
    input  wire               ce,
    input  wire               in_valid,
    input  wire signed [31:0] x,
    output reg                out_valid,
    output reg  signed [31:0] y
);
    reg        v0;
    reg [49:0] r0;
    reg        z0;
    always @(posedge clk) begin
        if (rst) v0 <= 1'b0;
        else if (ce) v0 <= in_valid;
        if (ce) begin
            r0 <= {1'b0, x[30:0], 18'd0};
            z0 <= x <= 32'sd0;
        end
    end

    wire        v1;
    wire [24:0] root;
    wire        z1;
    usqrt_pipe #(.NB(50), .UB(1)) isqrt (
        .clk(clk), .rst(rst), .ce(ce),
        .in_valid(v0), .x(r0), .user_in(z0),
        .out_valid(v1), .root(root), .user_out(z1)
    );

    // (root + 1) >> 1
    wire [24:0] rounded = {1'b0, root[24:1]} + {24'd0, root[0]};
    always @(posedge clk) begin
        if (rst) out_valid <= 1'b0;
        else if (ce) out_valid <= v1;
        if (ce) y <= z1 ? 32'sd0 : {7'd0, rounded};
    end
endmodule
`default_nettype wire
