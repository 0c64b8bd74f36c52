// rt_shade -- a pixel's colour from its nearest hit, as the golden model's `trace` and
// `row` compute it for Lambert materials with an optional Blinn-Phong highlight, point
// lights and no shadows, reflections or textures (sim-target/src/rt/kernel.rs; seed 002
// §3.5), bit for bit:
//
//   lk = ca.hadamard(La).scale(ka)  +  term(light 1)  +  ...  (rt_light, in light order)
//   c  = lk for a hit, the background for a miss
//   byte = floor(clamp(c, 0, 1) * 255)          per channel: RGB888
//
// kd c_d and k_s c_s are formed here (`mul_rn` per component) for the lanes. A material
// without an ambient term has ka = 0, whose product is 0, the model's "no term"; a lane
// beyond the scene's light count adds 0. Sums are saturating, in light order (the
// model's order: saturation makes them not associative).
//
// Ports: hit, eye, d, t, n (the ray, its nearest hit and the normal facing it), the
// hit object's material (ka, ca, kd, cd, ks, cs, e), la (the ambient light's colour),
// background, lit (bit i: lane i's light exists), lights and colours (lane i in bits
// [96i +: 96]); tag (TB bits alongside); in_valid / out_valid; colour (the Q16.16 sum
// before packing) and rgb (R in bits 23:16).
// Timing: latency 208 (kd c_d 2, the lanes 203, the sum 1, the choice 1, the packing 1),
// one pixel per clock.
// Parameters: LIGHTS 1..8 lanes (point lights built), TB >= 1.
`default_nettype none
module rt_shade #(
    parameter integer LIGHTS = 1,
    parameter integer TB = 1
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 ce,
    input  wire                 in_valid,
    input  wire                 hit,
    input  wire [95:0]          eye,
    input  wire [95:0]          d,
    input  wire [31:0]          t,
    input  wire [95:0]          n,
    input  wire [31:0]          ka,
    input  wire [95:0]          ca,
    input  wire [31:0]          kd,
    input  wire [95:0]          cd,
    input  wire [31:0]          ks,
    input  wire [95:0]          cs,
    input  wire [9:0]           e,
    input  wire [95:0]          la,
    input  wire [95:0]          background,
    input  wire [LIGHTS-1:0]    lit,
    input  wire [96*LIGHTS-1:0] lights,
    input  wire [96*LIGHTS-1:0] colours,
    input  wire [TB-1:0]        tag,
    output wire                 out_valid,
    output reg  [95:0]          colour,
    output reg  [23:0]          rgb,
    output wire [TB-1:0]        tag_out
);
    generate
        if (LIGHTS < 1 || LIGHTS > 8 || TB < 1) begin : bad_parameter
            rt_shade_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "q16_ops.vh"

    localparam integer LATENCY = 208;
    localparam integer LANE = 203;

    // ---- 1-2: kd c_d, k_s c_s; 1-4: the ambient term ----------------------------------------
    wire [95:0] kdcd, kscs, cala, amb;
    genvar c;
    generate
        for (c = 0; c < 3; c = c + 1) begin : material
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_kd (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(cd[32*c +: 32]), .b(kd), .out_valid(),
                .y(kdcd[32*c +: 32]), .sat());
            q16_dot #(.TERMS(1), .ROUND(1)) u_ks (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(cs[32*c +: 32]), .b(ks), .out_valid(),
                .y(kscs[32*c +: 32]), .sat());
            q16_dot #(.TERMS(1), .ROUND(1)) u_cala (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(ca[32*c +: 32]), .b(la[32*c +: 32]), .out_valid(),
                .y(cala[32*c +: 32]), .sat());
            q16_dot #(.TERMS(1), .ROUND(1)) u_amb (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(cala[32*c +: 32]), .b(ka2), .out_valid(),
                .y(amb[32*c +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    wire [31:0] ka2;
    dly #(.W(32), .N(2)) u_ka2 (.clk(clk), .rst(rst), .ce(ce), .d(ka), .q(ka2));
    wire [95:0] amb205;
    dly #(.W(96), .N(2 + LANE - 4)) u_amb205 (.clk(clk), .rst(rst), .ce(ce), .d(amb),
        .q(amb205));

    // the lanes' other inputs, delayed to meet kd c_d
    localparam integer LW = 96 + 96 + 32 + 96 + 10 + 96 * LIGHTS * 2 + LIGHTS;
    wire [LW-1:0] lane_in;
    dly #(.W(LW), .N(2)) u_lane_in (.clk(clk), .rst(rst), .ce(ce),
        .d({eye, d, t, n, e, lights, colours, lit}), .q(lane_in));
    wire [95:0]          eye2 = lane_in[LW-1 -: 96];
    wire [95:0]          d2 = lane_in[LW-97 -: 96];
    wire [31:0]          t2 = lane_in[LW-193 -: 32];
    wire [95:0]          n2 = lane_in[LW-225 -: 96];
    wire [9:0]           e2 = lane_in[LW-321 -: 10];
    wire [96*LIGHTS-1:0] lights2 = lane_in[LIGHTS + 96*LIGHTS +: 96*LIGHTS];
    wire [96*LIGHTS-1:0] colours2 = lane_in[LIGHTS +: 96*LIGHTS];
    wire [LIGHTS-1:0]    lit2 = lane_in[LIGHTS-1:0];

    // ---- 3-205: each light's term -----------------------------------------------------------
    wire [96*LIGHTS-1:0] terms;
    genvar l;
    generate
        for (l = 0; l < LIGHTS; l = l + 1) begin : lane
            wire [95:0] term;
            wire        on;
            /* verilator lint_off PINCONNECTEMPTY */
            rt_light #(.TB(1)) u_light (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
                .eye(eye2), .d(d2), .t(t2), .n(n2), .light(lights2[96*l +: 96]),
                .colour(colours2[96*l +: 96]), .kdcd(kdcd), .kscs(kscs), .e(e2),
                .tag(lit2[l]), .out_valid(), .term(term), .tag_out(on));
            /* verilator lint_on PINCONNECTEMPTY */
            assign terms[96*l +: 96] = on ? term : 96'd0;
        end
    endgenerate

    // ---- 206: lk = ambient + terms in light order ----------------------------------------------
    reg [95:0] lk;
    integer i;
    always @(*) begin
        lk = amb205;
        for (i = 0; i < LIGHTS; i = i + 1)
            lk = {q_add(lk[95:64], terms[96*i + 64 +: 32]),
                  q_add(lk[63:32], terms[96*i + 32 +: 32]),
                  q_add(lk[31:0], terms[96*i +: 32])};
    end
    reg [95:0] lk206;
    always @(posedge clk) if (ce) lk206 <= lk;

    // ---- 207: hit or background; 208: packing -----------------------------------------------
    wire [96:0] hb206;  // hit and background at 206
    dly #(.W(97), .N(206)) u_hb (.clk(clk), .rst(rst), .ce(ce), .d({hit, background}),
        .q(hb206));
    always @(posedge clk) if (ce) colour <= hb206[96] ? lk206 : hb206[95:0];

    // floor(clamp(v, 0, 1) * 255): the product is exact, so the byte is (v * 255) >> 16
    // (bits 23:16 of the product; the others are the fraction and zeros)
    /* verilator lint_off UNUSEDSIGNAL */
    function [7:0] pack(input [31:0] v);
        reg [31:0] cl;
        reg [39:0] p;
        begin
            cl = v[31] ? 32'd0 : (q_lt(Q_ONE, v) ? Q_ONE : v);
            p = {8'd0, cl} * 40'd255;
            pack = p[23:16];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk)
        if (ce) rgb <= {pack(colour[31:0]), pack(colour[63:32]), pack(colour[95:64])};

    dly #(.W(1), .N(LATENCY), .RESET(1)) u_valid (.clk(clk), .rst(rst), .ce(ce),
        .d(in_valid), .q(out_valid));
    dly #(.W(TB), .N(LATENCY)) u_tag (.clk(clk), .rst(rst), .ce(ce), .d(tag), .q(tag_out));
endmodule
`default_nettype wire
