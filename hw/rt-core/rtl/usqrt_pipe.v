// usqrt_pipe -- unsigned integer square root, one root bit per pipeline stage:
// root = floor(sqrt(x)) for an NB-bit x.
//
// Why digit by digit: the golden model's Q16.16 square root and reciprocal square root
// are correctly rounded, which an integer root reproduces exactly (q16_sqrt, q16_rsqrt
// round it), where a table seed with Newton-Raphson steps would be off by an LSB in
// places. Each stage is one compare-and-subtract, like udiv_pipe's. No seed section:
// seed 002 takes the square root from the HLS math library.
//
// Arithmetic: stage i brings down the next two bits of x into the partial remainder and
// tries the root bit: with the root so far r, it subtracts 4r + 1 from the remainder
// when that fits, and the bit is 1. The remainder stays at most 2r, RB + 2 bits.
//
// Ports
//   x (NB bits, NB even), user_in / user_out: UB bits carried alongside.
//   root: NB / 2 bits. in_valid / out_valid; ce low holds every stage.
// Timing: latency NB / 2, one operand per clock.
// Parameters: NB even and >= 4, UB >= 1.
`default_nettype none
module usqrt_pipe #(
    parameter integer NB = 50,
    parameter integer UB = 1
) (
    input  wire            clk,
    input  wire            rst,
    input  wire            ce,
    input  wire            in_valid,
    input  wire [NB-1:0]   x,
    input  wire [UB-1:0]   user_in,
    output wire            out_valid,
    output wire [NB/2-1:0] root,
    output wire [UB-1:0]   user_out
);
    generate
        if (NB < 4 || NB % 2 != 0 || UB < 1) begin : bad_parameter
            usqrt_pipe_parameter_out_of_range unsupported();
        end
    endgenerate

    localparam integer RB = NB / 2;
    localparam integer W = RB + 2;  // the remainder: at most 2 * root

    wire [W-1:0]  rem  [0:RB];
    wire [NB-1:0] rest [0:RB];
    wire [RB-1:0] rt   [0:RB];
    wire [UB-1:0] usr  [0:RB];
    wire          vld  [0:RB];

    assign rem[0] = {W{1'b0}};
    assign rest[0] = x;
    assign rt[0] = {RB{1'b0}};
    assign usr[0] = user_in;
    assign vld[0] = in_valid;

    genvar s;
    generate
        for (s = 0; s < RB; s = s + 1) begin : stage
            wire [W+1:0] trial = {rem[s], rest[s][NB-1:NB-2]};
            wire [W+1:0] sub = {2'b00, rt[s], 2'b01};
            // trial - sub with a borrow bit; without a borrow the difference is at most
            // 2 * root and fits W bits, so its bits above are not used
            /* verilator lint_off UNUSEDSIGNAL */
            wire [W+2:0] diff = {1'b0, trial} - {1'b0, sub};
            /* verilator lint_on UNUSEDSIGNAL */
            wire         take = !diff[W+2];
            reg  [W-1:0]  r_rem;
            reg  [NB-1:0] r_rest;
            reg  [RB-1:0] r_rt;
            reg  [UB-1:0] r_usr;
            reg           r_vld;
            always @(posedge clk) begin
                if (rst) r_vld <= 1'b0;
                else if (ce) r_vld <= vld[s];
                if (ce) begin
                    r_rem <= take ? diff[W-1:0] : trial[W-1:0];
                    r_rest <= {rest[s][NB-3:0], 2'b00};
                    r_rt <= {rt[s][RB-2:0], take};
                    r_usr <= usr[s];
                end
            end
            assign rem[s+1] = r_rem;
            assign rest[s+1] = r_rest;
            assign rt[s+1] = r_rt;
            assign usr[s+1] = r_usr;
            assign vld[s+1] = r_vld;
        end
    endgenerate

    assign out_valid = vld[RB];
    assign root = rt[RB];
    assign user_out = usr[RB];
endmodule
`default_nettype wire
