// dly -- a W-bit value N clock enables later: how a pipeline carries an operand to the
// stage that needs it (the ray's origin to the height test, tmin / tmax to the range
// tests, a tag to the output).
//
// Why a module: the core's schedules are written as "value v at stage T"; a delay of
// N stages between the producer and the consumer keeps that bookkeeping in one place
// per value, and N is checked (N = 0 is a wire).
// Why a RAM for long wide chains: the core carries rays and tags for 70-odd stages, and
// the 332-bit pair tag held in flip-flops for the intersection unit's 72 stages is
// 24 000 of them. A data chain of N >= RAM_MIN_N stages and W * N >= RAM_MIN_BITS bits
// is a ring of N - 1 words instead (write the new word, read the one written N - 1
// enables ago into a read register and then an output register, all on ce): an FPGA's
// block RAM with a registered read, a handful of EBRs where the flip-flops took
// thousands, and the same q clock for clock.
// Ports: d in, q = d of N enabled cycles ago; RESET = 1 clears the chain on rst (for
// valid bits; data chains have no reset, and a ring's rst only rewinds its pointer).
// ce low holds it.
// Timing: latency N.
// Parameters: W >= 1 bits, N >= 0 stages; RESET 0 or 1; RAM_MIN_N >= 2 and RAM_MIN_BITS
// choose the ring (a chain with RESET = 1 never is one).
`default_nettype none
module dly #(
    parameter integer W = 32,
    parameter integer N = 1,
    parameter integer RESET = 0,
    parameter integer RAM_MIN_N = 16,
    parameter integer RAM_MIN_BITS = 1024
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         ce,
    input  wire [W-1:0] d,
    output wire [W-1:0] q
);
    generate
        if (W < 1 || N < 0 || (RESET != 0 && RESET != 1) || RAM_MIN_N < 2) begin : bad_parameter
            dly_parameter_out_of_range unsupported();
        end
        if (N == 0) begin : wire_through
            assign q = d;
            // rst, clk and ce are not needed without a register
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused = &{1'b0, clk, rst, ce};
            /* verilator lint_on UNUSEDSIGNAL */
        end else if (RESET == 0 && N >= RAM_MIN_N && W * N >= RAM_MIN_BITS) begin : ring
            // a ring of M = N - 1 words: word a was written M enables before the write
            // that follows it round the ring, so reading the word after the write address
            // gives d of M - 1 enables ago; the RAM's read register adds one and a register
            // in the fabric the last, because a block RAM's output is slow (4.1 ns on an
            // ECP5 EBR) and must not start a path of logic
            localparam integer M = N - 1;
            localparam integer AB = $clog2(M);
            localparam [31:0] LAST = M - 1;
            reg [W-1:0]  mem [0:M-1];
            reg [AB-1:0] wa;
            wire [AB-1:0] ra = wa == LAST[AB-1:0] ? {AB{1'b0}} : wa + 1'b1;
            reg [W-1:0]  r0, r;
            always @(posedge clk) begin
                if (rst) wa <= {AB{1'b0}};
                else if (ce) wa <= ra;
            end
            always @(posedge clk) begin
                if (ce) begin
                    mem[wa] <= d;
                    r0 <= mem[ra];
                    r <= r0;
                end
            end
            assign q = r;
        end else begin : chain
            // stage k in bits [W*k +: W], the oldest at the top
            reg [W*N-1:0] r;
            wire [W*N-1:0] shifted;
            if (N == 1) begin : one
                assign shifted = d;
            end else begin : many
                assign shifted = {r[W*(N-1)-1:0], d};
            end
            if (RESET != 0) begin : with_reset
                always @(posedge clk) begin
                    if (rst) r <= {W*N{1'b0}};
                    else if (ce) r <= shifted;
                end
            end else begin : data
                always @(posedge clk) if (ce) r <= shifted;
                // a data chain has no reset
                /* verilator lint_off UNUSEDSIGNAL */
                wire unused = &{1'b0, rst};
                /* verilator lint_on UNUSEDSIGNAL */
            end
            assign q = r[W*N-1 -: W];
        end
    endgenerate
endmodule
`default_nettype wire
