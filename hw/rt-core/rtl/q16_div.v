// q16_div -- Q16.16 division, truncated toward zero and saturated: the golden model's
// Q16.16 `/` bit for bit (sim-target/src/num/formats.rs, `fixed`'s saturating_div).
//
// Why: every shape's hit distance is a quotient (-o.y / d.y for the flat shapes, the slab
// distances of the cube, q / a and c / q of the quadratics), and the model's is the exact
// truncated quotient of a 48-bit dividend, which a restoring divider (udiv_pipe) gives
// without the last-bit differences of a reciprocal-and-multiply. Seed 002 divides in
// `ap_fixed<32,16>` with AP_SAT, as here.
//
// Arithmetic: y = trunc(a * 2^16 / b) clamped to [-2^31, 2^31 - 1]; b = 0 gives 2^31 - 1
// for a >= 0 and -2^31 for a < 0 (a divider core that flags rather than traps). The
// magnitudes divide as |a| * 2^16 / |b|; when |a| >> 16 >= |b| the quotient needs more
// than 32 bits and clips before the divider's result is used. `sat` is high when the
// result clipped or b = 0 (the model counts both as saturations).
//
// Ports: a, b signed Q16.16; in_valid / out_valid; ce low holds the pipeline.
// Timing: latency Q_DIV_LAT = 35 (q16_lat.vh: operands, their magnitudes, 32 quotient
// bits, sign and clamp), one operand pair per clock. The operands are registered as they
// come so that the caller's operand logic (a saturating negation or difference) and the
// magnitudes' negation and comparison are not one clock at 100 MHz.
`default_nettype none
module q16_div (
    input  wire               clk,
    input  wire               rst,
    input  wire               ce,
    input  wire               in_valid,
    input  wire signed [31:0] a,
    input  wire signed [31:0] b,
    output reg                out_valid,
    output reg  signed [31:0] y,
    output reg                sat
);
    `include "q16_lat.vh"
    generate
        if (Q_DIV_LAT != 35) begin : bad_latency
            q16_div_stage_count_differs_from_q_div_lat unsupported();
        end
    endgenerate

    // side band: [2] negative quotient, [1] clip to the maximum, [0] clip to the minimum
    localparam integer UB = 3;

    reg                vi;
    reg  signed [31:0] ai, bi;
    always @(posedge clk) begin
        if (rst) vi <= 1'b0;
        else if (ce) vi <= in_valid;
        if (ce) begin
            ai <= a;
            bi <= b;
        end
    end
    wire [31:0] mag_a = ai[31] ? 32'd0 - ai : ai;
    wire [31:0] mag_b = bi[31] ? 32'd0 - bi : bi;

    reg          v0;
    reg  [31:0]  n0;
    reg  [31:0]  d0;
    reg  [UB-1:0] u0;
    always @(posedge clk) begin
        if (rst) v0 <= 1'b0;
        else if (ce) v0 <= vi;
        if (ce) begin
            n0 <= mag_a;
            d0 <= mag_b;
            if (bi == 32'sd0)
                u0 <= {1'b0, !ai[31], ai[31]};
            else if ({16'd0, mag_a[31:16]} >= mag_b)
                u0 <= {1'b0, ai[31] == bi[31], ai[31] != bi[31]};
            else
                u0 <= {ai[31] != bi[31], 2'b00};
        end
    end

    wire          v1;
    wire [31:0]   q1;
    wire [UB-1:0] u1;
    udiv_pipe #(.DB(32), .QB(32), .UB(UB)) magnitude (
        .clk(clk), .rst(rst), .ce(ce),
        .in_valid(v0),
        // a clipping quotient's dividend may break the divider's n_hi < d; its result
        // is not used
        .n_hi({16'd0, n0[31:16]}),
        .n_lo({n0[15:0], 16'd0}),
        .d(d0),
        .user_in(u0),
        .out_valid(v1),
        .q(q1),
        .user_out(u1)
    );

    always @(posedge clk) begin
        if (rst) out_valid <= 1'b0;
        else if (ce) out_valid <= v1;
        if (ce) begin
            // the clip flags first: with either set, q1 is not a quotient
            if (u1[1]) begin
                y <= 32'sh7fffffff;
                sat <= 1'b1;
            end else if (u1[0]) begin
                y <= 32'sh80000000;
                sat <= 1'b1;
            end else if (!u1[2] && q1[31]) begin
                y <= 32'sh7fffffff;
                sat <= 1'b1;
            end else if (u1[2] && q1 > 32'h80000000) begin
                y <= 32'sh80000000;
                sat <= 1'b1;
            end else begin
                y <= u1[2] ? 32'd0 - q1 : q1;
                sat <= 1'b0;
            end
        end
    end
endmodule
`default_nettype wire
