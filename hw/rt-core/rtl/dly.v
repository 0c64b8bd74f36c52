// dly -- a W-bit value N clock enables later: how a pipeline carries an operand to the
// stage that needs it (the ray's origin to the height test, tmin / tmax to the range
// tests, a tag to the output).
//
// Why a module: the core's schedules are written as "value v at stage T"; a delay of
// N stages between the producer and the consumer keeps that bookkeeping in one place
// per value, and N is checked (N = 0 is a wire).
// Ports: d in, q = d of N enabled cycles ago; RESET = 1 clears the chain on rst (for
// valid bits; data chains have no reset). ce low holds it.
// Timing: latency N.
`default_nettype none
module dly #(
    parameter integer W = 32,
    parameter integer N = 1,
    parameter integer RESET = 0
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         ce,
    input  wire [W-1:0] d,
    output wire [W-1:0] q
);
    generate
        if (W < 1 || N < 0 || (RESET != 0 && RESET != 1)) begin : bad_parameter
            dly_parameter_out_of_range unsupported();
        end
        if (N == 0) begin : wire_through
            assign q = d;
            // rst, clk and ce are not needed without a register
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused = &{1'b0, clk, rst, ce};
            /* verilator lint_on UNUSEDSIGNAL */
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
