// rt_shade -- a pixel's colour from its nearest hit, as the golden model's `trace` and
// `row` compute it for Lambert materials with an optional Blinn-Phong highlight, point
// lights, hard shadows and no reflections or textures (sim-target/src/rt/kernel.rs; seed
// 002 §3.5), bit for bit:
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
// Shadows: with `shadows` high every pixel sends out one shadow ray per lane (sh_*: the
// origin p + n.scale(bias) shared by the lanes, each lane's direction wi and extent
// dist), whether it hit or not, so the caller's schedule is fixed; the caller tests them
// and returns one occlusion word per pixel, in pixel order (occ_valid, occ: bit i, lane
// i's light is blocked). A blocked light's term is replaced by 0, which is the model's
// `continue` (the saturating sum with 0 is the identity); whether a light whose term is
// already 0 is blocked does not matter. The lanes' terms wait for their pixel's word in a
// queue of 2^TQA pixels and the words for their terms in one of 2^OQA (both in pixel
// order, so the join pops both); which one fills depends on the caller's schedule, which
// bounds both (rt_cast). With `shadows` low the terms pass without a word.
//
// Ports: hit, eye, d, t (the ray, its nearest hit), n (the normal facing the ray), the
// hit object's material (ka, ca, kd, cd, ks, cs, e), la (the ambient light's colour),
// background, lit (bit i: lane i's light exists), lights and colours (lane i in bits
// [96i +: 96]), bias (the scene's), shadows; tag (TB bits alongside); in_valid; sh_valid
// with sh_o, sh_d (lane i in [96i +: 96]), sh_tmax (lane i in [32i +: 32]); occ_valid,
// occ; out_valid with colour (the Q16.16 sum before packing), rgb (R in bits 23:16) and
// tag_out. A queue that overflows or underflows is a schedule error: rt_fifo stops the
// simulation.
// Timing (rt_light.vh, q16_lat.vh): shadow rays at stage D + L_WI = 97 (kd c_d
// D = Q_DOT_LAT = 4, the lanes' wi 93); the terms at D + L_LAT = 247 (the lanes 243) enter
// the queue; the join pops at 248 at the earliest (with shadows off, always), then the sum
// 1, the choice 1, the clamp 1, the packing 1: latency 251 + 1 without shadows. colour
// and rgb come out together.
// ce low holds every stage and the join; one pixel per clock.
// Parameters: LIGHTS 1..8 lanes (point lights built), TB >= 1, TQA, OQA >= 1.
`default_nettype none
module rt_shade #(
    parameter integer LIGHTS = 1,
    parameter integer TB = 1,
    parameter integer TQA = 3,
    parameter integer OQA = 6
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
    input  wire [31:0]          bias,
    input  wire                 shadows,
    input  wire [TB-1:0]        tag,
    output wire                 sh_valid,
    output reg  [95:0]          sh_o,
    output wire [96*LIGHTS-1:0] sh_d,
    output wire [32*LIGHTS-1:0] sh_tmax,
    input  wire                 occ_valid,
    input  wire [LIGHTS-1:0]    occ,
    output wire                 out_valid,
    output reg  [95:0]          colour,
    output reg  [23:0]          rgb,
    output wire [TB-1:0]        tag_out
);
    generate
        if (LIGHTS < 1 || LIGHTS > 8 || TB < 1 || TQA < 1 || OQA < 1) begin : bad_parameter
            rt_shade_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "q16_ops.vh"

    `include "rt_light.vh"
    localparam integer D = Q_DOT_LAT;
    localparam integer LANE = L_LAT;
    localparam integer WI = L_WI;  // the lanes' wi and dist

    // ---- D: kd c_d, k_s c_s; 2 D: the ambient term -------------------------------------
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
                .in_valid(1'b1), .a(cala[32*c +: 32]), .b(ka_cala), .out_valid(),
                .y(amb[32*c +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    wire [31:0] ka_cala;
    dly #(.W(32), .N(D)) u_ka_cala (.clk(clk), .rst(rst), .ce(ce), .d(ka), .q(ka_cala));
    wire [95:0] amb_q;
    dly #(.W(96), .N(LANE - D)) u_amb_q (.clk(clk), .rst(rst), .ce(ce), .d(amb),
        .q(amb_q));

    // the lanes' other inputs, delayed to meet kd c_d
    localparam integer LW = 96 + 96 + 32 + 96 + 10 + 96 * LIGHTS * 2 + LIGHTS;
    wire [LW-1:0] lane_in;
    dly #(.W(LW), .N(D)) u_lane_in (.clk(clk), .rst(rst), .ce(ce),
        .d({eye, d, t, n, e, lights, colours, lit}), .q(lane_in));
    wire [95:0]          eye_l = lane_in[LW-1 -: 96];
    wire [95:0]          d_l = lane_in[LW-97 -: 96];
    wire [31:0]          t_l = lane_in[LW-193 -: 32];
    wire [95:0]          n_l = lane_in[LW-225 -: 96];
    wire [9:0]           e_l = lane_in[LW-321 -: 10];
    wire [96*LIGHTS-1:0] lights_l = lane_in[LIGHTS + 96*LIGHTS +: 96*LIGHTS];
    wire [96*LIGHTS-1:0] colours_l = lane_in[LIGHTS +: 96*LIGHTS];
    wire [LIGHTS-1:0]    lit_l = lane_in[LIGHTS-1:0];

    // ---- D + 1 to D + LANE: each light's term -----------------------------------------------
    wire [96*LIGHTS-1:0] terms, ps;
    genvar l;
    generate
        for (l = 0; l < LIGHTS; l = l + 1) begin : lane
            wire [95:0] term;
            wire        on;
            /* verilator lint_off PINCONNECTEMPTY */
            rt_light #(.TB(1)) u_light (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
                .eye(eye_l), .d(d_l), .t(t_l), .n(n_l), .light(lights_l[96*l +: 96]),
                .colour(colours_l[96*l +: 96]), .kdcd(kdcd), .kscs(kscs), .e(e_l),
                .tag(lit_l[l]), .out_valid(), .term(term), .tag_out(on),
                .p(ps[96*l +: 96]), .wi(sh_d[96*l +: 96]), .extent(sh_tmax[32*l +: 32]));
            /* verilator lint_on PINCONNECTEMPTY */
            assign terms[96*l +: 96] = on ? term : 96'd0;
        end
    endgenerate

    // ---- D: n.scale(bias); D + L_P + 1: the shadow rays' origin p + n.scale(bias) ----------
    // (every lane computes the same p; lane 0's is taken)
    /* verilator lint_off UNUSEDSIGNAL */
    wire [96*LIGHTS-1:0] ps_all = ps;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [95:0] nb, nb_p;
    generate
        for (c = 0; c < 3; c = c + 1) begin : offset
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_nb (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(n[32*c +: 32]), .b(bias), .out_valid(),
                .y(nb[32*c +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    dly #(.W(96), .N(L_P)) u_nb_p (.clk(clk), .rst(rst), .ce(ce), .d(nb), .q(nb_p));
    reg [95:0] po;
    always @(posedge clk) begin
        if (ce) begin
            po <= {q_add(ps_all[95:64], nb_p[95:64]), q_add(ps_all[63:32], nb_p[63:32]),
                    q_add(ps_all[31:0], nb_p[31:0])};
        end
    end
    wire [95:0] po_wi;
    dly #(.W(96), .N(WI - L_P - 2)) u_po (.clk(clk), .rst(rst), .ce(ce), .d(po), .q(po_wi));
    always @(posedge clk) if (ce) sh_o <= po_wi;
    dly #(.W(1), .N(D + WI), .RESET(1)) u_sh_valid (.clk(clk), .rst(rst), .ce(ce),
        .d(in_valid && shadows), .q(sh_valid));

    // ---- D + LANE: the pixel waits for its occlusion word; both queues in pixel order -------
    wire         v_q;
    dly #(.W(1), .N(D + LANE), .RESET(1)) u_v_q (.clk(clk), .rst(rst), .ce(ce), .d(in_valid),
        .q(v_q));
    wire [97+TB-1:0] hbt_q;  // hit, background and tag at D + LANE
    dly #(.W(97 + TB), .N(D + LANE)) u_hbt (.clk(clk), .rst(rst), .ce(ce),
        .d({hit, background, tag}), .q(hbt_q));
    localparam integer QW = 97 + TB + 96 + 96 * LIGHTS;
    wire [QW-1:0] tq_head;
    wire          tq_empty, oq_empty;
    wire [LIGHTS-1:0] oq_head;
    wire          join_ = ce && !tq_empty && (!shadows || !oq_empty);
    /* verilator lint_off PINCONNECTEMPTY */
    rt_fifo #(.W(QW), .AW(TQA)) u_tq (.clk(clk), .rst(rst), .push(ce && v_q),
        .din({hbt_q, amb_q, terms}), .pop(join_), .dout(tq_head), .empty(tq_empty),
        .count(), .ovf(), .unf());
    rt_fifo #(.W(LIGHTS), .AW(OQA)) u_oq (.clk(clk), .rst(rst), .push(ce && occ_valid),
        .din(occ), .pop(join_ && shadows), .dout(oq_head), .empty(oq_empty),
        .count(), .ovf(), .unf());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [96*LIGHTS-1:0] j_terms = tq_head[96*LIGHTS-1:0];
    wire [95:0]          j_amb = tq_head[96*LIGHTS +: 96];
    wire [TB-1:0]        j_tag = tq_head[96*LIGHTS + 96 +: TB];
    wire [96:0]          j_hb = tq_head[QW-1 -: 97];
    wire [LIGHTS-1:0]    j_occ = shadows ? oq_head : {LIGHTS{1'b0}};

    // ---- join + 1: lk = ambient + the unblocked terms in light order --------------------------
    reg [95:0] lk;
    reg [95:0] tm;
    integer i;
    always @(*) begin
        lk = j_amb;
        for (i = 0; i < LIGHTS; i = i + 1) begin
            tm = j_occ[i] ? 96'd0 : j_terms[96*i +: 96];
            lk = {q_add(lk[95:64], tm[95:64]), q_add(lk[63:32], tm[63:32]),
                  q_add(lk[31:0], tm[31:0])};
        end
    end
    reg [95:0]   lk1;
    reg [96:0]   hb1;
    reg [TB-1:0] tag1, tag2, tag3, tag4;
    reg          v1, v2, v3, v4;
    always @(posedge clk) begin
        if (rst) begin
            v1 <= 1'b0;
            v2 <= 1'b0;
            v3 <= 1'b0;
            v4 <= 1'b0;
        end else if (ce) begin
            v1 <= join_;
            v2 <= v1;
            v3 <= v2;
            v4 <= v3;
        end
        if (ce) begin
            lk1 <= lk;
            hb1 <= j_hb;
            tag1 <= j_tag;
            tag2 <= tag1;
            tag3 <= tag2;
            tag4 <= tag3;
        end
    end

    // ---- join + 2: hit or background; join + 3: clamped to [0, 1]; join + 4: the bytes
    // (one carry chain per clock: the clamp's comparison, then the product)
    function [31:0] clamp01(input [31:0] v);
        clamp01 = v[31] ? 32'd0 : (q_lt(Q_ONE, v) ? Q_ONE : v);
    endfunction
    // floor(v * 255) of a clamped v: the product is exact, so the byte is (v * 255) >> 16
    // (bits 23:16 of the product; the others are the fraction and zeros)
    /* verilator lint_off UNUSEDSIGNAL */
    function [7:0] byte255(input [31:0] cl);
        reg [39:0] pr;
        begin
            pr = {8'd0, cl} * 40'd255;
            byte255 = pr[23:16];
        end
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */
    reg [95:0] c2, c3, cl3;
    always @(posedge clk) begin
        if (ce) begin
            c2 <= hb1[96] ? lk1 : hb1[95:0];
            c3 <= c2;
            cl3 <= {clamp01(c2[95:64]), clamp01(c2[63:32]), clamp01(c2[31:0])};
            colour <= c3;
            rgb <= {byte255(cl3[31:0]), byte255(cl3[63:32]), byte255(cl3[95:64])};
        end
    end
    assign out_valid = v4;
    assign tag_out = tag4;
endmodule
`default_nettype wire
