// isect_cube -- the cube [-1, 1]^3 by the slab test in object space, one (ray, object)
// pair per clock: the golden model's `shapes::cube` (sim-target/src/rt/shapes.rs), bit
// for bit. From inside, the exit face.
//
// Why six dividers: the slab test needs both slab distances of all three axes for the
// same ray, and one pair per clock allows no sharing. Seed 002 §3.4 lists the box among
// its shapes; the model's form is the textbook slab test.
//
// The model's steps: near = -(2^31 - 1), far = 2^31 - 1; per axis a (x, y, z): da = 0:
// no hit when |oa| > 1, else the axis is skipped; otherwise t0 = (-1 - oa) / da,
// t1 = (1 - oa) / da, near = max(near, min(t0, t1)), far = min(far, max(t0, t1)). Then
// near > far: no hit; near in [tmin, tmax]: near; far in [tmin, tmax]: far; else none.
//
// Why the slabs take three clocks: max and min are order-free, so a skipped axis can
// stand in as near's and far's starting values, and the axes join two, then one, at a
// time; one after another they were six comparisons in a clock.
//
// Ports: o, d (object-space ray, Q16.16), tmin, tmax; hit and t at LAT_CUBE.
// Timing: latency LAT_CUBE = Q_DIV_LAT + 4 = 39 (isect.vh: quotients, each axis's
// ordered pair 1, x with y 1, with z 1, pick 1), one pair per clock; ce low holds
// everything.
`default_nettype none
module isect_cube (
    input  wire        clk,
    input  wire        rst,
    input  wire        ce,
    input  wire [31:0] ox,
    input  wire [31:0] oy,
    input  wire [31:0] oz,
    input  wire [31:0] dx,
    input  wire [31:0] dy,
    input  wire [31:0] dz,
    input  wire [31:0] tmin,
    input  wire [31:0] tmax,
    output reg         hit,
    output reg  [31:0] t
);
    `include "q16_ops.vh"
    `include "isect.vh"

    wire [95:0] o = {oz, oy, ox};
    wire [95:0] d = {dz, dy, dx};
    wire [95:0] t0_q, t1_q;
    wire [2:0]  flat0, out0;
    genvar k;
    generate
        for (k = 0; k < 3; k = k + 1) begin : axis
            wire [31:0] oa = o[32*k +: 32];
            wire [31:0] da = d[32*k +: 32];
            assign flat0[k] = da == 32'd0;
            assign out0[k] = q_lt(Q_ONE, q_abs(oa));
            /* verilator lint_off PINCONNECTEMPTY */
            q16_div u_t0 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
                .a(q_sub(q_neg(Q_ONE), oa)), .b(da), .out_valid(), .y(t0_q[32*k +: 32]),
                .sat());
            q16_div u_t1 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
                .a(q_sub(Q_ONE, oa)), .b(da), .out_valid(), .y(t1_q[32*k +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate

    // the schedule: the quotients at T_Q, the result at T_Q + 4
    localparam integer T_Q = Q_DIV_LAT;
    generate
        if (T_Q + 4 != LAT_CUBE) begin : bad_schedule
            isect_cube_schedule_differs_from_isect_vh unsupported();
        end
    endgenerate
    // near's and far's starting values
    localparam [31:0] NEAR0 = 32'h8000_0001;
    localparam [31:0] FAR0 = Q_MAX;

    wire [2:0]  flat_q, out_q;
    wire [31:0] tmin_q, tmax_q;
    dly #(.W(70), .N(T_Q)) d_ray_q (.clk(clk), .rst(rst), .ce(ce),
        .d({flat0, out0, tmin, tmax}), .q({flat_q, out_q, tmin_q, tmax_q}));

    // T_Q + 1: each axis's pair in order; a skipped axis gives the starting values, and
    // max(NEAR0, lo) is lo but for lo = Q_MIN
    reg  [95:0] lo1, hi1;
    reg         none1;
    reg  [63:0] range1;
    generate
        for (k = 0; k < 3; k = k + 1) begin : order
            wire [31:0] t0 = t0_q[32*k +: 32], t1 = t1_q[32*k +: 32];
            wire [31:0] lo = q_le(t0, t1) ? t0 : t1;
            wire [31:0] hi = q_le(t0, t1) ? t1 : t0;
            always @(posedge clk) if (ce) begin
                lo1[32*k +: 32] <= flat_q[k] || lo == Q_MIN ? NEAR0 : lo;
                hi1[32*k +: 32] <= flat_q[k] ? FAR0 : hi;
            end
        end
    endgenerate
    always @(posedge clk) if (ce) begin
        none1 <= |(flat_q & out_q);
        range1 <= {tmin_q, tmax_q};
    end

    // T_Q + 2: x with y; T_Q + 3: with z
    reg  [31:0] near2, far2, near3, far3, loz2, hiz2;
    reg         none2, none3;
    reg  [63:0] range2, range3;
    always @(posedge clk) if (ce) begin
        near2 <= q_lt(lo1[31:0], lo1[63:32]) ? lo1[63:32] : lo1[31:0];
        far2 <= q_lt(hi1[63:32], hi1[31:0]) ? hi1[63:32] : hi1[31:0];
        loz2 <= lo1[95:64];
        hiz2 <= hi1[95:64];
        near3 <= q_lt(near2, loz2) ? loz2 : near2;
        far3 <= q_lt(hiz2, far2) ? hiz2 : far2;
        none2 <= none1;
        none3 <= none2;
        range2 <= range1;
        range3 <= range2;
    end

    // T_Q + 4: the pick
    wire [31:0] tmin3 = range3[63:32], tmax3 = range3[31:0];
    wire in_near = q_le(tmin3, near3) && q_le(near3, tmax3);
    wire in_far = q_le(tmin3, far3) && q_le(far3, tmax3);
    always @(posedge clk) if (ce) begin
        hit <= !none3 && !q_lt(far3, near3) && (in_near || in_far);
        t <= in_near ? near3 : far3;
    end
endmodule
`default_nettype wire
