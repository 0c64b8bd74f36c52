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
// Ports: o, d (object-space ray, Q16.16), tmin, tmax; hit and t at LAT.
// Timing: latency LAT = 36 (quotients 34, slabs 1, pick 1), one pair per clock; ce low
// holds everything.
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

    wire [95:0] o = {oz, oy, ox};
    wire [95:0] d = {dz, dy, dx};
    wire [95:0] t0_34, t1_34;
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
                .a(q_sub(q_neg(Q_ONE), oa)), .b(da), .out_valid(), .y(t0_34[32*k +: 32]),
                .sat());
            q16_div u_t1 (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
                .a(q_sub(Q_ONE, oa)), .b(da), .out_valid(), .y(t1_34[32*k +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate

    wire [2:0]  flat34, out34;
    wire [31:0] tmin34, tmax34;
    dly #(.W(70), .N(34)) d_ray34 (.clk(clk), .rst(rst), .ce(ce),
        .d({flat0, out0, tmin, tmax}), .q({flat34, out34, tmin34, tmax34}));

    // near and far over the axes, in the model's order x, y, z
    reg [31:0] near_c, far_c, lo, hi;
    integer a;
    always @(*) begin
        near_c = 32'h8000_0001;
        far_c = Q_MAX;
        for (a = 0; a < 3; a = a + 1) begin
            lo = q_le(t0_34[32*a +: 32], t1_34[32*a +: 32]) ? t0_34[32*a +: 32] : t1_34[32*a +: 32];
            hi = q_le(t0_34[32*a +: 32], t1_34[32*a +: 32]) ? t1_34[32*a +: 32] : t0_34[32*a +: 32];
            if (!flat34[a]) begin
                if (q_lt(near_c, lo)) near_c = lo;
                if (q_lt(hi, far_c)) far_c = hi;
            end
        end
    end

    reg        none35;
    reg [31:0] near35, far35, tmin35, tmax35;
    always @(posedge clk) if (ce) begin
        none35 <= |(flat34 & out34);
        near35 <= near_c;
        far35 <= far_c;
        tmin35 <= tmin34;
        tmax35 <= tmax34;
    end

    wire in_near = q_le(tmin35, near35) && q_le(near35, tmax35);
    wire in_far = q_le(tmin35, far35) && q_le(far35, tmax35);
    always @(posedge clk) if (ce) begin
        hit <= !none35 && !q_lt(far35, near35) && (in_near || in_far);
        t <= in_near ? near35 : far35;
    end
endmodule
`default_nettype wire
