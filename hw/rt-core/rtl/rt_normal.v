// rt_normal -- the shading normal at a ray's nearest hit, as the golden model's `trace`
// computes it (sim-target/src/rt/kernel.rs): the object-space hit point
// lp = lo + ld.scale(t) (`mul_rn` per component, saturating sum), the shape's normal
// there (`shapes::normal`), back to world space by the transpose of M^-1 (each row one
// `dot3`), normalised (`q16_norm3`), and turned towards the ray when it points away from
// it: n = -n when n.d >= 0 (INTERNAL_SHADING, seed 002 §3.5: both sides shade).
//
// Shape normals (rt_map.vh codes): sphere lp; plane, disk, square (0, 1, 0); cylinder
// (x, 0, z); cone (x, 1 - y, z); cube the axis of the largest |component| (x before y
// before z on ties) with that component's sign, |.| saturating as the model's `abs`.
//
// Ports: shape, lo, ld (the object-space ray), t (its hit distance), m (M^-1 row-major as
// rt_xform takes it), d (the world-space ray direction), tag (TB bits alongside);
// in_valid / out_valid; n (world space, unit, facing the ray). ce low holds every stage.
// Timing: latency LATENCY = 3 Q_DOT_LAT + Q_NORM3_LAT + 4 = 103 (hit point Q_DOT_LAT + 1,
// |components| 1, shape normal 1, transform Q_DOT_LAT, normalise Q_NORM3_LAT, facing
// test Q_DOT_LAT, flip 1), one hit per clock; no clock holds more than one carry chain
// and its multiplexers.
// Parameters: TB >= 1.
`default_nettype none
`include "rt_map.vh"
module rt_normal #(
    parameter integer TB = 1
) (
    input  wire                      clk,
    input  wire                      rst,
    input  wire                      ce,
    input  wire                      in_valid,
    input  wire [`RT_SHAPE_BITS-1:0] shape,
    input  wire [95:0]               lo,
    input  wire [95:0]               ld,
    input  wire [31:0]               t,
    input  wire [287:0]              m,
    input  wire [95:0]               d,
    input  wire [TB-1:0]             tag,
    output wire                      out_valid,
    output reg  [95:0]               n,
    output wire [TB-1:0]             tag_out
);
    generate
        if (TB < 1) begin : bad_parameter
            rt_normal_parameter_out_of_range unsupported();
        end
    endgenerate

    `include "q16_ops.vh"

    // the stages: hit point, shape normal, world normal, normalised, facing the ray
    localparam integer T_LP = Q_DOT_LAT + 1;
    localparam integer T_ABS = T_LP + 1;
    localparam integer T_ON = T_ABS + 1;
    localparam integer T_NW = T_ON + Q_DOT_LAT;
    localparam integer T_NN = T_NW + Q_NORM3_LAT;
    localparam integer LATENCY = T_NN + Q_DOT_LAT + 1;
    localparam integer SB = `RT_SHAPE_BITS;

    // ld * t
    wire [95:0] ldt;
    genvar c;
    generate
        for (c = 0; c < 3; c = c + 1) begin : scale
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(1), .ROUND(1)) u_s (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a(ld[32*c +: 32]), .b(t), .out_valid(), .y(ldt[32*c +: 32]),
                .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    wire [95:0] lo_dt;
    wire [SB-1:0] shape_dt;
    dly #(.W(96 + SB), .N(Q_DOT_LAT)) u_lo_dt (.clk(clk), .rst(rst), .ce(ce), .d({shape, lo}),
        .q({shape_dt, lo_dt}));

    // T_LP: lp = lo + ld * t
    reg [95:0] lp;
    reg [SB-1:0] shape_lp;
    always @(posedge clk) begin
        if (ce) begin
            lp <= {q_add(lo_dt[95:64], ldt[95:64]), q_add(lo_dt[63:32], ldt[63:32]),
                    q_add(lo_dt[31:0], ldt[31:0])};
            shape_lp <= shape_dt;
        end
    end

    // T_ABS: |x|, |y|, |z| (the cube's test compares them), lp beside them
    reg [95:0] lp_a;
    reg [SB-1:0] shape_a;
    reg [31:0] ax, ay, az;
    always @(posedge clk) begin
        if (ce) begin
            lp_a <= lp;
            shape_a <= shape_lp;
            ax <= q_abs(lp[31:0]);
            ay <= q_abs(lp[63:32]);
            az <= q_abs(lp[95:64]);
        end
    end

    // T_ON: the shape's normal at lp
    wire [31:0] px = lp_a[31:0], py = lp_a[63:32], pz = lp_a[95:64];
    // -1 for a negative component, else 1
    function [31:0] sgn(input negative);
        sgn = negative ? q_neg(Q_ONE) : Q_ONE;
    endfunction
    reg [95:0] on;
    always @(posedge clk) begin
        if (ce) begin
            case (shape_a)
                `RT_SHAPE_SPHERE: on <= lp_a;
                `RT_SHAPE_CYLINDER: on <= {pz, 32'd0, px};
                `RT_SHAPE_CONE: on <= {pz, q_sub(Q_ONE, py), px};
                `RT_SHAPE_CUBE: begin
                    if (!q_lt(ax, ay) && !q_lt(ax, az)) on <= {32'd0, 32'd0, sgn(px[31])};
                    else if (!q_lt(ay, az)) on <= {32'd0, sgn(py[31]), 32'd0};
                    else on <= {sgn(pz[31]), 32'd0, 32'd0};
                end
                default: on <= {32'd0, Q_ONE, 32'd0};  // plane, disk, square
            endcase
        end
    end

    // T_NW: back to world space by the transpose of M^-1: row r is column r of m
    wire [287:0] m_on;
    dly #(.W(288), .N(T_ON)) u_m_on (.clk(clk), .rst(rst), .ce(ce), .d(m), .q(m_on));
    wire [95:0] nw;
    genvar r;
    generate
        for (r = 0; r < 3; r = r + 1) begin : row
            /* verilator lint_off PINCONNECTEMPTY */
            q16_dot #(.TERMS(3), .ROUND(1)) u_n (.clk(clk), .rst(rst), .ce(ce),
                .in_valid(1'b1), .a({m_on[32*(6+r) +: 32], m_on[32*(3+r) +: 32], m_on[32*r +: 32]}),
                .b(on), .out_valid(), .y(nw[32*r +: 32]), .sat());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate

    // T_NN: normalised
    wire [95:0] nn;
    /* verilator lint_off PINCONNECTEMPTY */
    q16_norm3 #(.TB(1)) u_norm (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .x(nw[31:0]), .y(nw[63:32]), .z(nw[95:64]), .tag(1'b0), .out_valid(),
        .nx(nn[31:0]), .ny(nn[63:32]), .nz(nn[95:64]), .tag_out());
    /* verilator lint_on PINCONNECTEMPTY */

    // n.d, with n alongside
    wire [95:0] d_nn;
    dly #(.W(96), .N(T_NN)) u_d_nn (.clk(clk), .rst(rst), .ce(ce), .d(d), .q(d_nn));
    // only its sign is read
    /* verilator lint_off UNUSEDSIGNAL */
    wire [31:0] nd;
    /* verilator lint_on UNUSEDSIGNAL */
    /* verilator lint_off PINCONNECTEMPTY */
    q16_dot #(.TERMS(3), .ROUND(1)) u_nd (.clk(clk), .rst(rst), .ce(ce), .in_valid(1'b1),
        .a(nn), .b(d_nn), .out_valid(), .y(nd), .sat());
    /* verilator lint_on PINCONNECTEMPTY */
    wire [95:0] nn_nd;
    dly #(.W(96), .N(Q_DOT_LAT)) u_nn_nd (.clk(clk), .rst(rst), .ce(ce), .d(nn), .q(nn_nd));

    // LATENCY: facing the ray
    always @(posedge clk) begin
        if (ce) begin
            if (!nd[31])
                n <= {q_neg(nn_nd[95:64]), q_neg(nn_nd[63:32]), q_neg(nn_nd[31:0])};
            else
                n <= nn_nd;
        end
    end

    dly #(.W(1), .N(LATENCY), .RESET(1)) u_valid (.clk(clk), .rst(rst), .ce(ce),
        .d(in_valid), .q(out_valid));
    dly #(.W(TB), .N(LATENCY)) u_tag (.clk(clk), .rst(rst), .ce(ce), .d(tag), .q(tag_out));
endmodule
`default_nettype wire
