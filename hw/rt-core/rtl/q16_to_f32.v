// q16_to_f32 -- a Q16.16 word as IEEE binary32, rounded to nearest, ties to even: the
// golden model's `to_f64() as f32` (the f64 is exact, so one rounding), which its depth
// and normal planes hold and the read-back window gives out (protocol::frame's
// DepthF32 and NormalF32; seed 002 §3.8 reads the frame back to the host).
//
// Why a unit: every word of those planes passes through it, and its rounding (a 32-bit
// magnitude into 24 significant bits) is where a converter goes wrong by an LSB.
//
// Arithmetic: 0 gives +0.0. Otherwise m = |q| (2^31 for -2^31), k its leading one,
// value = m * 2^-16, exponent k - 16 + 127; k <= 23 shifts left exactly, k > 23 drops
// k - 23 bits, rounded to nearest even, a carry out of the significand bumping the
// exponent. Every Q16.16 word is a normal binary32 (2^-16 .. 2^15), so nothing else
// arises.
//
// Ports: q in with in_valid; y out with out_valid; ce low holds both stages.
// Timing: latency 2 (magnitude and leading one, then shift and rounding), one word per
// clock.
`default_nettype none
module q16_to_f32 (
    input  wire        clk,
    input  wire        rst,
    input  wire        ce,
    input  wire        in_valid,
    input  wire [31:0] q,
    output reg         out_valid,
    output reg  [31:0] y
);
    // ---- 1: sign, magnitude, its leading one ----------------------------------------------
    function [4:0] lead(input [31:0] v);
        integer i;
        begin
            lead = 5'd0;
            for (i = 0; i < 32; i = i + 1) if (v[i]) lead = i[4:0];
        end
    endfunction
    reg        v1, s1, z1;
    reg [31:0] m1;
    reg [4:0]  k1;
    wire [31:0] mag = q[31] ? 32'd0 - q : q;
    always @(posedge clk) begin
        if (rst) v1 <= 1'b0;
        else if (ce) v1 <= in_valid;
        if (ce) begin
            s1 <= q[31];
            z1 <= q == 32'd0;
            m1 <= mag;
            k1 <= lead(mag);
        end
    end

    // ---- 2: the significand, rounded to nearest even --------------------------------------
    // m shifted so its leading one is bit 31: the significand is bits 31..8, the rest the
    // rounding's guard (bit 7) and sticky bits
    wire [31:0] norm = m1 << (5'd31 - k1);
    wire        guard = norm[7];
    wire        sticky = norm[6:0] != 7'd0;
    wire [24:0] sig = {1'b0, norm[31:8]} + {24'd0, guard && (sticky || norm[8])};
    wire [7:0]  e = {3'd0, k1} + 8'd111 + {7'd0, sig[24]};  // k - 16 + 127
    wire [22:0] frac = sig[24] ? sig[23:1] : sig[22:0];
    always @(posedge clk) begin
        if (rst) out_valid <= 1'b0;
        else if (ce) out_valid <= v1;
        if (ce) y <= z1 ? 32'd0 : {s1, e, frac};
    end
endmodule
`default_nettype wire
