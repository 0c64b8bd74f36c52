// clear_unit -- fills the width x height frame with one colour, one pixel per cycle.
//
// Seed 000 ch. 6.3 (the SDRAM controller's clear: CB = 1 blanks the framebuffer). The
// clear is a fragment producer like the raster units, so it reaches memory through the
// fragment FIFO in order with the fragments of the packets before and after it. Its
// fragments are marked "not counted" (they are not drawing fragments).
//
// Ports: start (one cycle, in idle) latches wm1 / hm1 (width - 1, height - 1) and color;
// frag_* is a valid/ready fragment stream; done is a one-cycle strobe with the last
// fragment's hand-over.
// Timing: busy for exactly width * height cycles plus the cycles frag_ready is low;
// the first fragment is offered the cycle after start.
`default_nettype none
module clear_unit (
    input  wire       clk,
    input  wire       rst,
    input  wire       start,
    input  wire [8:0] wm1,
    input  wire [8:0] hm1,
    input  wire [7:0] color,
    output reg        busy,
    output wire       frag_valid,
    output wire [8:0] frag_x,
    output wire [8:0] frag_y,
    output wire [7:0] frag_col,
    input  wire       frag_ready,
    output wire       done
);
    reg [8:0] x, y, xm, ym;
    reg [7:0] col;
    reg       xe, ye;        // x == xm, y == ym: registers, so done and the clock
                             // enables are one LUT after frag_ready

    wire last = xe & ye;

    assign frag_valid = busy;
    assign frag_x     = x;
    assign frag_y     = y;
    assign frag_col   = col;
    assign done       = busy & frag_ready & last;

    always @(posedge clk) begin
        if (rst) begin
            busy <= 1'b0;
            x    <= 9'd0;
            y    <= 9'd0;
            xm   <= 9'd0;
            ym   <= 9'd0;
            col  <= 8'd0;
            xe   <= 1'b0;
            ye   <= 1'b0;
        end else if (!busy) begin
            if (start) begin
                busy <= 1'b1;
                x    <= 9'd0;
                y    <= 9'd0;
                xm   <= wm1;
                ym   <= hm1;
                xe   <= wm1 == 9'd0;
                ye   <= hm1 == 9'd0;
                col  <= color;
            end
        end else if (frag_ready) begin
            if (xe) begin
                x  <= 9'd0;
                xe <= xm == 9'd0;
                y  <= y + 9'd1;
                ye <= y + 9'd1 == ym;
                if (ye) busy <= 1'b0;
            end else begin
                x  <= x + 9'd1;
                xe <= x + 9'd1 == xm;
            end
        end
    end
endmodule
`default_nettype wire
