// q16_dot -- a sum of TERMS products of Q16.16 words, rounded once and saturated: the
// golden model's Q16.16 `*` (TERMS = 1, ROUND = 0), `mul_rn` (TERMS = 1, ROUND = 1),
// `dot2` (2, 1) and `dot3` (3, 1), bit for bit (sim-target/src/num/formats.rs).
//
// Why one module: the model forms the exact sum of the double-width products and rounds
// once at the end, as a DSP cascade with a wide accumulator does; a single product is the
// one-term case of the same sum, so one datapath (and one set of properties) serves all.
// Seed 002 §3 computes in `ap_fixed<32,16>` with AP_SAT: results beyond the word clip to
// its limits, as here, instead of wrapping.
//
// Arithmetic: p = a0*b0 + ... (exact, 64 + clog2(TERMS) bits), then
// y = clamp((p + (ROUND ? 2^15 : 0)) >>> 16, -2^31, 2^31 - 1): floor of the scaled sum
// (ROUND = 0, `ap_fixed`'s AP_TRN) or round half up (ROUND = 1). `sat` is high when the
// clamp changed the value (the model's saturation counter counts those).
//
// Why four stages: at 100 MHz a 32 x 32 product cannot share a clock with the logic that
// forms its operands (a saturating negation is four LUT levels) nor with the adders that
// join its partial products. So the operands are registered, each product is split into
// four 18 x 18 multiplier-sized pieces (a = ah 2^16 + al, al unsigned), the pieces are
// registered, joined into the term's product, and only then summed, rounded and clamped.
// The clamp tests the top 19 bits of the scaled sum for one sign instead of comparing 50
// bits.
//
// Ports
//   a, b: TERMS words each, term k in bits [32k+31 : 32k], two's complement Q16.16.
//   in_valid / out_valid: a result per accepted operand set; ce low holds the pipeline.
// Timing: latency Q_DOT_LAT = 4 (q16_lat.vh: operands, partial products, term products,
// sum / round / clamp), one operand set per clock.
// Parameters: TERMS 1..4, ROUND 0 or 1 (others stop elaboration).
`default_nettype none
module q16_dot #(
    parameter integer TERMS = 3,
    parameter integer ROUND = 1
) (
    input  wire                    clk,
    input  wire                    rst,
    input  wire                    ce,
    input  wire                    in_valid,
    input  wire [32*TERMS-1:0]     a,
    input  wire [32*TERMS-1:0]     b,
    output reg                     out_valid,
    output reg  signed [31:0]      y,
    output reg                     sat
);
    `include "q16_lat.vh"

    generate
        if (TERMS < 1 || TERMS > 4 || (ROUND != 0 && ROUND != 1)) begin : bad_parameter
            q16_dot_parameter_out_of_range unsupported();
        end
        if (Q_DOT_LAT != 4) begin : bad_latency
            q16_dot_stage_count_differs_from_q_dot_lat unsupported();
        end
    endgenerate

    localparam integer SUM_BITS = 66;  // four 63-bit magnitudes and the sign
    localparam signed [SUM_BITS-1:0] HALF = ROUND != 0 ? 66'sd32768 : 66'sd0;

    // stage 1: the operands
    reg [32*TERMS-1:0] a1, b1;
    // stage 2: each term's pieces: ah*bh, ah*bl, al*bh (17 x 17 signed), al*bl
    reg signed [31:0] p_hh [0:TERMS-1];
    reg signed [33:0] p_hl [0:TERMS-1];
    reg signed [33:0] p_lh [0:TERMS-1];
    reg        [31:0] p_ll [0:TERMS-1];
    // stage 3: each term's exact product
    reg signed [63:0] prod [0:TERMS-1];
    reg [2:0] v;
    integer k;

    always @(posedge clk) begin
        if (ce) begin
            a1 <= a;
            b1 <= b;
            for (k = 0; k < TERMS; k = k + 1) begin
                p_hh[k] <= $signed(a1[32*k+16 +: 16]) * $signed(b1[32*k+16 +: 16]);
                p_hl[k] <= $signed({a1[32*k+31], a1[32*k+16 +: 16]})
                    * $signed({1'b0, b1[32*k +: 16]});
                p_lh[k] <= $signed({1'b0, a1[32*k +: 16]})
                    * $signed({b1[32*k+31], b1[32*k+16 +: 16]});
                p_ll[k] <= a1[32*k +: 16] * b1[32*k +: 16];
                // ah bh 2^32 + al bl is a concatenation (al bl < 2^32)
                prod[k] <= $signed({p_hh[k], p_ll[k]})
                    + ($signed({{30{p_hl[k][33]}}, p_hl[k]} + {{30{p_lh[k][33]}}, p_lh[k]})
                       <<< 16);
            end
        end
    end

    reg signed [SUM_BITS-1:0] sum;
    reg        [SUM_BITS-17:0] scaled;
    reg                        fits;
    always @(*) begin
        sum = HALF;
        for (k = 0; k < TERMS; k = k + 1)
            sum = sum + {{(SUM_BITS - 64){prod[k][63]}}, prod[k]};
        scaled = sum[SUM_BITS-1:16];
        // the scaled sum is a word when its bits 49..31 are one sign
        fits = &scaled[SUM_BITS-17:31] || ~|scaled[SUM_BITS-17:31];
    end

    always @(posedge clk) begin
        if (rst) begin
            v <= 3'b000;
            out_valid <= 1'b0;
        end else if (ce) begin
            v <= {v[1:0], in_valid};
            out_valid <= v[2];
        end
        if (ce) begin
            if (fits) begin
                y <= scaled[31:0];
                sat <= 1'b0;
            end else begin
                y <= scaled[SUM_BITS-17] ? 32'sh80000000 : 32'sh7fffffff;
                sat <= 1'b1;
            end
        end
    end
endmodule
`default_nettype wire
