// rt_raygen -- the primary ray through a sample's image-plane position: the golden
// model's d = (u*x + v*y - w).normalize() (sim-target/src/rt/kernel.rs, `row` and
// `FrameCtx::new`; seed 002 §3.2, ViRAY's camera basis), bit for bit.
//
// Why the position comes in as an exact integer: the model places sample column c at
// x = (2c + 1 - width*g) * K and sample row r at y = (height*g - 2r - 1) * K, with the
// pixel pitch K an integer number of 2^-40 (scene register `camera.pitch`, derived by the
// host), and rounds the exact product to Q16.16 half away from zero
// (sim-target/src/rt/derive.rs). The caller keeps n*K as a running sum (adding 2K per
// column), so here the product is already exact and only the rounding is left:
// word = sign * ((|n*K| + 2^23) >> 24). The caller guarantees |n*K| < 2^52 (the host
// refuses a wider field of view), where the model's f64 is exact too.
//
// Then, as the model: ux = u.scale(x) and vy = v.scale(y) (each component `mul_rn`),
// d' = (ux + vy) - w (saturating), and d = d' normalised (`q16_norm3`).
//
// Ports
//   px, py: n*K of the sample's column and row, signed, 2^-40 units (PB bits).
//   ux..wz: the camera basis words (Q16.16), held for the frame.
//   tag: TB bits carried to the output beside the ray.
//   in_valid / out_valid; ce low holds every stage.
// Timing: latency 3 Q_DOT_LAT + 81 = 93 (round 1, scale Q_DOT_LAT, sum 1, normalise
// 2 Q_DOT_LAT + 79), one sample per clock.
// Parameters: PB (bits of px, py) 42..64, TB >= 1.
`default_nettype none
module rt_raygen #(
    parameter integer PB = 54,
    parameter integer TB = 16
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 ce,
    input  wire                 in_valid,
    input  wire signed [PB-1:0] px,
    input  wire signed [PB-1:0] py,
    input  wire [31:0]          ux,
    input  wire [31:0]          uy,
    input  wire [31:0]          uz,
    input  wire [31:0]          vx,
    input  wire [31:0]          vy,
    input  wire [31:0]          vz,
    input  wire [31:0]          wx,
    input  wire [31:0]          wy,
    input  wire [31:0]          wz,
    input  wire [TB-1:0]        tag,
    output wire                 out_valid,
    output wire [31:0]          dx,
    output wire [31:0]          dy,
    output wire [31:0]          dz,
    output wire [TB-1:0]        tag_out
);
    generate
        if (PB < 42 || PB > 64 || TB < 1) begin : bad_parameter
            rt_raygen_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "q16_ops.vh"
    // the stage of d' = (ux + vy) - w
    localparam integer T_SUM = 2 + Q_DOT_LAT;

    // the sample's position rounded to Q16.16, half away from zero; r's bits above 31 are
    // zero for every |p| < 2^52, the range the host guarantees
    /* verilator lint_off UNUSEDSIGNAL */
    function [31:0] round_pitch(input signed [PB-1:0] p);
        reg [PB-1:0] mag;
        reg [PB-1:0] r;
        begin
            mag = p[PB-1] ? 0 - p : p;
            r = (mag + (1 << 23)) >> 24;
            round_pitch = p[PB-1] ? 32'd0 - r[31:0] : r[31:0];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */

    // stage 1: the position words
    reg [31:0] x1, y1;
    always @(posedge clk) begin
        if (ce) begin
            x1 <= round_pitch(px);
            y1 <= round_pitch(py);
        end
    end

    // u*x, v*y
    wire [31:0] uxx, uxy, uxz, vyx, vyy, vyz;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(1), .ROUND(1)) u_ux (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(ux), .b(x1), .out_valid(), .y(uxx), .sat());
    q16_dot #(.TERMS(1), .ROUND(1)) u_uy (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(uy), .b(x1), .out_valid(), .y(uxy), .sat());
    q16_dot #(.TERMS(1), .ROUND(1)) u_uz (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(uz), .b(x1), .out_valid(), .y(uxz), .sat());
    q16_dot #(.TERMS(1), .ROUND(1)) u_vx (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(vx), .b(y1), .out_valid(), .y(vyx), .sat());
    q16_dot #(.TERMS(1), .ROUND(1)) u_vy (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(vy), .b(y1), .out_valid(), .y(vyy), .sat());
    q16_dot #(.TERMS(1), .ROUND(1)) u_vz (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(vz), .b(y1), .out_valid(), .y(vyz), .sat());
    /* verilator lint_on PINCONNECTEMPTY */

    // valid and tag to the sum's stage
    wire          valid_sum;
    wire [TB-1:0] tag_sum;
    dly #(.W(1), .N(T_SUM), .RESET(1)) u_valid_sum (.clk(clk), .rst(rst), .ce(ce), .d(in_valid),
        .q(valid_sum));
    dly #(.W(TB), .N(T_SUM)) u_tag_sum (.clk(clk), .rst(rst), .ce(ce), .d(tag), .q(tag_sum));

    // d' = (ux + vy) - w
    reg [31:0] rx, ry, rz;
    always @(posedge clk) begin
        if (ce) begin
            rx <= q_sub(q_add(uxx, vyx), wx);
            ry <= q_sub(q_add(uxy, vyy), wy);
            rz <= q_sub(q_add(uxz, vyz), wz);
        end
    end

    // d = d' normalised
    wire [TB-1:0] norm_tag;
    q16_norm3 #(.TB(TB)) u_norm (.clk(clk), .rst(rst), .ce(ce), .in_valid(valid_sum),
        .x(rx), .y(ry), .z(rz), .tag(tag_sum), .out_valid(out_valid), .nx(dx), .ny(dy),
        .nz(dz), .tag_out(norm_tag));
    assign tag_out = norm_tag;
endmodule
`default_nettype wire
