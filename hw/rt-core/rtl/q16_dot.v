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
// Ports
//   a, b: TERMS words each, term k in bits [32k+31 : 32k], two's complement Q16.16.
//   in_valid / out_valid: a result per accepted operand set; ce low holds the pipeline.
// Timing: latency 2 (products, then sum / round / clamp), one operand set per clock.
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
    generate
        if (TERMS < 1 || TERMS > 4 || (ROUND != 0 && ROUND != 1)) begin : bad_parameter
            q16_dot_parameter_out_of_range unsupported();
        end
    endgenerate

    localparam integer SUM_BITS = 66;  // four 63-bit magnitudes and the sign
    localparam signed [SUM_BITS-1:0] HALF = ROUND != 0 ? 66'sd32768 : 66'sd0;
    localparam signed [SUM_BITS-17:0] WORD_MAX = 50'sd2147483647;
    localparam signed [SUM_BITS-17:0] WORD_MIN = -50'sd2147483648;

    reg signed [63:0] prod [0:TERMS-1];
    reg               v1;
    integer k;

    always @(posedge clk) begin
        if (ce) begin
            for (k = 0; k < TERMS; k = k + 1)
                prod[k] <= $signed(a[32*k +: 32]) * $signed(b[32*k +: 32]);
        end
    end

    reg signed [SUM_BITS-1:0] sum;
    reg signed [SUM_BITS-17:0] scaled;
    always @(*) begin
        sum = HALF;
        for (k = 0; k < TERMS; k = k + 1)
            sum = sum + {{(SUM_BITS - 64){prod[k][63]}}, prod[k]};
        scaled = sum[SUM_BITS-1:16];
    end

    always @(posedge clk) begin
        if (rst) begin
            v1 <= 1'b0;
            out_valid <= 1'b0;
        end else if (ce) begin
            v1 <= in_valid;
            out_valid <= v1;
        end
        if (ce) begin
            if (scaled > WORD_MAX) begin
                y <= 32'sh7fffffff;
                sat <= 1'b1;
            end else if (scaled < WORD_MIN) begin
                y <= 32'sh80000000;
                sat <= 1'b1;
            end else begin
                y <= scaled[31:0];
                sat <= 1'b0;
            end
        end
    end
endmodule
`default_nettype wire
