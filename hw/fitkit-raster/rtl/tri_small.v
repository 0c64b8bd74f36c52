// tri_small -- flat triangles in few LUTs: the triangle unit for the seed's XC3S50.
//
// Seed 000 ch. 6.5 (triangle rasterization: three edge functions, the orientation from
// the vertices, the bounding box walked one pixel test per cycle), as tri_unit with
// LANES = 1, pixel for pixel, built for area instead of a 100 MHz iCE40 clock: the set-up
// is a sequence of products through one multiplier (one MULT18X18 on the Spartan-3: the
// XC3S50's other three sit beside the block's 36-bit-wide block RAMs, whose upper data
// bits they share) and one subtract-and-sign stage, and the walk is one adder per edge.
// Coverage and widths are tri_unit's (its header): per edge k (from input vertex
// (1, 2, 0) to (2, 0, 1)), f = s * e + tl - 1 with e = dy (2i + 1 - 2xs) - dx (2j + 1 - 2ys)
// at pixel (i, j), s the orientation's sign, tl the normalised edge's top-left flag; a
// pixel is covered when the three f are >= 0. The box is [min x, max x) x [min y, max y)
// clipped to the frame.
//
// Set-up (busy cycle c, counted from 1 after start). Each cycle the multiplier takes one
// product m = a * b (a a delta, b from a short list) and the stage forms d = p - m, p
// the previous cycle's product (0 after a value is taken), then (d ^ n) + c for a sign n
// and a constant c in -1..1:
//   1, 2        the area dy1 dx2 - dx1 dy2 (cw: < 0; degenerate: 0); the box's min (1),
//               its max clipped to the frame (2: the last column and row; one vertex
//               pick per axis serves min, max and then the edges' start vertices)
//   3, 6, 9     a of edge 0, 1, 2: the column step 2 s dy (b = -2; n = cw, c = cw)
//   4-5, 7-8, 10-11  f of edge 0, 1, 2 at (min x, min y): dy ox - dx oy, ox and oy the
//               corner's doubled offsets (n = cw, c = cw + tl - 1), into w; f (cleared in
//               1) takes it a cycle later by adding w as a row step would
//   3           the box's width - 1, and whether the box is empty: a width or height
//               below 1 (min >= max, or min past the frame)
//   12-13, 14-15, 16-17  w of edge 0, 1, 2: the row step from a row's last column to
//               the next row's first, -2 s (dy (width - 1) + dx) (b = 2 (width - 1),
//               then -2; n = ~cw, c = ~cw)
//   13          a degenerate, culled or off-frame triangle is done
//   18          the first step into the output register
// Walk: a step is the output register's pixel (covered or not); the edge values, column
// and row are those of the next step, and move when the output's step leaves it (not
// covered, or frag_ready).
//
// Ports: tri_unit's without LANES. The vertices, colour, frame and cull are read after
// start (the executor holds its packet and the frame registers until done).
// Timing: busy 18 + box pixels + the cycles a covered pixel waits for frag_ready (two
// set-up cycles more than tri_unit's 16: the model's hw::TRI_SMALL_SETUP_CYCLES); 13 for
// a rejected triangle (hw::TRI_REJECT_CYCLES, as tri_unit); done with the last step's
// last cycle.
// Resources: one 10 x 11-bit signed multiplier; 21-bit registers f, w and 11-bit a per
// edge, a 21-bit product register.
`default_nettype none
module tri_small (
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
    localparam [1:0] IDLE = 2'd0, SET = 2'd1, RUN = 2'd2;
    reg [1:0] state;
    reg [4:0] cyc;                           // SET's busy cycle, 1 .. 18

    // ---- the edges' deltas (edge k: start -> end), taken with start
    reg signed [9:0] dx0, dy0, dx1, dy1, dx2, dy2;
    function signed [9:0] sub9(input [8:0] a, input [8:0] b);
        sub9 = $signed({1'b0, a}) - $signed({1'b0, b});
    endfunction

    // ---- the box: the order from the deltas' signs (dx2 = x1 - x0, dx0 = x2 - x1,
    // dx1 = x0 - x2), ties broken one way, so a "min" is a minimum and a "max" a maximum
    wire c01x = ~dx2[9], c12x = ~dx0[9], c20x = ~dx1[9];   // x0 <= x1, x1 <= x2, x2 <= x0
    wire c01y = ~dy2[9], c12y = ~dy0[9], c20y = ~dy1[9];
    function [8:0] pick3(input s0, input s1, input [8:0] a, input [8:0] b, input [8:0] c);
        pick3 = s0 ? a : s1 ? b : c;
    endfunction
    // One vertex pick per axis serves the box's min (cycle 1), its max (cycle 2) and,
    // after, the start vertex of the set-up's edge k (v1, v2, v0 for k = 0, 1, 2).
    reg  [1:0] k;                            // the set-up's edge (below)
    wire       c1 = cyc == 5'd1, c2 = cyc == 5'd2;
    wire       sx0 = c1 ? c01x & ~c20x : c2 ? ~c01x & c20x : k == 2'd2;
    wire       sx1 = c1 ? ~c01x & c12x : c2 ? c01x & ~c12x : k == 2'd0;
    wire       sy0 = c1 ? c01y & ~c20y : c2 ? ~c01y & c20y : k == 2'd2;
    wire       sy1 = c1 ? ~c01y & c12y : c2 ? c01y & ~c12y : k == 2'd0;
    wire [8:0] vx = pick3(sx0, sx1, x0, x1, x2);
    wire [8:0] vy = pick3(sy0, sy1, y0, y1, y2);
    reg  [8:0] minx, miny;                   // cycle 1
    // the last column and row, inclusive (cycle 2; -1 for a box on row or column 0 with
    // max = min = 0), the clipped box's width - 1 and height - 1 (cycle 3): a negative
    // one is an empty box (min >= max, or min past the frame)
    reg  signed [9:0] xl, yl, wx;
    reg        hneg;                         // height - 1 < 0
    reg        cw, degen;
    wire       empty = wx[9] | hneg;

    // ---- the set-up's products: the edge, the operand and what is taken each cycle
    reg        use_dx;                       // a = dx (else dy)
    reg  [2:0] bsel;                         // b: 0 dx2, 1 dy2, 2 ox, 3 oy, 4 -2, 5 2 wx
    reg        t_a, t_f, t_w;                // this cycle's d is a, f or w of edge k
    always @* begin
        k = 2'd0; use_dx = 1'b0; bsel = 3'd4; t_a = 1'b0; t_f = 1'b0; t_w = 1'b0;
        case (cyc)
            5'd1:  begin k = 2'd1; bsel = 3'd0; end
            5'd2:  begin k = 2'd1; use_dx = 1'b1; bsel = 3'd1; end
            5'd3:  begin k = 2'd0; t_a = 1'b1; end
            5'd4:  begin k = 2'd0; bsel = 3'd2; end
            5'd5:  begin k = 2'd0; use_dx = 1'b1; bsel = 3'd3; t_f = 1'b1; end
            5'd6:  begin k = 2'd1; t_a = 1'b1; end
            5'd7:  begin k = 2'd1; bsel = 3'd2; end
            5'd8:  begin k = 2'd1; use_dx = 1'b1; bsel = 3'd3; t_f = 1'b1; end
            5'd9:  begin k = 2'd2; t_a = 1'b1; end
            5'd10: begin k = 2'd2; bsel = 3'd2; end
            5'd11: begin k = 2'd2; use_dx = 1'b1; bsel = 3'd3; t_f = 1'b1; end
            5'd12: begin k = 2'd0; bsel = 3'd5; end
            5'd13: begin k = 2'd0; use_dx = 1'b1; t_w = 1'b1; end
            5'd14: begin k = 2'd1; bsel = 3'd5; end
            5'd15: begin k = 2'd1; use_dx = 1'b1; t_w = 1'b1; end
            5'd16: begin k = 2'd2; bsel = 3'd5; end
            5'd17: begin k = 2'd2; use_dx = 1'b1; t_w = 1'b1; end
            default: ;
        endcase
    end
    wire signed [9:0] dxk = (k == 2'd0) ? dx0 : (k == 2'd1) ? dx1 : dx2;
    wire signed [9:0] dyk = (k == 2'd0) ? dy0 : (k == 2'd1) ? dy1 : dy2;
    // 2 (min - start) + 1: the offsets of the box's corner pixel centre, doubled
    wire signed [10:0] ox = {sub9(minx, vx), 1'b1};
    wire signed [10:0] oy = {sub9(miny, vy), 1'b1};
    reg  signed [10:0] mb;
    always @* begin
        case (bsel)
            3'd0:    mb = {dx2[9], dx2};
            3'd1:    mb = {dy2[9], dy2};
            3'd2:    mb = ox;
            3'd3:    mb = oy;
            3'd5:    mb = {wx, 1'b0};
            default: mb = -11'sd2;
        endcase
    end
    wire signed [9:0]  ma = use_dx ? dxk : dyk;
    wire signed [20:0] m  = ma * mb;
    // the previous cycle's product: cleared after a value's second product and before an
    // a (whose d is 0 - dy * -2)
    reg  signed [20:0] p;
    wire signed [20:0] d = p - m;

    // the top-left flag of the normalised edge k (clockwise input reverses it): a
    // horizontal edge of a triangle that is not degenerate has dx != 0
    function top_left(input exn, input signed [9:0] ey, input rev);
        top_left = (ey == 10'sd0) ? (exn ^ rev) : (~ey[9] ^ rev);
    endfunction
    wire tl = top_left(dxk[9], dyk, cw);
    // (d ^ n) + c: f = s e + tl - 1 (n = cw, c = cw + tl - 1), a = 2 s dy (c = n = cw),
    // w = -2 s (dy wx + dx) (c = n = ~cw)
    wire n = t_w ? ~cw : cw;
    wire [1:0] csum = t_f ? {1'b0, cw} + {1'b0, tl} : {n, ~n};    // c + 1, 0..2
    wire signed [20:0] cval = (csum == 2'd0) ? -21'sd1 : (csum == 2'd1) ? 21'sd0 : 21'sd1;
    wire signed [20:0] res = (d ^ {21{n}}) + cval;

    // ---- per edge: f (the next step's value), a (column step), w (row step; in the
    // set-up first f's value at the corner, which f takes by adding it to 0)
    reg  signed [20:0] f0, f1, f2, w0, w1, w2;
    reg  signed [10:0] a0, a1, a2;
    reg  [8:0]         x, y;                 // the next step's pixel
    wire               xe = x == xl[8:0];    // the row's last column
    wire               ye = y == yl[8:0];    // the box's last row

    // ---- the output register: the step presented to the fragment stream
    reg       qs, qc, ql;                    // a step is here; it is covered; it is the last
    reg [8:0] qx, qy;
    wire      leave = qs & (~qc | frag_ready);
    // the walk moves: the first step in SET's last cycle, then whenever a step leaves
    // and it was not the last
    wire      reject = degen | empty | (cull[0] & cw) | (cull[1] & ~cw);
    wire      step = ((state == SET) & (cyc == 5'd18) & ~reject) | ((state == RUN) & leave & ~ql);
    wire      covered = ~f0[20] & ~f1[20] & ~f2[20];
    // the set-up's f loads (f = 0 + w), one edge a cycle after its value
    wire      fl0 = (state == SET) & (cyc == 5'd6);
    wire      fl1 = (state == SET) & (cyc == 5'd9);
    wire      fl2 = (state == SET) & (cyc == 5'd12);
    wire      wr  = step & xe;               // the walk wraps to the next row

    assign busy       = state != IDLE;
    assign frag_valid = qs & qc;
    assign frag_x     = qx;
    assign frag_y     = qy;
    assign frag_col   = color;
    assign done       = ((state == SET) & (cyc == 5'd13) & reject) | ((state == RUN) & leave & ql);

    always @(posedge clk) begin
        if (rst) begin
            state <= IDLE;
            cyc   <= 5'd0;
            dx0 <= 10'sd0; dy0 <= 10'sd0; dx1 <= 10'sd0; dy1 <= 10'sd0;
            dx2 <= 10'sd0; dy2 <= 10'sd0;
            minx <= 9'd0; miny <= 9'd0;
            xl <= 10'sd0; yl <= 10'sd0; wx <= 10'sd0; hneg <= 1'b0;
            cw <= 1'b0; degen <= 1'b0;
            f0 <= 21'sd0; f1 <= 21'sd0; f2 <= 21'sd0;
            w0 <= 21'sd0; w1 <= 21'sd0; w2 <= 21'sd0;
            a0 <= 11'sd0; a1 <= 11'sd0; a2 <= 11'sd0;
            p <= 21'sd0;
            x <= 9'd0; y <= 9'd0;
            qs <= 1'b0; qc <= 1'b0; ql <= 1'b0; qx <= 9'd0; qy <= 9'd0;
        end else begin
            case (state)
                IDLE: if (start) begin
                    dx0 <= sub9(x2, x1); dy0 <= sub9(y2, y1);
                    dx1 <= sub9(x0, x2); dy1 <= sub9(y0, y2);
                    dx2 <= sub9(x1, x0); dy2 <= sub9(y1, y0);
                    cyc   <= 5'd1;
                    state <= SET;
                end
                SET: begin
                    cyc <= cyc + 5'd1;
                    p   <= (cyc == 5'd2 || t_f || t_w) ? 21'sd0 : m;
                    case (cyc)
                        5'd1: begin
                            minx <= vx;
                            miny <= vy;
                            f0 <= 21'sd0; f1 <= 21'sd0; f2 <= 21'sd0;
                        end
                        5'd2: begin
                            cw    <= d[20];
                            degen <= d == 21'sd0;
                            // vx, vy: the max
                            xl <= (vx <= wm1) ? sub9(vx, 9'd1) : $signed({1'b0, wm1});
                            yl <= (vy <= hm1) ? sub9(vy, 9'd1) : $signed({1'b0, hm1});
                        end
                        5'd3: begin
                            wx <= xl - $signed({1'b0, minx});
                            hneg <= yl < $signed({1'b0, miny});
                        end
                        5'd13: if (reject) state <= IDLE;
                        5'd17: begin
                            x <= minx;
                            y <= miny;
                        end
                        5'd18: state <= RUN;
                        default: ;
                    endcase
                    // the set-up's results: a, f's corner value and then w into w
                    if ((t_f | t_w) && k == 2'd0) w0 <= res;
                    if ((t_f | t_w) && k == 2'd1) w1 <= res;
                    if ((t_f | t_w) && k == 2'd2) w2 <= res;
                    if (t_a && k == 2'd0) a0 <= res[10:0];
                    if (t_a && k == 2'd1) a1 <= res[10:0];
                    if (t_a && k == 2'd2) a2 <= res[10:0];
                end
                RUN: if (leave & ql) state <= IDLE;
                default: state <= IDLE;
            endcase
            // the edge values: the set-up's corner values, then the walk's steps
            if (fl0 | step) f0 <= f0 + (fl0 | wr ? w0 : {{10{a0[10]}}, a0});
            if (fl1 | step) f1 <= f1 + (fl1 | wr ? w1 : {{10{a1[10]}}, a1});
            if (fl2 | step) f2 <= f2 + (fl2 | wr ? w2 : {{10{a2[10]}}, a2});
            if (step) begin
                x  <= xe ? minx : x + 9'd1;
                y  <= xe ? y + 9'd1 : y;
                qs <= 1'b1;
                qc <= covered;
                ql <= xe & ye;
                qx <= x;
                qy <= y;
            end else if (leave) begin
                qs <= 1'b0;
            end
        end
    end

endmodule
`default_nettype wire
