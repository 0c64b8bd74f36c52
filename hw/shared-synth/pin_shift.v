// pin_shift -- the two shift registers a pin wrapper puts around a design with more ports
// than a package has, for place and route only: NI input bits shifted in from `sin`, one
// per clock, and NO output bits loaded on `load` and shifted out on `sout`. Every input
// of the design is then driven and every output observed, so synthesis keeps it all, and
// its paths stay register to register.
//
// Ports: clk, sin, load, outs (the design's outputs); ins (its inputs), sout.
// Timing: one bit in and one out per clock; outs is sampled on the clock `load` is high.
// Parameters: NI >= 2, NO >= 2.
`default_nettype none
module pin_shift #(
    parameter integer NI = 2,
    parameter integer NO = 2
) (
    input  wire          clk,
    input  wire          sin,
    input  wire          load,
    input  wire [NO-1:0] outs,
    output wire [NI-1:0] ins,
    output wire          sout
);
    generate
        if (NI < 2 || NO < 2) begin : bad_parameter
            pin_shift_parameter_out_of_range unsupported();
        end
    endgenerate
    reg [NI-1:0] in_sr;
    reg [NO-1:0] out_sr;
    always @(posedge clk) begin
        in_sr <= {in_sr[NI-2:0], sin};
        out_sr <= load ? outs : {out_sr[NO-2:0], 1'b0};
    end
    assign ins = in_sr;
    assign sout = out_sr[NO-1];
endmodule
`default_nettype wire
