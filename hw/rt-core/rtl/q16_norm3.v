// q16_norm3 -- a vector made unit length as the golden model's `V3::normalize` does it
// (sim-target/src/rt/vec.rs): l2 = v.v (`dot3`, one rounding), then each component
// `mul_rn` by 1/sqrt(l2) (the format's correctly rounded core, `q16_rsqrt`), and v itself
// when l2 <= 0 (the zero vector stays zero), bit for bit.
//
// Why a module: the primary ray and the shading normal are both normalised this way, and
// the secondary rays will be; one datapath keeps the three identical.
//
// Ports: x, y, z (Q16.16), tag (TB bits carried alongside); in_valid / out_valid; nx, ny,
// nz the result. ce low holds every stage.
// Timing: latency LATENCY = 2 Q_DOT_LAT + 79 = 87 (dot3, rsqrt 79, scale), one vector
// per clock.
// Parameters: TB >= 1.
`default_nettype none
module q16_norm3 #(
    parameter integer TB = 1
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          ce,
    input  wire          in_valid,
    input  wire [31:0]   x,
    input  wire [31:0]   y,
    input  wire [31:0]   z,
    input  wire [TB-1:0] tag,
    output wire          out_valid,
    output reg  [31:0]   nx,
    output reg  [31:0]   ny,
    output reg  [31:0]   nz,
    output wire [TB-1:0] tag_out
);
    generate
        if (TB < 1) begin : bad_parameter
            q16_norm3_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "q16_lat.vh"
    localparam integer RSQRT_LAT = Q_RSQRT_LAT;
    localparam integer LATENCY = Q_NORM3_LAT;

    // l2 = v.v
    wire [31:0] l2;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(3), .ROUND(1)) u_l2 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a({z, y, x}), .b({z, y, x}), .out_valid(), .y(l2), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [95:0] v_l2;
    dly #(.W(96), .N(Q_DOT_LAT)) u_v_l2 (.clk(clk), .rst(rst), .ce(ce), .d({z, y, x}), .q(v_l2));

    // 1/sqrt(l2), with v and "l2 <= 0" alongside
    wire [31:0] inv;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_rsqrt u_inv (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1), .x(l2),
        .out_valid(), .y(inv), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [96:0] v_inv;
    dly #(.W(97), .N(RSQRT_LAT)) u_v_inv (.clk(clk), .rst(rst), .ce(ce),
        .d({$signed(l2) <= 0, v_l2}), .q(v_inv));

    // the last product: v * inv, or v when l2 <= 0
    wire [31:0] sx, sy, sz;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(1), .ROUND(1)) u_sx (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(v_inv[31:0]), .b(inv), .out_valid(), .y(sx), .sat());
    q16_dot #(.TERMS(1), .ROUND(1)) u_sy (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(v_inv[63:32]), .b(inv), .out_valid(), .y(sy), .sat());
    q16_dot #(.TERMS(1), .ROUND(1)) u_sz (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(v_inv[95:64]), .b(inv), .out_valid(), .y(sz), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [96:0] v_s;
    dly #(.W(97), .N(Q_DOT_LAT)) u_v_s (.clk(clk), .rst(rst), .ce(ce), .d(v_inv), .q(v_s));
    always @(*) begin
        if (v_s[96]) begin
            nx = v_s[31:0];
            ny = v_s[63:32];
            nz = v_s[95:64];
        end else begin
            nx = sx;
            ny = sy;
            nz = sz;
        end
    end

    dly #(.W(1), .N(LATENCY), .RESET(1)) u_valid (.clk(clk), .rst(rst), .ce(ce),
        .d(in_valid), .q(out_valid));
    dly #(.W(TB), .N(LATENCY), .RESET(0)) u_tag (.clk(clk), .rst(rst), .ce(ce),
        .d(tag), .q(tag_out));
endmodule
`default_nettype wire
