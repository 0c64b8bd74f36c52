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
// Timing: busy = 1 set-up cycle + (max(|x1 - x0|, |y1 - y0|) + 1) pixel cycles, plus the
// cycles frag_ready is low. A zero-length line is 2 cycles.
// Widths: deltas 9 bits unsigned (0..511); decision variable p in [-2*511, 2*511] held
// in 12 bits signed.
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
    localparam [1:0] IDLE = 2'd0, SETUP = 2'd1, RUN = 2'd2;

    reg [1:0]  state;
    reg [8:0]  ax, ay, bx, by;      // latched end points
    reg [7:0]  col;
    reg        xmaj;
    reg [8:0]  m, n, left;          // major, minor, pixels left after this one
    reg [9:0]  dn2;                 // 2 * minor delta
    reg [9:0]  dm2;                 // 2 * major delta
    reg        sn;                  // minor steps down (-1)
    reg signed [11:0] p;

    // Set-up, from the latched end points.
    wire [8:0] dx     = (bx >= ax) ? bx - ax : ax - bx;
    wire [8:0] dy     = (by >= ay) ? by - ay : ay - by;
    wire       s_xmaj = dx >= dy;
    wire       s_swap = s_xmaj ? (bx < ax) : (by < ay);
    wire [8:0] sx     = s_swap ? bx : ax;
    wire [8:0] sy     = s_swap ? by : ay;
    wire [8:0] ex     = s_swap ? ax : bx;
    wire [8:0] ey     = s_swap ? ay : by;
    wire [8:0] s_dm   = s_xmaj ? dx : dy;
    wire [8:0] s_dn   = s_xmaj ? dy : dx;
    wire       s_sn   = s_xmaj ? (ey < sy) : (ex < sx);

    wire signed [11:0] p_step0 = $signed({2'b00, dn2});
    wire signed [11:0] p_step1 = $signed({2'b00, dn2}) - $signed({2'b00, dm2});

    assign busy       = state != IDLE;
    assign frag_valid = state == RUN;
    assign frag_x     = xmaj ? m : n;
    assign frag_y     = xmaj ? n : m;
    assign frag_col   = col;
    assign done       = (state == RUN) & frag_ready & (left == 9'd0);

    always @(posedge clk) begin
        if (rst) begin
            state <= IDLE;
            ax <= 9'd0; ay <= 9'd0; bx <= 9'd0; by <= 9'd0;
            col <= 8'd0; xmaj <= 1'b0; m <= 9'd0; n <= 9'd0; left <= 9'd0;
            dn2 <= 10'd0; dm2 <= 10'd0; sn <= 1'b0; p <= 12'sd0;
        end else begin
            case (state)
                IDLE: if (start) begin
                    ax <= x0; ay <= y0; bx <= x1; by <= y1; col <= color;
                    state <= SETUP;
                end
                SETUP: begin
                    xmaj  <= s_xmaj;
                    m     <= s_xmaj ? sx : sy;
                    n     <= s_xmaj ? sy : sx;
                    left  <= s_dm;
                    dn2   <= {s_dn, 1'b0};
                    dm2   <= {s_dm, 1'b0};
                    sn    <= s_sn;
                    p     <= $signed({2'b00, s_dn, 1'b0}) - $signed({3'b000, s_dm});
                    state <= RUN;
                end
                RUN: if (frag_ready) begin
                    if (left == 9'd0) begin
                        state <= IDLE;
                    end else begin
                        left <= left - 9'd1;
                        m    <= m + 9'd1;
                        if (p < 0) begin
                            p <= p + p_step0;
                        end else begin
                            p <= p + p_step1;
                            n <= sn ? n - 9'd1 : n + 9'd1;
                        end
                    end
                end
                default: state <= IDLE;
            endcase
        end
    end
endmodule
`default_nettype wire
