// tri_unit -- flat triangles: edge functions, top-left rule, bounding-box traversal.
//
// Seed 000 ch. 6.5 (triangle rasterization: three edge functions, the third vertex
// fixes the orientation, the bounding box is walked one pixel test per cycle; 8-pixel
// parallel evaluation). Coverage is the golden model's (sim-target raster::tri, FITkit
// layout, subpixel_bits = 0):
//   * orientation normalised once: area = (x2-x0)(y1-y0) - (y2-y0)(x1-x0); area < 0 is
//     clockwise (y down), for which the model swaps vertices 1 and 2; area = 0
//     (degenerate) draws nothing. Swapping 1 and 2 reverses all three edges, and a
//     reversed edge's function is the negated one (whichever end point it is measured
//     from), so this unit keeps the input order's edges and tests them with the sign
//     s the orientation gives (s = +1 counter-clockwise, -1 clockwise), e = 0 decided by
//     the top-left rule of the normalised (reversed) edge;
//   * culling from the set-up: cull[0] discards clockwise, cull[1] counter-clockwise
//     triangles (cull = 3 discards both windings);
//   * edges k = 0, 1, 2 run from input vertex (1, 2, 0) to (2, 0, 1); pixel (i, j) is
//     tested at its centre (i + 1/2, j + 1/2);
//   * top-left rule: a normalised edge with dy > 0, or dy = 0 and dx < 0 (dx, dy from its
//     start to its end) owns the pixels whose centre lies on it; the others do not;
//   * bounding box [min x, max x) x [min y, max y), clipped to the frame; empty -> nothing.
//
// Widths. The model works in doubled units (X = 2x, so pixel centres 2i + 1 are
// integers) and tests E - bias >= 0 (bias 0 on top-left edges, else 1) with
// E = A(2i + 1 - Xp) + B(2j + 1 - Yp), A = 2dy, B = -2dx. E is always even, so this
// unit keeps e = E / 2 = dy(2i + 1 - 2xp) - dx(2j + 1 - 2yp):
//   dx, dy        10 bits signed (|.| <= 511)
//   2i + 1 - 2xp  11 bits signed (-1021..1021 inside the box)
//   e             21 bits signed: |e| <= 2 * 511 * 1021 = 1 043 462 < 2^20
// and, per edge, f = s * e + tl - 1 (tl = 1 on top-left edges): the model's test is
// f >= 0, so a pixel is covered when the three f have their sign bits clear -- one LUT
// after the registers. f steps by s * 2dy per column and s * (-2dx) per row.
//
// Pipeline (one carry chain per clock; see Timing):
//   start  the vertices, colour, frame and cull latched; the edge deltas and their
//          negations (x2 - x1 and x1 - x2, ...), whose signs order the vertices;
//   U      the box corner's offsets 2 min + 1 - 2 v are muxes of the deltas; the eight
//          products (area: dy1 dx2, dx1 dy2; per edge dy * ox, dx * oy) start in
//          mul_seq, one bit of the multiplier per clock (the first bit in U);
//   MUL    ten more bits (the area's 10-bit products end a clock early, and its sign
//          and zero, cw and degenerate, are taken in the tenth); meanwhile the box is
//          clipped and sized, one chain per clock;
//   P1     s * e per edge (e = dy * ox - dx * oy, or u - t - 1 = ~e when clockwise) and
//          what f adds to it from the top-left flags (+1, -1 or nothing);
//   P2     the reject decision (degenerate, empty box, culled: done here), or f = s * e +
//          tl - 1 per edge into every lane;
//   INIT   LG + 1 clocks: lane g's f gets g column steps (one per bit of g), and r, the
//          same lane one row down, f + the row step;
//   RUN    the traversal pushes one step per clock (LANES pixels of a row, their
//          coverage from the f sign bits) into a 2-entry queue; the emitter hands a
//          step's covered pixels to frag_* one per cycle, lowest first. A row's covered
//          pixels are contiguous (the triangle is convex), so a step is its first
//          pixel's x and a count (thermometer-coded: no adder after the lanes). The
//          lanes' clock enables are flip-flops (steps left and the queue's room,
//          computed a cycle ahead), never the fragment handshake.
//
// Ports: start (one cycle, in idle) latches the vertices (9-bit unsigned pixels), color,
// the frame (wm1 = width - 1, hm1 = height - 1) and cull; frag_* is a valid/ready stream of
// covered pixels (all registers); done is a one-cycle strobe with the last step's last
// cycle (or with P2 for a rejected triangle).
//
// Timing: busy = 16 + LG set-up cycles (LG = log2 LANES: U, 10 MUL, P1, P2, LG + 1 INIT and
// the queue's 2 fill cycles) + one cycle per step, or the step's covered pixels when it
// has more than one: for LANES = 1, 16 + (min(max x, W) - min x) * (min(max y, H) - min y).
// A degenerate, culled or off-frame triangle is 13 cycles (U, MUL, P1, P2). Plus the
// cycles frag_ready is low while a covered pixel waits. This is the model's
// hw::tri_setup_cycles(LANES) + steps and hw::TRI_REJECT_CYCLES (docs/rtl.md).
//
// Parameter LANES (1, 2, 4, 8; seed 000's 8-pixel parallel evaluation): each traversal
// step tests LANES pixels of a row (i .. i + LANES - 1, those past the box masked off).
`default_nettype none
module tri_unit #(
    parameter integer LANES = 1      // pixels tested per cycle: 1, 2, 4 or 8
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
    localparam integer LG = (LANES == 8) ? 3 : (LANES == 4) ? 2 : (LANES == 2) ? 1 : 0;
    localparam integer L  = 1 << LG;
    localparam [8:0]    L9 = L[8:0];
    generate
        if (L != LANES) begin : bad_parameter
            tri_unit_lanes_must_be_1_2_4_or_8 unsupported();
        end
    endgenerate

    localparam [2:0] IDLE = 3'd0, U = 3'd1, MUL = 3'd2, P1 = 3'd3, P2 = 3'd4, INIT = 3'd5,
                     RUN = 3'd6;
    reg [2:0] state;
    reg [3:0] cnt;                           // MUL's bit

    // ---- start: latched inputs, edge deltas (edge k: start -> end) and their negations
    reg [8:0] vx0, vy0, vx1, vy1, vx2, vy2;
    reg [7:0] col;
    reg [8:0] fw, fh;                        // frame - 1
    reg [1:0] cul;
    reg signed [9:0] dx0, dy0, dx1, dy1, dx2, dy2, nx0, ny0, nx1, ny1, nx2, ny2;

    function signed [9:0] sub9(input [8:0] a, input [8:0] b);
        sub9 = $signed({1'b0, a}) - $signed({1'b0, b});
    endfunction

    // The vertex order from the deltas' signs: dx2 = x1 - x0, dx1 = x0 - x2, dx0 = x2 - x1.
    wire x01 = ~dx2[9], x02 = ~nx1[9], x12 = ~dx0[9];    // x0 <= x1, x0 <= x2, x1 <= x2
    wire y01 = ~dy2[9], y02 = ~ny1[9], y12 = ~dy0[9];
    wire mnx0 = x01 & x02, mnx1 = ~x01 & x12;            // which vertex is min x (else 2)
    wire mny0 = y01 & y02, mny1 = ~y01 & y12;
    wire mxx0 = ~x01 & ~x02, mxx1 = x01 & ~x12;          // which is max x (else 2)
    wire mxy0 = ~y01 & ~y02, mxy1 = y01 & ~y12;

    // U: the offsets 2 (min - v) + 1 of each edge's start vertex (1, 2, 0), from the deltas.
    function signed [10:0] off(input z0, input z1, input signed [9:0] d0,
                               input signed [9:0] d1, input signed [9:0] d2);
        off = {(z0 ? d0 : z1 ? d1 : d2), 1'b1};
    endfunction
    wire signed [10:0] ox0 = off(mnx0, mnx1, nx2, 10'sd0, dx0);   // min x - x1
    wire signed [10:0] ox1 = off(mnx0, mnx1, dx1, nx0, 10'sd0);   // min x - x2
    wire signed [10:0] ox2 = off(mnx0, mnx1, 10'sd0, dx2, nx1);   // min x - x0
    wire signed [10:0] oy0 = off(mny0, mny1, ny2, 10'sd0, dy0);
    wire signed [10:0] oy1 = off(mny0, mny1, dy1, ny0, 10'sd0);
    wire signed [10:0] oy2 = off(mny0, mny1, 10'sd0, dy2, ny1);

    // ---- the eight products, started in U
    wire mload = state == U;
    wire mstep = state == MUL;
    // The area's products have 10-bit multipliers: they end a clock before the edges',
    // so the orientation is known when the edge values are formed.
    reg  mneg;                               // the last bit (b's sign): MUL's tenth clock
    reg  aneg;                               // the area's last bit: MUL's ninth clock
    wire signed [19:0] pa, pb;
    wire signed [20:0] t0, t1, t2, u0, u1, u2;
    wire mastep = mstep & ~mneg;             // the area's products hold in the last clock
    mul_seq #(.AW(10), .BW(10)) m_pa (.clk(clk), .load(mload), .step(mastep), .neg(aneg),
        .a(dy1), .b(dx2), .p(pa));
    mul_seq #(.AW(10), .BW(10)) m_pb (.clk(clk), .load(mload), .step(mastep), .neg(aneg),
        .a(dx1), .b(dy2), .p(pb));
    mul_seq #(.AW(10), .BW(11)) m_t0 (.clk(clk), .load(mload), .step(mstep), .neg(mneg),
        .a(dy0), .b(ox0), .p(t0));
    mul_seq #(.AW(10), .BW(11)) m_t1 (.clk(clk), .load(mload), .step(mstep), .neg(mneg),
        .a(dy1), .b(ox1), .p(t1));
    mul_seq #(.AW(10), .BW(11)) m_t2 (.clk(clk), .load(mload), .step(mstep), .neg(mneg),
        .a(dy2), .b(ox2), .p(t2));
    mul_seq #(.AW(10), .BW(11)) m_u0 (.clk(clk), .load(mload), .step(mstep), .neg(mneg),
        .a(dx0), .b(oy0), .p(u0));
    mul_seq #(.AW(10), .BW(11)) m_u1 (.clk(clk), .load(mload), .step(mstep), .neg(mneg),
        .a(dx1), .b(oy1), .p(u1));
    mul_seq #(.AW(10), .BW(11)) m_u2 (.clk(clk), .load(mload), .step(mstep), .neg(mneg),
        .a(dx2), .b(oy2), .p(u2));

    // ---- the box, clipped and sized: stages from the latched vertices, run in U and MUL
    // and settled long before P2 reads them (one chain per clock); held after, so a
    // simulator evaluates nothing here while the triangle is walked
    reg [8:0] minx, maxx, miny, maxy;                    // from the order
    reg       inx, iny, lox, loy, offx, offy;            // max <= frame, min >= max, min > frame
    reg [8:0] mxm1, mym1;                                // max - 1
    reg [8:0] xl, yl;                                    // last column and row, inclusive
    reg       empty;
    reg [8:0] wx, hy;                                    // box width - 1, height - 1
    reg       dxz0, dxz1, dxz2, dyz0, dyz1, dyz2;        // deltas that are 0
    always @(posedge clk) if (state == U || state == MUL) begin
        minx <= mnx0 ? vx0 : mnx1 ? vx1 : vx2;
        maxx <= mxx0 ? vx0 : mxx1 ? vx1 : vx2;
        miny <= mny0 ? vy0 : mny1 ? vy1 : vy2;
        maxy <= mxy0 ? vy0 : mxy1 ? vy1 : vy2;
        dxz0 <= dx0 == 10'sd0; dxz1 <= dx1 == 10'sd0; dxz2 <= dx2 == 10'sd0;
        dyz0 <= dy0 == 10'sd0; dyz1 <= dy1 == 10'sd0; dyz2 <= dy2 == 10'sd0;
        inx  <= maxx <= fw;      iny  <= maxy <= fh;
        lox  <= minx >= maxx;    loy  <= miny >= maxy;
        offx <= minx > fw;       offy <= miny > fh;
        mxm1 <= maxx - 9'd1;     mym1 <= maxy - 9'd1;
        xl    <= inx ? mxm1 : fw;
        yl    <= iny ? mym1 : fh;
        empty <= lox | loy | offx | offy;
        wx <= xl - minx;
        hy <= yl - miny;
    end
    // steps per row - 1, lanes of a row's last step, rows - 1 (valid with a non-empty box)
    wire [8:0]   spr_m1 = wx >> LG;
    wire [L-1:0] tail;
    genvar g;
    generate
        for (g = 0; g < L; g = g + 1) begin : tails
            if (g == 0) begin : all
                assign tail[g] = 1'b1;
            end else begin : some
                localparam [LG-1:0] G = g;
                assign tail[g] = G <= wx[LG-1:0];
            end
        end
    endgenerate

    // ---- P1, P2: orientation, reject, f and the steps
    wire reject;                 // degenerate, off the frame or culled: P2 ends the triangle
    reg               cw, degen;
    reg signed [20:0] xe0, xe1, xe2;                     // s e - (cw ? 1 : 0)
    reg               kp0, kp1, kp2, km0, km1, km2;      // f adds +1, -1
    reg signed [20:0] st0, st1, st2, rs0, rs1, rs2;      // s * 2dy << b, s * -2dx
    reg [LG:0]        ib;                                // INIT's clock b, one-hot

    // from the deltas' signs and zero flags, for both orientations (registers taken in
    // MUL, after U has the zero flags): kc = clockwise and top-left (f = ~e + 1), kn =
    // counter-clockwise and not top-left (f = e - 1)
    function top_left(input exn, input ez, input eyn, input eyz, input rev);
        top_left = rev ? (( eyn & ~eyz) | (eyz & ~exn & ~ez))
                       : ((~eyn & ~eyz) | (eyz &  exn));
    endfunction
    reg kc0, kc1, kc2, kn0, kn1, kn2;
    always @(posedge clk) if (state == MUL) begin
        kc0 <= top_left(dx0[9], dxz0, dy0[9], dyz0, 1'b1);
        kc1 <= top_left(dx1[9], dxz1, dy1[9], dyz1, 1'b1);
        kc2 <= top_left(dx2[9], dxz2, dy2[9], dyz2, 1'b1);
        kn0 <= ~top_left(dx0[9], dxz0, dy0[9], dyz0, 1'b0);
        kn1 <= ~top_left(dx1[9], dxz1, dy1[9], dyz1, 1'b0);
        kn2 <= ~top_left(dx2[9], dxz2, dy2[9], dyz2, 1'b0);
    end
    // f = s e + tl - 1: counter-clockwise e + (tl ? 0 : -1), clockwise ~e + tl; P1 has
    // taken ~e (= -e - 1) or e, P2 adds +1 or -1 to a register
    wire signed [20:0] fi0 = xe0 + {21{km0}} + {20'd0, kp0};
    wire signed [20:0] fi1 = xe1 + {21{km1}} + {20'd0, kp1};
    wire signed [20:0] fi2 = xe2 + {21{km2}} + {20'd0, kp2};
    function signed [20:0] dbl(input signed [9:0] d);
        dbl = {{10{d[9]}}, d, 1'b0};
    endfunction

    // ---- the traversal
    reg [8:0] ti, tj;            // the step's first column, its row
    reg [8:0] ccol, crow;        // steps left in the row, rows left (each minus 1)
    reg       row_end, last_row, trun;   // trun: steps left to push
    wire      last = row_end & last_row;
    reg [1:0] qn;                // queued steps
    // A step is pushed (the lanes move) while steps are left and the queue has room:
    // kept as a flip-flop from the next cycle's counts, since it enables every lane.
    reg       push;

    // ---- the lanes: f and r (one row down) per edge, in tri_lane; per lane, whether
    // it moves (loaded in P2, an INIT column step, a traversal step) and its coverage,
    // the three sign bits
    reg          ld;             // P2 (f loads)
    reg  [L-1:0] lmv;            // each lane's enable, a flip-flop: ld, push or INIT's move
    wire [L-1:0] mask;
    generate
        for (g = 0; g < L; g = g + 1) begin : covered
            wire en = lmv[g];
            wire n0, n1, n2;
            tri_lane l0 (.clk(clk), .en(en), .load(ld), .wrap(row_end), .rinit(ib[LG]),
                .f_in(fi0), .step(st0), .rs(rs0), .neg(n0));
            tri_lane l1 (.clk(clk), .en(en), .load(ld), .wrap(row_end), .rinit(ib[LG]),
                .f_in(fi1), .step(st1), .rs(rs1), .neg(n1));
            tri_lane l2 (.clk(clk), .en(en), .load(ld), .wrap(row_end), .rinit(ib[LG]),
                .f_in(fi2), .step(st2), .rs(rs2), .neg(n2));
            assign mask[g] = ~n0 & ~n1 & ~n2 & (~row_end | tail[g]);
        end
    endgenerate
    // the lanes INIT moves at clock b: those with bit b set
    function [L-1:0] lanes_with_bit(input integer b);
        integer j;
        begin
            lanes_with_bit = {L{1'b0}};
            for (j = 0; j < L; j = j + 1) lanes_with_bit[j] = ((j >> b) & 1) == 1;
        end
    endfunction
    reg [L-1:0] ladd_next;
    integer b;
    always @* begin
        ladd_next = {L{1'b0}};
        for (b = 0; b + 1 < LG; b = b + 1) if (ib[b]) ladd_next = lanes_with_bit(b + 1);
    end
    // the lanes' moves, and with them each lane's enable as its own flip-flop: f loads in
    // P2, INIT moves the lanes of its clock's bit, RUN pushes while steps are left and
    // the queue will have room
    reg          ld_d, push_d;
    reg  [L-1:0] ladd_d;
    always @* begin
        ld_d   = state == P1;
        ladd_d = {L{1'b0}};
        if (state == P2 && LG > 0 && !reject) ladd_d = lanes_with_bit(0);
        if (state == INIT) ladd_d = ladd_next;
        push_d = (state == INIT) & ib[LG];
        if (state == RUN)
            push_d = trun & ~(push & last) & ((qn + {1'b0, push} - {1'b0, pop}) != 2'd2);
    end
    always @(posedge clk) begin
        ld   <= ~rst & ld_d;
        push <= ~rst & push_d;
        lmv  <= rst ? {L{1'b0}} : ({L{ld_d | push_d}} | ladd_d);
    end
    // A step's pixel count as a thermometer code, m_th[k] = at least k + 1 covered, so
    // no carry chain lies between the lanes' sign bits and the queue. The covered lanes
    // are contiguous (each edge's f is linear along the row, the box's tail a prefix of
    // the lanes), so at least k + 1 are covered exactly when two lanes k apart both are.
    reg [L-1:0]  m_th;
    reg [LG:0]   m_first;        // one bit more than a lane index, so LG = 0 has a bit
    integer q, k;
    always @* begin
        m_th    = {L{1'b0}};
        m_first = {(LG+1){1'b0}};
        for (q = L - 1; q >= 0; q = q - 1) begin
            if (mask[q]) m_first = q[LG:0];
            for (k = 0; q + k < L; k = k + 1) m_th[k] = m_th[k] | (mask[q] & mask[q + k]);
        end
    end

    // the 2-entry queue: the step's x, its first covered lane, y, count, last step
    reg [8:0]    qx [0:1];
    reg [LG:0]   qf [0:1];
    reg [8:0]    qy [0:1];
    reg [L-1:0]  qt [0:1];       // the count, thermometer-coded
    reg          ql [0:1];
    reg          qw, qr;         // write and read slots

    // ---- the emitter
    reg          ev, ez, eo, el; // holds a step; of no, of one pixel; the last step
    reg          fz;             // ~ev | ez: free whatever frag_ready
    reg          qne;            // qn != 0
    reg [L-1:0]  et;             // pixels left of the step, thermometer-coded
    // the head's count and the emitter's, two bits wider so that one and two pixels
    // (thermometer 1 and 11) are codes for every LANES
    localparam [L+1:0] T1 = 1, T2 = 3;
    wire [L+1:0] qth = {2'b00, qt[qr]};
    wire [L+1:0] etw = {2'b00, et};
    reg [8:0]    ex, ey;
    // E moves when it can without a fragment (fz) or the fragment is taken: go is the
    // only gate frag_ready passes, and what E does then is chosen by registers alone
    wire go   = fz | frag_ready;
    wire fr   = fz | eo;         // moving, E lets its step go
    wire free = go & fr;
    wire pop  = free & qne;

    assign busy       = state != IDLE;
    assign frag_valid = ev & ~ez;
    assign frag_x     = ex;
    assign frag_y     = ey;
    assign frag_col   = col;
    // the last step's last cycle, from registers and frag_ready alone (ev, el, ez, eo are
    // only ever set in RUN, and ev & el in RUN's last cycle)
    assign reject     = degen | empty | (cul[0] & cw) | (cul[1] & ~cw);
    assign done       = ((state == P2) & reject) | (ev & el & (ez | (eo & frag_ready)));

    always @(posedge clk) begin
        if (rst) begin
            state <= IDLE;
            cnt   <= 4'd0;
            vx0 <= 9'd0; vy0 <= 9'd0; vx1 <= 9'd0; vy1 <= 9'd0; vx2 <= 9'd0; vy2 <= 9'd0;
            col <= 8'd0; fw <= 9'd0; fh <= 9'd0; cul <= 2'd0;
            dx0 <= 10'sd0; dy0 <= 10'sd0; dx1 <= 10'sd0; dy1 <= 10'sd0; dx2 <= 10'sd0;
            dy2 <= 10'sd0; nx0 <= 10'sd0; ny0 <= 10'sd0; nx1 <= 10'sd0; ny1 <= 10'sd0;
            nx2 <= 10'sd0; ny2 <= 10'sd0;
            cw <= 1'b0; degen <= 1'b0;
            xe0 <= 21'sd0; xe1 <= 21'sd0; xe2 <= 21'sd0;
            kp0 <= 1'b0; kp1 <= 1'b0; kp2 <= 1'b0; km0 <= 1'b0; km1 <= 1'b0; km2 <= 1'b0;
            st0 <= 21'sd0; st1 <= 21'sd0; st2 <= 21'sd0; ib <= {(LG+1){1'b0}}; mneg <= 1'b0;
            aneg <= 1'b0;
            rs0 <= 21'sd0; rs1 <= 21'sd0; rs2 <= 21'sd0;
            ti <= 9'd0; tj <= 9'd0; ccol <= 9'd0; crow <= 9'd0;
            row_end <= 1'b0; last_row <= 1'b0; trun <= 1'b0;
            qn <= 2'd0; qw <= 1'b0; qr <= 1'b0;
            ev <= 1'b0; ez <= 1'b0; eo <= 1'b0; el <= 1'b0; et <= {L{1'b0}};
            fz <= 1'b1; qne <= 1'b0;
            ex <= 9'd0; ey <= 9'd0;
        end else begin
            case (state)
                IDLE: if (start) begin
                    vx0 <= x0; vy0 <= y0; vx1 <= x1; vy1 <= y1; vx2 <= x2; vy2 <= y2;
                    dx0 <= sub9(x2, x1); dy0 <= sub9(y2, y1);
                    dx1 <= sub9(x0, x2); dy1 <= sub9(y0, y2);
                    dx2 <= sub9(x1, x0); dy2 <= sub9(y1, y0);
                    nx0 <= sub9(x1, x2); ny0 <= sub9(y1, y2);
                    nx1 <= sub9(x2, x0); ny1 <= sub9(y2, y0);
                    nx2 <= sub9(x0, x1); ny2 <= sub9(y0, y1);
                    col <= color; fw <= wm1; fh <= hm1; cul <= cull;
                    state <= U;
                end
                U: begin
                    cnt   <= 4'd1;
                    mneg  <= 1'b0;
                    aneg  <= 1'b0;
                    state <= MUL;
                end
                MUL: begin
                    cnt  <= cnt + 4'd1;
                    aneg <= cnt == 4'd8;
                    mneg <= cnt == 4'd9;
                    if (mneg) begin
                        // the area's products are done: its sign and zero
                        cw    <= pa < pb;
                        degen <= pa == pb;
                        state <= P1;
                    end
                end
                P1: begin
                    // s * e, and what f adds to it: clockwise ~e + tl, else e + tl - 1
                    xe0 <= cw ? u0 + ~t0 : t0 - u0;
                    xe1 <= cw ? u1 + ~t1 : t1 - u1;
                    xe2 <= cw ? u2 + ~t2 : t2 - u2;
                    kp0 <= cw & kc0; kp1 <= cw & kc1; kp2 <= cw & kc2;
                    km0 <= ~cw & kn0; km1 <= ~cw & kn1; km2 <= ~cw & kn2;
                    state <= P2;
                end
                P2: begin
                    st0 <= cw ? dbl(ny0) : dbl(dy0);
                    st1 <= cw ? dbl(ny1) : dbl(dy1);
                    st2 <= cw ? dbl(ny2) : dbl(dy2);
                    ib  <= {{LG{1'b0}}, 1'b1};
                    rs0 <= cw ? dbl(dx0) : dbl(nx0);
                    rs1 <= cw ? dbl(dx1) : dbl(nx1);
                    rs2 <= cw ? dbl(dx2) : dbl(nx2);
                    row_end <= 1'b0;         // the lanes' INIT adds, not wraps
                    state   <= reject ? IDLE : INIT;
                end
                INIT: begin
                    // the column step doubles until it is LANES columns
                    if (!ib[LG]) begin
                        st0 <= st0 <<< 1; st1 <= st1 <<< 1; st2 <= st2 <<< 1;
                    end
                    ib <= ib << 1;
                    if (ib[LG]) begin
                        ti <= minx; tj <= miny;
                        ccol <= spr_m1; crow <= hy;
                        row_end <= spr_m1 == 9'd0; last_row <= hy == 9'd0; trun <= 1'b1;
                        qn <= 2'd0; qw <= 1'b0; qr <= 1'b0; qne <= 1'b0;
                        ev <= 1'b0; fz <= 1'b1;
                        state <= RUN;
                    end
                end
                RUN: begin
                    if (push) begin
                        qx[qw] <= ti;
                        qf[qw] <= m_first;
                        qy[qw] <= tj;
                        qt[qw] <= m_th;
                        ql[qw] <= last;
                        qw     <= ~qw;
                        trun   <= ~last;
                        if (row_end) begin
                            ti       <= minx;
                            tj       <= tj + 9'd1;
                            ccol     <= spr_m1;
                            crow     <= crow - 9'd1;
                            row_end  <= spr_m1 == 9'd0;
                            last_row <= crow == 9'd1;
                        end else begin
                            ti      <= ti + L9;
                            ccol    <= ccol - 9'd1;
                            row_end <= ccol == 9'd1;
                        end
                    end
                    qn    <= qn + {1'b0, push} - {1'b0, pop};
                    qne   <= (qn + {1'b0, push} - {1'b0, pop}) != 2'd0;
                    if (go) begin
                        if (fr && qne) begin
                            qr <= ~qr;
                            ev <= 1'b1;
                            ex <= qx[qr] + {{(8-LG){1'b0}}, qf[qr]};
                            ey <= qy[qr];
                            et <= qt[qr];
                            ez <= ~qth[0];
                            fz <= ~qth[0];
                            eo <= qth == T1;
                            el <= ql[qr];
                        end else if (fr) begin
                            ev <= 1'b0;
                            fz <= 1'b1;
                        end else begin
                            // one of the step's several pixels went; the next is x + 1
                            ex <= ex + 9'd1;
                            et <= et >> 1;
                            eo <= etw == T2;
                        end
                    end
                    if (ev & el & free) state <= IDLE;
                end
                default: state <= IDLE;
            endcase
        end
    end

endmodule
`default_nettype wire
