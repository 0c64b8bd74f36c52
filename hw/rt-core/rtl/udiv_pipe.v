// udiv_pipe -- unsigned restoring division, one quotient bit per pipeline stage:
// q = floor(({n_hi, n_lo}) / d) for a dividend whose high part is below the divisor.
//
// Why restoring and one bit per stage: it gives the exact truncated quotient (the golden
// model's Q16.16 `/` and the dividend of its 1/sqrt core are exact integer quotients),
// accepts an operand set every clock, and its stages are plain compare-and-subtract
// adders that place well; two bits per stage would halve the latency for three
// comparators per stage. No seed section: seed 002's HLS divider is a black box.
//
// Arithmetic: with n_hi < d the quotient fits QB bits. Stage i (i = 0 .. QB-1) shifts the
// next dividend bit (n_lo[QB-1-i]) into the partial remainder r (DB + 1 bits: r < 2d)
// and subtracts d when r >= d, which sets quotient bit QB-1-i. The caller keeps n_hi < d
// (q16_div checks for overflow first); d = 0 or n_hi >= d give an unspecified q.
//
// Ports
//   n_hi (DB bits), n_lo (QB bits), d (DB bits): the dividend {n_hi, n_lo} and divisor.
//   user_in / user_out: UB bits carried alongside (signs, special cases of the caller).
//   in_valid / out_valid; ce low holds every stage.
// Timing: latency QB, one operand set per clock.
// Parameters: DB >= 1, QB >= 2, UB >= 1.
`default_nettype none
module udiv_pipe #(
    parameter integer DB = 32,
    parameter integer QB = 32,
    parameter integer UB = 1
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          ce,
    input  wire          in_valid,
    input  wire [DB-1:0] n_hi,
    input  wire [QB-1:0] n_lo,
    input  wire [DB-1:0] d,
    input  wire [UB-1:0] user_in,
    output wire          out_valid,
    output wire [QB-1:0] q,
    output wire [UB-1:0] user_out
);
    generate
        if (DB < 1 || QB < 2 || UB < 1) begin : bad_parameter
            udiv_pipe_parameter_out_of_range unsupported();
        end
    endgenerate

    // Stage s holds the state after s quotient bits: partial remainder, the dividend bits
    // still to shift in (top-aligned), the divisor, the quotient so far, the side band.
    wire [DB-1:0] rem  [0:QB];
    wire [QB-1:0] rest [0:QB];
    wire [DB-1:0] div  [0:QB];
    wire [QB-1:0] quo  [0:QB];
    wire [UB-1:0] usr  [0:QB];
    wire          vld  [0:QB];

    assign rem[0] = n_hi;
    assign rest[0] = n_lo;
    assign div[0] = d;
    assign quo[0] = {QB{1'b0}};
    assign usr[0] = user_in;
    assign vld[0] = in_valid;

    genvar s;
    generate
        for (s = 0; s < QB; s = s + 1) begin : stage
            wire [DB:0] trial = {rem[s], rest[s][QB-1]};
            // trial - d with a borrow bit; when there is no borrow the difference is
            // below d, so its bit DB is clear and not used
            /* verilator lint_off UNUSEDSIGNAL */
            wire [DB+1:0] diff = {1'b0, trial} - {2'b00, div[s]};
            /* verilator lint_on UNUSEDSIGNAL */
            wire          take = !diff[DB+1];
            wire [DB-1:0] left = take ? diff[DB-1:0] : trial[DB-1:0];
            reg  [DB-1:0] r_rem;
            reg  [QB-1:0] r_rest;
            reg  [DB-1:0] r_div;
            reg  [QB-1:0] r_quo;
            reg  [UB-1:0] r_usr;
            reg           r_vld;
            always @(posedge clk) begin
                if (rst) r_vld <= 1'b0;
                else if (ce) r_vld <= vld[s];
                if (ce) begin
                    r_rem <= left;
                    r_rest <= {rest[s][QB-2:0], 1'b0};
                    r_div <= div[s];
                    r_quo <= {quo[s][QB-2:0], take};
                    r_usr <= usr[s];
                end
            end
            assign rem[s+1] = r_rem;
            assign rest[s+1] = r_rest;
            assign div[s+1] = r_div;
            assign quo[s+1] = r_quo;
            assign usr[s+1] = r_usr;
            assign vld[s+1] = r_vld;
        end
    endgenerate

    assign out_valid = vld[QB];
    assign q = quo[QB];
    assign user_out = usr[QB];
endmodule
`default_nettype wire
