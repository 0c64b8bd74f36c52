// line_unit -- Bresenham lines, all octants, both end points, one pixel per cycle.
//
// Seed 000 ch. 6.4 (line rasterization: p1 = 2dy - dx, integer end points). Coverage is
// the golden model's (sim-target raster::line::thin_pixels, LineAlgo::Bresenham): the
// direction is canonicalised before stepping -- the walk starts at the end point with
// the smaller major coordinate (x when |dx| >= |dy|, else y) -- so A->B and B->A draw the
// same pixels; p < 0 keeps the minor coordinate, p >= 0 steps it.
//
// Ports: start (one cycle, in idle) latches x0 y0 x1 y1 (9-bit unsigned pixels) and
// color; frag_* is a valid/ready stream of every pixel of the line (clipping to the
// frame is the writer's); done is a one-cycle strobe with the last fragment's hand-over.
//
// Set-up, one carry chain per clock: start latches the end points and takes the signed
// deltas; S1 their magnitudes; S2 which is the major axis (|dx| >= |dy|) and both
// candidates of p1 and of the step p takes when the minor coordinate moves; S3 chooses.
// In RUN both next decision values are computed side by side and p's sign bit picks one;
// the last pixel is a registered flag.
//
// Timing: busy = 3 set-up cycles + (max(|x1 - x0|, |y1 - y0|) + 1) pixel cycles, plus the
// cycles frag_ready is low (the model's hw::LINE_SETUP_CYCLES). A zero-length line is 4
// cycles.
// Widths: deltas 10 bits signed, magnitudes 9 bits unsigned (0..511); decision variable p
// in [-2*511, 2*511] held in 12 bits signed.
`default_nettype none
module line_unit (
    input  wire       clk,
    input  wire       rst,
    input  wire       start,
    input  wire [8:0] x0,
    input  wire [8:0] y0,
    input  wire [8:0] x1,
    input  wire [8:0] y1,
    input  wire [7:0] color,
    output wire       busy,
    output wire       frag_valid,
    output wire [8:0] frag_x,
    output wire [8:0] frag_y,
    output wire [7:0] frag_col,
    input  wire       frag_ready,
    output wire       done
);
    localparam [2:0] IDLE = 3'd0, S1 = 3'd1, S2 = 3'd2, S3 = 3'd3, RUN = 3'd4;

    reg [2:0]  state;
    reg        run;                 // state == RUN, as its own flip-flop
    reg [8:0]  ax, ay, bx, by;      // latched end points
    reg [7:0]  col;
    reg signed [9:0] dxs, dys;      // b - a
    reg [8:0]  adx, ady;            // |b - a|
    reg        nx, ny, zx, zy;      // b < a; b = a
    reg        xmaj;                // |dx| >= |dy|
    reg signed [11:0] px, py;       // p1 = 2 minor - major, for either major axis
    reg signed [11:0] qx, qy;       // 2 minor - 2 major, likewise
    // RUN
    reg        rx;                  // the major axis is x
    reg [8:0]  m, n, left;          // major, minor, pixels left after this one
    reg        lz;                  // left == 0
    reg signed [11:0] d0, d1;       // p's step: minor kept, minor stepped
    reg        sn;                  // minor steps down (-1)
    reg signed [11:0] p;

    function signed [9:0] sub9(input [8:0] a, input [8:0] b);
        sub9 = $signed({1'b0, a}) - $signed({1'b0, b});
    endfunction

    // S3: the walk starts at the end with the smaller major coordinate; the minor one
    // steps towards the other end's
    wire swap = xmaj ? nx : ny;
    wire [8:0] sx = swap ? bx : ax;
    wire [8:0] sy = swap ? by : ay;
    wire minor_down = xmaj ? (swap ? ~ny & ~zy : ny) : (swap ? ~nx & ~zx : nx);

    wire signed [11:0] p_keep = p + d0;
    wire signed [11:0] p_step = p + d1;

    assign busy       = state != IDLE;
    assign frag_valid = run;
    assign frag_x     = rx ? m : n;
    assign frag_y     = rx ? n : m;
    assign frag_col   = col;
    assign done       = run & frag_ready & lz;

    always @(posedge clk) begin
        if (rst) begin
            state <= IDLE;
            run   <= 1'b0;
            ax <= 9'd0; ay <= 9'd0; bx <= 9'd0; by <= 9'd0; col <= 8'd0;
            dxs <= 10'sd0; dys <= 10'sd0; adx <= 9'd0; ady <= 9'd0;
            nx <= 1'b0; ny <= 1'b0; zx <= 1'b0; zy <= 1'b0; xmaj <= 1'b0;
            px <= 12'sd0; py <= 12'sd0; qx <= 12'sd0; qy <= 12'sd0;
            rx <= 1'b0; m <= 9'd0; n <= 9'd0; left <= 9'd0; lz <= 1'b0;
            d0 <= 12'sd0; d1 <= 12'sd0; sn <= 1'b0; p <= 12'sd0;
        end else begin
            case (state)
                IDLE: if (start) begin
                    ax <= x0; ay <= y0; bx <= x1; by <= y1; col <= color;
                    dxs <= sub9(x1, x0);
                    dys <= sub9(y1, y0);
                    state <= S1;
                end
                S1: begin
                    adx <= dxs[9] ? 9'd0 - dxs[8:0] : dxs[8:0];
                    ady <= dys[9] ? 9'd0 - dys[8:0] : dys[8:0];
                    nx  <= dxs[9];
                    ny  <= dys[9];
                    zx  <= dxs == 10'sd0;
                    zy  <= dys == 10'sd0;
                    state <= S2;
                end
                S2: begin
                    xmaj <= adx >= ady;
                    px <= $signed({2'b00, ady, 1'b0}) - $signed({3'b000, adx});
                    py <= $signed({2'b00, adx, 1'b0}) - $signed({3'b000, ady});
                    qx <= $signed({2'b00, ady, 1'b0}) - $signed({2'b00, adx, 1'b0});
                    qy <= $signed({2'b00, adx, 1'b0}) - $signed({2'b00, ady, 1'b0});
                    state <= S3;
                end
                S3: begin
                    rx    <= xmaj;
                    m     <= xmaj ? sx : sy;
                    n     <= xmaj ? sy : sx;
                    left  <= xmaj ? adx : ady;
                    lz    <= xmaj ? zx : zy;
                    d0    <= $signed({2'b00, xmaj ? ady : adx, 1'b0});
                    d1    <= xmaj ? qx : qy;
                    p     <= xmaj ? px : py;
                    sn    <= minor_down;
                    state <= RUN;
                    run   <= 1'b1;
                end
                RUN: if (frag_ready) begin
                    // the walk steps on after its last pixel too (S3 sets it up anew), so
                    // the registers' enables are run and frag_ready alone
                    if (lz) begin
                        state <= IDLE;
                        run   <= 1'b0;
                    end
                    left <= left - 9'd1;
                    lz   <= left == 9'd1;
                    m    <= m + 9'd1;
                    if (p[11]) begin
                        p <= p_keep;
                    end else begin
                        p <= p_step;
                        n <= sn ? n - 9'd1 : n + 9'd1;
                    end
                end
                default: state <= IDLE;
            endcase
        end
    end
endmodule
`default_nettype wire
