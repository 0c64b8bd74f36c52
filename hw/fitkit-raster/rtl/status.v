// status -- the status block (SPI channel 0x20): counters, flags, the sticky error.
//
// Not in seed 000 (its MCU only polled FIFO_FREE); the layout is docs/rtl.md "Status
// block". All 32 bytes are captured in one cycle (snap, when the address byte 0x20
// completes), so a read is a consistent snapshot however slowly the master clocks it.
//
// Counters (32 bits, wrapping), zeroed by rst and by cnt_clr (a set-up starting):
//   packets    pkt_done strobes: line, triangle and clear packets completed
//   fragments  frag_written strobes: counted fragments the memory accepted
//   line/tri   cycles line_busy / tri_busy is high
//   clear      cycles clr_busy is high (set-up clears, clear packets, CB clears)
//   last       the value of `cycle` at the last done strobe (any packet, set-up included);
//              `cycle` counts clk cycles from the cnt_clr cycle (0 there)
//   max occ    the highest committed input FIFO occupancy, / 2, saturating at 255
// The first error after rst is kept (code, channel, packet index = commits so far);
// later errors are ignored until rst. A decoder error wins over a simultaneous underrun.
//
// Parameters LINE_UNIT, TRI_UNIT (0 or 1): the units this build has, as fitkit_raster's;
// a missing one sets its FLAG_NO_* bit, fixed for the bitstream, so the controller learns
// which design it talks to from any status read.
// Ports: byte_index selects tx_byte = snapshot byte byte_index - 1 (bytes after the
// address), 0 past byte 31.
// The layout (byte offsets, flag bits), the underrun's error code and channel are the
// generated map's (fitkit_map.vh), which the host decodes the block by.
`default_nettype none
`include "fitkit_map.vh"
module status #(
    parameter LINE_UNIT = 1,
    parameter TRI_UNIT = 1
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       cnt_clr,
    input  wire       pkt_done,
    input  wire       any_done,
    input  wire       frag_written,
    input  wire       line_busy,
    input  wire       tri_busy,
    input  wire       clr_busy,
    input  wire       commit,
    input  wire [9:0] fifo_free,
    input  wire [9:0] fifo_occ,
    input  wire       busy,
    input  wire       setup_done,
    input  wire       dec_err,
    input  wire [`FITKIT_ERR_BITS-1:0] dec_code,
    input  wire [7:0] dec_chan,
    input  wire       underrun,
    input  wire       snap,
    input  wire [7:0] byte_index,
    output wire [7:0] tx_byte
);
    reg [31:0] packets, fragments, line_cyc, tri_cyc, clr_cyc, cycle, last;
    reg [9:0]  max_occ;
    reg [15:0] commits;
    reg        err;
    reg [`FITKIT_ERR_BITS-1:0] err_code;
    reg [7:0]  err_chan;
    reg [15:0] err_pkt;

    // The block is big-endian: byte 0 is the top byte, a field's first byte its most
    // significant. TOP is bit 7 of byte 0; a field at byte offset o is [TOP - 8o -: width].
    localparam BYTES = `FITKIT_STATUS_BYTES;
    localparam TOP   = 8 * BYTES - 1;
    localparam KW    = $clog2(BYTES);
    localparam [7:0] LAST_BYTE = BYTES;   // byte_index of the block's last byte

    reg [TOP:0] snapshot;

    wire [7:0] occ_half = (max_occ[9:1] > 9'd255) ? 8'd255 : max_occ[8:1];
    wire [7:0] err_code_byte = {{(8 - `FITKIT_ERR_BITS){1'b0}}, err_code};
    reg  [7:0] flags;
    reg  [TOP:0] block;
    always @* begin
        flags = 8'd0;
        flags[`FITKIT_FLAG_BUSY]       = busy;
        flags[`FITKIT_FLAG_ERROR]      = err;
        flags[`FITKIT_FLAG_FIFO_EMPTY] = fifo_occ == 10'd0;
        flags[`FITKIT_FLAG_SETUP_DONE] = setup_done;
        flags[`FITKIT_FLAG_NO_LINE]     = LINE_UNIT == 0;
        flags[`FITKIT_FLAG_NO_TRIANGLE] = TRI_UNIT == 0;
        block = {(TOP + 1){1'b0}};
        block[TOP - 8 * `FITKIT_STATUS_FREE -: 16]           = {6'd0, fifo_free};
        block[TOP - 8 * `FITKIT_STATUS_FLAGS -: 8]           = flags;
        block[TOP - 8 * `FITKIT_STATUS_ERROR_CODE -: 8]      = err_code_byte;
        block[TOP - 8 * `FITKIT_STATUS_ERROR_CHANNEL -: 8]   = err_chan;
        block[TOP - 8 * `FITKIT_STATUS_ERROR_PACKET -: 16]   = err_pkt;
        block[TOP - 8 * `FITKIT_STATUS_PACKETS -: 32]        = packets;
        block[TOP - 8 * `FITKIT_STATUS_FRAGMENTS -: 32]      = fragments;
        block[TOP - 8 * `FITKIT_STATUS_LINE_CYCLES -: 32]    = line_cyc;
        block[TOP - 8 * `FITKIT_STATUS_TRIANGLE_CYCLES -: 32] = tri_cyc;
        block[TOP - 8 * `FITKIT_STATUS_CLEAR_CYCLES -: 32]   = clr_cyc;
        block[TOP - 8 * `FITKIT_STATUS_END_CYCLE -: 32]      = last;
        block[TOP - 8 * `FITKIT_STATUS_FIFO_MAX_PAIRS -: 8]  = occ_half;
    end

    // The byte for the slave, registered: byte_index changes on a byte's last rising SCK
    // edge, at least 4 cycles before the next byte's tx_load (docs/rtl.md, SPI framing),
    // and the snapshot is taken with the address byte, so a cycle late is in time.
    // Byte index i (1 .. BYTES) selects snapshot byte i - 1, by a mux on the index itself.
    reg  [7:0] pick;
    reg  [7:0] tx_r;
    integer    i;
    always @* begin
        pick = 8'd0;
        for (i = 1; i <= BYTES; i = i + 1)
            if (byte_index[KW-1:0] == i[KW-1:0]) pick = snapshot[TOP - 8 * (i - 1) -: 8];
    end
    always @(posedge clk)
        tx_r <= (!rst && byte_index >= 8'd1 && byte_index <= LAST_BYTE) ? pick : 8'd0;
    assign tx_byte = tx_r;

    always @(posedge clk) begin
        if (rst) begin
            packets <= 32'd0; fragments <= 32'd0; line_cyc <= 32'd0; tri_cyc <= 32'd0;
            clr_cyc <= 32'd0; cycle <= 32'd0; last <= 32'd0; max_occ <= 10'd0;
            commits <= 16'd0; err <= 1'b0; err_code <= {`FITKIT_ERR_BITS{1'b0}};
            err_chan <= 8'd0; err_pkt <= 16'd0; snapshot <= {(TOP + 1){1'b0}};
        end else begin
            if (cnt_clr) begin
                packets <= 32'd0; fragments <= 32'd0; line_cyc <= 32'd0; tri_cyc <= 32'd0;
                clr_cyc <= 32'd0; cycle <= 32'd0; last <= 32'd0; max_occ <= fifo_occ;
            end else begin
                cycle <= cycle + 32'd1;
                if (pkt_done) packets <= packets + 32'd1;
                if (frag_written) fragments <= fragments + 32'd1;
                if (line_busy) line_cyc <= line_cyc + 32'd1;
                if (tri_busy) tri_cyc <= tri_cyc + 32'd1;
                if (clr_busy) clr_cyc <= clr_cyc + 32'd1;
                if (any_done) last <= cycle;
                if (fifo_occ > max_occ) max_occ <= fifo_occ;
            end
            if (commit) commits <= commits + 16'd1;
            if (!err && (dec_err || underrun)) begin
                err      <= 1'b1;
                err_code <= dec_err ? dec_code : `FITKIT_ERR_READ_UNDERRUN;
                err_chan <= dec_err ? dec_chan : `FITKIT_ADDR_READ;
                err_pkt  <= commits;
            end
            if (snap) snapshot <= block;
        end
    end

`ifdef FORMAL
    // The first error is kept until a reset: once the flag is up, its code, channel and
    // packet index never change but by rst; the code is not 0 exactly while the flag is
    // up; and an error comes up only from a decoder error or an underrun.
    reg reset_seen = 1'b0, past_valid = 1'b0;
    always @(posedge clk) begin
        past_valid <= 1'b1;
        if (rst) reset_seen <= 1'b1;
    end
    always @(*) if (reset_seen) assert (err == (err_code != {`FITKIT_ERR_BITS{1'b0}}));
    always @(*) assume (!dec_err || dec_code != {`FITKIT_ERR_BITS{1'b0}});
    always @(posedge clk) begin
        if (reset_seen && past_valid && !$past(rst)) begin
            if ($past(err))
                assert (err && err_code == $past(err_code) && err_chan == $past(err_chan)
                        && err_pkt == $past(err_pkt));
            if (err && !$past(err)) assert ($past(dec_err) || $past(underrun));
        end
    end
`endif
endmodule
`default_nettype wire
