// q16_powi -- x^e for a Q16.16 word and an exponent 0..1023, as the golden model's
// `num::powi` (sim-target/src/num/approx.rs): binary exponentiation with the format's
// floored product, bit for bit (seed 002's specular power by repeated squaring, ten
// steps).
//
// Why the same bits although the order looks different: the model squares the base past
// the exponent's trailing zeros, takes acc = base at the lowest set bit, then squares and
// multiplies for each higher bit. Here every stage k squares the base and multiplies acc
// by it where bit k is set, with acc starting at 1.0; 1.0 * base floored is base exactly,
// so the first multiplication is the model's assignment, and the products agree from
// there. e = 0 gives 1.0, as the model. (Squarings past the highest set bit run here and
// not in the model; they change no result.)
//
// Ports: x, e (the exponent's 10 bits), tag (TB bits alongside); in_valid / out_valid; y.
// ce low holds every stage.
// Timing: latency LAT = 10 Q_DOT_LAT = 40 (ten stages of one product each), one operand
// per clock.
// Parameters: TB >= 1.
`default_nettype none
module q16_powi #(
    parameter integer TB = 1
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          ce,
    input  wire          in_valid,
    input  wire [31:0]   x,
    input  wire [9:0]    e,
    input  wire [TB-1:0] tag,
    output wire          out_valid,
    output wire [31:0]   y,
    output wire [TB-1:0] tag_out
);
    generate
        if (TB < 1) begin : bad_parameter
            q16_powi_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "q16_lat.vh"
    localparam integer LAT = Q_POWI_LAT;

    // stage k's inputs: base (x^(2^k)), acc, the exponent's bits still to use
    wire [31:0] base [0:10];
    wire [31:0] acc  [0:10];
    wire [9:0]  bits [0:10];
    assign base[0] = x;
    assign acc[0] = 32'h0001_0000;
    assign bits[0] = e;
    genvar k;
    generate
        for (k = 0; k < 10; k = k + 1) begin : stage
            wire [31:0] prod;
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(0)) u_sq (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(base[k]), .b(base[k]), .out_valid(), .y(base[k+1]),
                .sat());
            q16_dot #(.TERMS(1), .ROUND(0)) u_mul (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(acc[k]), .b(base[k]), .out_valid(), .y(prod), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
            wire [31:0] acc_k2;
            dly #(.W(32 + 10), .N(Q_DOT_LAT)) u_keep (.clk(clk), .rst(rst), .ce(ce),
                .d({acc[k], bits[k]}), .q({acc_k2, bits[k+1]}));
            assign acc[k+1] = bits[k+1][k] ? prod : acc_k2;
        end
    endgenerate
    assign y = acc[10];

    dly #(.W(1), .N(LAT), .RESET(1)) u_valid (.clk(clk), .rst(rst), .ce(ce), .d(in_valid),
        .q(out_valid));
    dly #(.W(TB), .N(LAT)) u_tag (.clk(clk), .rst(rst), .ce(ce), .d(tag), .q(tag_out));
endmodule
`default_nettype wire
