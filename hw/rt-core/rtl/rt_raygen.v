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
// Timing: latency Q_DOT_LAT + 5 + Q_NORM3_LAT = 96 (round 3, scale Q_DOT_LAT, sum 1,
// difference 1, normalise Q_NORM3_LAT), one sample per clock; no clock holds more than
// one carry chain.
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
    // the stages: the position words, u*x + v*y, d' = (u*x + v*y) - w
    localparam integer T_POS = 3;
    localparam integer T_SUM = T_POS + Q_DOT_LAT + 1;
    localparam integer T_D = T_SUM + 1;

    // the sample's position rounded to Q16.16, half away from zero, one carry chain per
    // clock: the magnitude, the rounded word, the sign again; r's bits above 31 are zero
    // for every |p| < 2^52, the range the host guarantees
    reg [PB-1:0] mx1, my1;
    // bits above 31 are zero in the host's range, and not read
    /* verilator lint_off UNUSEDSIGNAL */
    reg [PB-1:0] rx2, ry2;
    /* verilator lint_on UNUSEDSIGNAL */
    reg          sx1, sy1, sx2, sy2;
    reg [31:0]   x1, y1;
    always @(posedge clk) begin
        if (ce) begin
            sx1 <= px[PB-1];
            sy1 <= py[PB-1];
            mx1 <= px[PB-1] ? 0 - px : px;
            my1 <= py[PB-1] ? 0 - py : py;
            sx2 <= sx1;
            sy2 <= sy1;
            rx2 <= (mx1 + (1 << 23)) >> 24;
            ry2 <= (my1 + (1 << 23)) >> 24;
            x1 <= sx2 ? 32'd0 - rx2[31:0] : rx2[31:0];
            y1 <= sy2 ? 32'd0 - ry2[31:0] : ry2[31:0];
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

    // valid and tag to d'
    wire          valid_sum;
    wire [TB-1:0] tag_sum;
    dly #(.W(1), .N(T_D), .RESET(1)) u_valid_sum (.clk(clk), .rst(rst), .ce(ce), .d(in_valid),
        .q(valid_sum));
    dly #(.W(TB), .N(T_D)) u_tag_sum (.clk(clk), .rst(rst), .ce(ce), .d(tag), .q(tag_sum));

    // d' = (ux + vy) - w, one saturating operation per clock
    reg [31:0] sx, sy, sz, rx, ry, rz;
    always @(posedge clk) begin
        if (ce) begin
            sx <= q_add(uxx, vyx);
            sy <= q_add(uxy, vyy);
            sz <= q_add(uxz, vyz);
            rx <= q_sub(sx, wx);
            ry <= q_sub(sy, wy);
            rz <= q_sub(sz, wz);
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
