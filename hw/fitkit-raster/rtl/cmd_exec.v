// cmd_exec -- runs the input FIFO's packets in order on the units.
//
// Seed 000 ch. 6.2 (the FIFO's reader: it pops a packet and starts the unit its channel
// names). One packet at a time; the units share the fragment FIFO and only one runs:
//   set-up (tag 0)   waits until every earlier fragment is in memory (pipe_idle), then
//                    latches width - 1, height - 1, background and cull, zeroes the
//                    counters (cnt_clr) and clears the frame to the background;
//                    setup_done stays high from its end until rst;
//   line / triangle  CB = 1 first clears the frame to the background, then the unit runs;
//   clear (tag 3)    clears the frame to the packet's colour.
// Before the first set-up the frame is 512 x 512, background 0, no culling.
//
// Ports: DATA_OUT / DATA_VLD / FIFO_NEXT to fifo36; *_start and packet (bits 70..9 of
// the 72-bit packet, MSB = CB dropped, padding dropped) to
// the units, their done strobes back; pkt_done (line, triangle, clear packet finished)
// and any_done (that, or a set-up finished) to the status block; busy: a packet is
// being executed.
// Timing (not counted in any unit's busy cycles): 2 cycles to pop a 1-record packet and
// 3 for a 2-record one from a primed FIFO, 1 to start each unit (the CB clear too), 1
// after a line's or triangle's done strobe (registered here: the strobe depends on the
// fragment FIFO's room, and this FSM's enables are a tree of every state's condition);
// a set-up adds the drain wait and 1 cycle to latch.
// The tags are the record channels' addresses and the power-on frame is the map's side
// (fitkit_map.vh).
`default_nettype none
`include "fitkit_map.vh"
module cmd_exec (
    input  wire        clk,
    input  wire        rst,
    input  wire [37:0] DATA_OUT,
    input  wire        DATA_VLD,
    output wire        FIFO_NEXT,
    input  wire        pipe_idle,
    output reg  [8:0]  wm1,
    output reg  [8:0]  hm1,
    output reg  [1:0]  cull,
    output reg         setup_done,
    output reg         cnt_clr,
    output reg         clr_start,
    output reg  [7:0]  clr_color,
    input  wire        clr_done,
    output reg         line_start,
    input  wire        line_done,
    output reg         tri_start,
    input  wire        tri_done,
    output wire [70:9] packet,
    output reg         pkt_done,
    output reg         any_done,
    output wire        busy
);
    localparam [3:0] IDLE = 4'd0, GET1 = 4'd1, DISPATCH = 4'd2, DRAIN = 4'd3,
                     SETUP_CLR = 4'd4, WAIT_SETUP = 4'd5, WAIT_CB = 4'd6, DRAW = 4'd7,
                     WAIT_DRAW = 4'd8, WAIT_CLR = 4'd9;
    // A record's tag is the low two bits of its channel's address.
    localparam [7:0] A_SETUP = `FITKIT_ADDR_SETUP, A_LINE = `FITKIT_ADDR_LINE,
                     A_TRI = `FITKIT_ADDR_TRIANGLE, A_CLEAR = `FITKIT_ADDR_CLEAR;
    localparam [1:0] T_SETUP = A_SETUP[1:0], T_LINE = A_LINE[1:0], T_TRI = A_TRI[1:0],
                     T_CLEAR = A_CLEAR[1:0];
    // Width - 1 and height - 1 before the first set-up: the whole frame.
    localparam integer FRAME_M1 = `FITKIT_FRAME_SIDE - 1;
    localparam [8:0]   SIDE_M1  = FRAME_M1[8:0];

    reg [3:0]  state;
    wire       two = (DATA_OUT[37:36] == T_LINE) | (DATA_OUT[37:36] == T_TRI);  // records
    reg [1:0]  tag;
    reg [35:0] r0;
    reg [35:9] r1;       // record 1 without the padding bits
    reg [7:0]  bg;
    reg        drawn;    // a line or triangle unit's done, one cycle late
    // state is IDLE or GET1 (this FSM pops records), as a flip-flop of its own: FIFO_NEXT
    // gates the input FIFO's read and output register, a unit's width away
    reg        popping;

    assign FIFO_NEXT = DATA_VLD & popping;
    assign packet    = {r0[34:0], r1[35:9]};
    assign busy      = state != IDLE;

    always @(posedge clk) begin
        cnt_clr    <= 1'b0;
        clr_start  <= 1'b0;
        line_start <= 1'b0;
        tri_start  <= 1'b0;
        pkt_done   <= 1'b0;
        any_done   <= 1'b0;
        drawn      <= ~rst & (line_done | tri_done);
        if (rst) begin
            state      <= IDLE;
            popping    <= 1'b1;
            tag        <= 2'd0;
            r0         <= 36'd0;
            r1         <= 27'd0;
            wm1        <= SIDE_M1;
            hm1        <= SIDE_M1;
            bg         <= 8'd0;
            cull       <= 2'd0;
            setup_done <= 1'b0;
            clr_color  <= 8'd0;
        end else begin
            case (state)
                IDLE: if (DATA_VLD) begin
                    r0      <= DATA_OUT[35:0];
                    tag     <= DATA_OUT[37:36];
                    state   <= two ? GET1 : DISPATCH;
                    popping <= two;
                end
                GET1: if (DATA_VLD) begin
                    r1      <= DATA_OUT[35:9];
                    state   <= DISPATCH;
                    popping <= 1'b0;
                end
                DISPATCH: begin
                    case (tag)
                        T_SETUP: state <= DRAIN;
                        T_CLEAR: begin
                            clr_color <= r0[34:27];
                            clr_start <= 1'b1;
                            state     <= WAIT_CLR;
                        end
                        default: if (r0[35]) begin
                            clr_color <= bg;
                            clr_start <= 1'b1;
                            state     <= WAIT_CB;
                        end else begin
                            state <= DRAW;
                        end
                    endcase
                end
                DRAIN: if (pipe_idle) begin
                    wm1     <= r0[35:27];
                    hm1     <= r0[26:18];
                    bg      <= r0[17:10];
                    cull    <= r0[9:8];
                    cnt_clr <= 1'b1;
                    state   <= SETUP_CLR;
                end
                SETUP_CLR: begin
                    clr_color <= bg;
                    clr_start <= 1'b1;
                    state     <= WAIT_SETUP;
                end
                WAIT_SETUP: if (clr_done) begin
                    setup_done <= 1'b1;
                    any_done   <= 1'b1;
                    state      <= IDLE;
                    popping    <= 1'b1;
                end
                WAIT_CB: if (clr_done) state <= DRAW;
                DRAW: begin
                    line_start <= tag == T_LINE;
                    tri_start  <= tag == T_TRI;
                    state      <= WAIT_DRAW;
                end
                WAIT_DRAW: if (drawn) begin
                    pkt_done <= 1'b1;
                    any_done <= 1'b1;
                    state    <= IDLE;
                    popping  <= 1'b1;
                end
                WAIT_CLR: if (clr_done) begin
                    pkt_done <= 1'b1;
                    any_done <= 1'b1;
                    state    <= IDLE;
                    popping  <= 1'b1;
                end
                default: begin
                    state   <= IDLE;
                    popping <= 1'b1;
                end
            endcase
        end
    end

`ifdef FORMAL
    // From the first reset on, the pop flag is the state's decode, whatever the FIFO and
    // the units do (every input is free), and the state is one of the FSM's.
    reg reset_seen = 1'b0;
    always @(posedge clk) if (rst) reset_seen <= 1'b1;
    always @(*) begin
        if (reset_seen) begin
            assert (popping == ((state == IDLE) | (state == GET1)));
            assert (state <= WAIT_CLR);
        end
    end
`endif
endmodule
`default_nettype wire
