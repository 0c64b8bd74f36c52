// tri_unit -- flat triangles: edge functions, top-left rule, bounding-box traversal.
//
// Seed 000 ch. 6.5 (triangle rasterization: three edge functions, the third vertex
// fixes the orientation, the bounding box is walked one pixel test per cycle). Coverage
// is the golden model's (sim-target raster::tri, FITkit layout, subpixel_bits = 0):
//   * orientation normalised once: area = (x2-x0)(y1-y0) - (y2-y0)(x1-x0); area < 0 is
//     clockwise (y down), for which the model swaps vertices 1 and 2; area = 0
//     (degenerate) draws nothing. Swapping 1 and 2 reverses all three edges, and a
//     reversed edge's function is the negated one (whichever end point it is measured
//     from), so this unit keeps the input order's edges and tests them with the sign
//     the orientation gives: inside is e > 0 (counter-clockwise) or e < 0 (clockwise),
//     and e = 0 is decided by the top-left rule of the normalised (reversed) edge;
//   * culling from the set-up: cull[0] discards clockwise, cull[1] counter-clockwise
//     triangles (cull = 3 discards both windings);
//   * edges k = 0, 1, 2 run from input vertex (1, 2, 0) to (2, 0, 1); pixel (i, j) is
//     tested at its centre (i + 1/2, j + 1/2);
//   * top-left rule: a normalised edge with dy > 0, or dy = 0 and dx < 0 (dx, dy from its
//     start to its end) owns the pixels whose centre lies on it; the others do not;
//   * bounding box [min x, max x) x [min y, max y), clipped to the frame; empty -> nothing.
//
// Widths. The model works in doubled units (X = 2x, so pixel centres 2i + 1 are
// integers): X, Y are 10 bits unsigned (0..1022), the edge deltas A = 2dy, B = -2dx are
// 11 bits signed (|A| <= 1022), the model's per-pixel steps 2A, 2B are 12 bits signed
// (|.| <= 2044) and its edge value at a pixel centre E = A(2i + 1 - Xp) + B(2j + 1 - Yp)
// is bounded by 2 * 1022 * 1021 = 2 086 924 < 2^21 (22 bits signed) for any pixel of
// the bounding box of a 512 x 512 frame (|2i + 1 - Xp| <= 1021 there). E is always
// even, so this unit keeps e = E / 2 = dy(2i + 1 - 2xp) - dx(2j + 1 - 2yp):
//   dx, dy        10 bits signed (|.| <= 511)
//   2i + 1 - 2xp  11 bits signed (-1021..1021 inside the box, -1021..1 at its corner)
//   steps         2dy per column, -2dx per row: 11 bits signed
//   e             21 bits signed: |e| <= 2 * 511 * 1021 = 1 043 462 < 2^20
// and the model's test E - bias >= 0 (bias = 0 on top-left edges, else 1) is e >= 0 on
// top-left edges and e > 0 on the others (signs flipped for clockwise input, above).
// Three 10 x 11 -> 21-bit multipliers are shared by the set-up cycles, each product
// registered: S0 the area's two products, S1 dy * ox, S2 dx * oy per edge; S3 subtracts.
// Set-up pipeline: start latches the vertices and the edge deltas; S0 bounding box and
// offsets; S1 area sign; S2 top-left flags and the reject decision; S3 the edge values.
//
// Ports: start (one cycle, in idle) latches the vertices (9-bit unsigned pixels), color,
// the frame (wm1 = width - 1, hm1 = height - 1) and cull; frag_* is a valid/ready stream of
// covered pixels; done is a one-cycle strobe with the last pixel test.
//
// Timing: busy = 4 set-up cycles + one pixel test per cycle over the clipped bounding
// box, i.e. 4 + (min(max x, W) - min x) * (min(max y, H) - min y), the product taken
// as 0 when the box is empty, the triangle degenerate or culled; plus the cycles
// frag_ready is low while a covered pixel waits. This is the model's
// hw::SETUP_CYCLES + pixel_tests for Traversal::BoundingBox.
//
// Parameter LANES (1, 2, 4, 8; seed 000's 8-pixel parallel evaluation): each traversal
// step tests LANES pixels of a row (i .. i + LANES - 1, those past the box masked off)
// and hands the covered ones to the fragment FIFO one per cycle, lowest first. A step
// takes max(1, covered pixels in it) cycles, so busy = 4 + the sum over the box's rows
// and its ceil(box width / LANES) steps per row of max(1, covered) (plus stalls);
// LANES = 1 is the formula above.
`default_nettype none
module tri_unit #(
    parameter LANES = 1      // pixels tested per cycle: 1, 2, 4 or 8
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       start,
    input  wire [8:0] x0,
    input  wire [8:0] y0,
    input  wire [8:0] x1,
    input  wire [8:0] y1,
    input  wire [8:0] x2,
    input  wire [8:0] y2,
    input  wire [7:0] color,
    input  wire [8:0] wm1,
    input  wire [8:0] hm1,
    input  wire [1:0] cull,
    output wire       busy,
    output wire       frag_valid,
    output wire [8:0] frag_x,
    output wire [8:0] frag_y,
    output wire [7:0] frag_col,
    input  wire       frag_ready,
    output wire       done
);
    localparam [2:0] IDLE = 3'd0, S0 = 3'd1, S1 = 3'd2, S2 = 3'd3, S3 = 3'd4, RUN = 3'd5;

    reg [2:0] state;
    // Latched at start.
    reg [8:0] vx0, vy0, vx1, vy1, vx2, vy2;
    reg [7:0] col;
    reg [8:0] fw, fh;        // frame - 1
    reg [1:0] cul;
    reg signed [9:0] dx0, dy0, dx1, dy1, dx2, dy2;   // edge k: start -> end
    // After S0.
    reg       empty;
    reg [8:0] bx0, by0, bxl, byl;                    // box, inclusive
    reg signed [10:0] ox0, oy0, ox1, oy1, ox2, oy2;  // 2 box corner + 1 - 2 start
    reg signed [20:0] pa, pb;                        // the area's products
    // After S1.
    reg       cw, degen;
    reg signed [20:0] t0, t1, t2;                    // dy * ox
    // After S2.
    reg       tl0, tl1, tl2, reject;
    reg signed [20:0] u0, u1, u2;                    // dx * oy
    // Edge values: e at the current pixel, er at the current row's first pixel.
    reg signed [20:0] e0, e1, e2, er0, er1, er2;
    reg [8:0]         i, j;

    function signed [9:0] sub9(input [8:0] a, input [8:0] b);
        sub9 = $signed({1'b0, a}) - $signed({1'b0, b});
    endfunction

    function signed [10:0] offs(input [8:0] b, input [8:0] v);
        offs = $signed({1'b0, b, 1'b1}) - $signed({1'b0, v, 1'b0});
    endfunction

    // Top-left rule of the normalised edge: the input edge itself, or reversed (cw).
    function top_left(input signed [9:0] ex, input signed [9:0] ey, input rev);
        top_left = rev ? ((ey < 10'sd0) | ((ey == 10'sd0) & (ex > 10'sd0)))
                       : ((ey > 10'sd0) | ((ey == 10'sd0) & (ex < 10'sd0)));
    endfunction

    // S0: the bounding box.
    wire [8:0] minx = (vx0 <= vx1) ? ((vx0 <= vx2) ? vx0 : vx2) : ((vx1 <= vx2) ? vx1 : vx2);
    wire [8:0] maxx = (vx0 >= vx1) ? ((vx0 >= vx2) ? vx0 : vx2) : ((vx1 >= vx2) ? vx1 : vx2);
    wire [8:0] miny = (vy0 <= vy1) ? ((vy0 <= vy2) ? vy0 : vy2) : ((vy1 <= vy2) ? vy1 : vy2);
    wire [8:0] maxy = (vy0 >= vy1) ? ((vy0 >= vy2) ? vy0 : vy2) : ((vy1 >= vy2) ? vy1 : vy2);
    // Exclusive ends min(max, frame size), 10 bits.
    wire [9:0] xe = ({1'b0, maxx} <= {1'b0, fw}) ? {1'b0, maxx} : {1'b0, fw} + 10'd1;
    wire [9:0] ye = ({1'b0, maxy} <= {1'b0, fh}) ? {1'b0, maxy} : {1'b0, fh} + 10'd1;
    wire [8:0] xl = xe[8:0] - 9'd1;
    wire [8:0] yl = ye[8:0] - 9'd1;

    // The shared multipliers. area = (x2-x0)(y1-y0) - (y2-y0)(x1-x0) = dy1 dx2 - dx1 dy2.
    reg  signed [9:0]  ma0, ma1, ma2;
    reg  signed [10:0] mb0, mb1, mb2;
    wire signed [20:0] mp0 = ma0 * mb0;
    wire signed [20:0] mp1 = ma1 * mb1;
    wire signed [20:0] mp2 = ma2 * mb2;
    always @* begin
        case (state)
            S0: begin
                ma0 = dy1; mb0 = {dx2[9], dx2};
                ma1 = dx1; mb1 = {dy2[9], dy2};
                ma2 = 10'sd0; mb2 = 11'sd0;
            end
            S1: begin
                ma0 = dy0; mb0 = ox0;
                ma1 = dy1; mb1 = ox1;
                ma2 = dy2; mb2 = ox2;
            end
            S2: begin
                ma0 = dx0; mb0 = oy0;
                ma1 = dx1; mb1 = oy1;
                ma2 = dx2; mb2 = oy2;
            end
            default: begin
                ma0 = 10'sd0; mb0 = 11'sd0;
                ma1 = 10'sd0; mb1 = 11'sd0;
                ma2 = 10'sd0; mb2 = 11'sd0;
            end
        endcase
    end
    wire signed [20:0] area = pa - pb;

    // RUN: the pixel tests of one step (LANES pixels of a row) and the steps.
    localparam LG = (LANES >= 8) ? 3 : (LANES >= 4) ? 2 : (LANES >= 2) ? 1 : 0;
    localparam L  = 1 << LG;
    localparam [9:0] L10 = L;
    wire signed [20:0] sx0 = {{10{dy0[9]}}, dy0, 1'b0};
    wire signed [20:0] sx1 = {{10{dy1[9]}}, dy1, 1'b0};
    wire signed [20:0] sx2 = {{10{dy2[9]}}, dy2, 1'b0};
    wire signed [20:0] sy0 = -{{10{dx0[9]}}, dx0, 1'b0};
    wire signed [20:0] sy1 = -{{10{dx1[9]}}, dx1, 1'b0};
    wire signed [20:0] sy2 = -{{10{dx2[9]}}, dx2, 1'b0};

    // Lane g tests pixel i + g: e + g * step (past the box the value may wrap, but the
    // lane is masked off there).
    wire [L-1:0] mask;
    genvar g;
    generate
        for (g = 0; g < L; g = g + 1) begin : lane
            localparam signed [20:0] K = g;
            localparam [9:0] G10 = g;
            wire signed [20:0] v0 = e0 + sx0 * K;
            wire signed [20:0] v1 = e1 + sx1 * K;
            wire signed [20:0] v2 = e2 + sx2 * K;
            wire in0 = (v0 == 21'sd0) ? tl0 : (v0[20] == cw);
            wire in1 = (v1 == 21'sd0) ? tl1 : (v1[20] == cw);
            wire in2 = (v2 == 21'sd0) ? tl2 : (v2[20] == cw);
            assign mask[g] = (({1'b0, i} + G10) <= {1'b0, bxl}) & in0 & in1 & in2;
        end
    endgenerate

    // The covered lanes go out one per cycle, lowest first; a step takes max(1, covered).
    reg  [L-1:0] sent;                       // lanes of this step already handed over
    wire [L-1:0] pend = mask & ~sent;
    wire [L-1:0] low  = pend & (~pend + 1'b1);
    wire         one  = (pend & ~low) == {L{1'b0}};
    reg  [2:0]   idx;
    integer      q;
    always @* begin
        idx = 3'd0;
        for (q = L - 1; q >= 0; q = q - 1) if (low[q]) idx = q[2:0];
    end
    wire adv     = (state == RUN) & ((pend == {L{1'b0}}) | (one & frag_ready));
    wire row_end = ({1'b0, i} + L10) > {1'b0, bxl};
    wire last    = row_end & (j == byl);

    assign busy       = state != IDLE;
    assign frag_valid = (state == RUN) & (pend != {L{1'b0}});
    assign frag_x     = i + {6'd0, idx};
    assign frag_y     = j;
    assign frag_col   = col;
    assign done       = ((state == S3) & reject) | (adv & last);

    always @(posedge clk) begin
        if (rst) begin
            state <= IDLE;
            vx0 <= 9'd0; vy0 <= 9'd0; vx1 <= 9'd0; vy1 <= 9'd0; vx2 <= 9'd0; vy2 <= 9'd0;
            col <= 8'd0; fw <= 9'd0; fh <= 9'd0; cul <= 2'd0;
            dx0 <= 10'sd0; dy0 <= 10'sd0; dx1 <= 10'sd0; dy1 <= 10'sd0; dx2 <= 10'sd0; dy2 <= 10'sd0;
            empty <= 1'b0; bx0 <= 9'd0; by0 <= 9'd0; bxl <= 9'd0; byl <= 9'd0;
            ox0 <= 11'sd0; oy0 <= 11'sd0; ox1 <= 11'sd0; oy1 <= 11'sd0; ox2 <= 11'sd0; oy2 <= 11'sd0;
            pa <= 21'sd0; pb <= 21'sd0; cw <= 1'b0; degen <= 1'b0;
            t0 <= 21'sd0; t1 <= 21'sd0; t2 <= 21'sd0; u0 <= 21'sd0; u1 <= 21'sd0; u2 <= 21'sd0;
            tl0 <= 1'b0; tl1 <= 1'b0; tl2 <= 1'b0; reject <= 1'b0;
            e0 <= 21'sd0; e1 <= 21'sd0; e2 <= 21'sd0; er0 <= 21'sd0; er1 <= 21'sd0; er2 <= 21'sd0;
            i <= 9'd0; j <= 9'd0; sent <= {L{1'b0}};
        end else begin
            case (state)
                IDLE: if (start) begin
                    vx0 <= x0; vy0 <= y0; vx1 <= x1; vy1 <= y1; vx2 <= x2; vy2 <= y2;
                    dx0 <= sub9(x2, x1); dy0 <= sub9(y2, y1);
                    dx1 <= sub9(x0, x2); dy1 <= sub9(y0, y2);
                    dx2 <= sub9(x1, x0); dy2 <= sub9(y1, y0);
                    col <= color; fw <= wm1; fh <= hm1; cul <= cull;
                    state <= S0;
                end
                S0: begin
                    empty <= ({1'b0, minx} >= xe) | ({1'b0, miny} >= ye);
                    bx0 <= minx; by0 <= miny; bxl <= xl; byl <= yl;
                    ox0 <= offs(minx, vx1); oy0 <= offs(miny, vy1);
                    ox1 <= offs(minx, vx2); oy1 <= offs(miny, vy2);
                    ox2 <= offs(minx, vx0); oy2 <= offs(miny, vy0);
                    pa <= mp0; pb <= mp1;
                    state <= S1;
                end
                S1: begin
                    cw    <= area < 21'sd0;
                    degen <= area == 21'sd0;
                    t0 <= mp0; t1 <= mp1; t2 <= mp2;
                    state <= S2;
                end
                S2: begin
                    tl0 <= top_left(dx0, dy0, cw);
                    tl1 <= top_left(dx1, dy1, cw);
                    tl2 <= top_left(dx2, dy2, cw);
                    reject <= degen | empty | (cul[0] & cw) | (cul[1] & ~cw);
                    u0 <= mp0; u1 <= mp1; u2 <= mp2;
                    state <= S3;
                end
                S3: begin
                    e0  <= t0 - u0; e1  <= t1 - u1; e2  <= t2 - u2;
                    er0 <= t0 - u0; er1 <= t1 - u1; er2 <= t2 - u2;
                    i <= bx0;
                    j <= by0;
                    sent <= {L{1'b0}};
                    state <= reject ? IDLE : RUN;
                end
                RUN: if (adv) begin
                    sent <= {L{1'b0}};
                    if (last) begin
                        state <= IDLE;
                    end else if (row_end) begin
                        i   <= bx0;
                        j   <= j + 9'd1;
                        er0 <= er0 + sy0; er1 <= er1 + sy1; er2 <= er2 + sy2;
                        e0  <= er0 + sy0; e1  <= er1 + sy1; e2  <= er2 + sy2;
                    end else begin
                        i  <= i + L10[8:0];
                        e0 <= e0 + (sx0 <<< LG); e1 <= e1 + (sx1 <<< LG); e2 <= e2 + (sx2 <<< LG);
                    end
                end else if (frag_ready) begin
                    sent <= sent | low;
                end
                default: state <= IDLE;
            endcase
        end
    end
endmodule
`default_nettype wire
