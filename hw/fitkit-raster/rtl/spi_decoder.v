// spi_decoder -- the FITkit address decoder: channels, packet assembly, packet checks.
//
// Seed 000 ch. 6.1 (MCU control / SPI + address decoder). The first byte of a transaction
// selects the channel (docs/rtl.md "SPI framing"). On a write channel the payload bytes
// are cut into 36-bit records that are written into fifo36 as they complete (record 0
// after payload byte 5, record 1 after byte 9), tagged with the channel; when CS_n rises
// the packet is checked and committed, or discarded with an error:
//   1 length   payload bytes != 5 (set-up, clear), 9 (line, triangle), 0 (reset), or a
//              partial byte;
//   2 padding  a bit past the packet's fields (record padding or byte padding) is 1;
//   4 clear without CB;
//   3 overrun  a record found the FIFO full (the packet is never partly queued);
//   (checked in this order: the first failing check is the one reported), and at the
//   address byte
//   5 unknown address (with LINE_UNIT or TRI_UNIT 0, the absent unit's address too: its
//     payload is ignored, as any unknown address's is).
// Channel 0x7F resets the block (soft_rst) when CS_n rises after an address-only
// transaction. Channel 0x20 asks the status block for a snapshot (snap) as the address
// byte completes. A transaction without a whole address byte is ignored.
//
// Ports: the spi_slave's byte events in; chan / chan_valid (the current transaction's
// address); fifo_* to fifo36; err_* a one-cycle error report; commit (a packet entered
// the FIFO, counted for the status block's packet index).
// Timing: one record write per completed byte at most; commit/discard the cycle after
// cs_end.
// Addresses, error codes and packet lengths are the generated map's (fitkit_map.vh), so
// the decoder and protocol::fitkit_spi cannot drift apart.
`default_nettype none
`include "fitkit_map.vh"
module spi_decoder #(
    parameter LINE_UNIT = 1,     // the block has a line unit (0: address 0x01 is unknown)
    parameter TRI_UNIT = 1       // the block has a triangle unit (0: address 0x02 is unknown)
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        cs_start,
    input  wire        cs_end,
    input  wire        cs_partial,
    input  wire        rx_valid,
    input  wire [7:0]  rx_byte,
    input  wire        fifo_room,
    output reg  [7:0]  chan,
    output reg         chan_valid,
    output reg  [37:0] fifo_din,
    output reg         fifo_we,
    output reg         fifo_commit,
    output reg         fifo_discard,
    output reg         err_valid,
    output reg  [`FITKIT_ERR_BITS-1:0] err_code,
    output reg  [7:0]  err_chan,
    output reg         soft_rst,
    output reg         snap
);
    // Payload bytes of a 1-record packet (set-up, clear) and of a 2-record one (line,
    // triangle): the records' bits padded to whole bytes.
    localparam [7:0] BYTES1 = (`FITKIT_RECORD_BITS + 7) / 8;
    localparam [7:0] BYTES2 = `FITKIT_MAX_PACKET_BYTES;

    // The last 5 payload bytes, newest at the bottom. Bits 38..32 are shifted through
    // but not read: they are the colour of a clear, which has no check.
    /* verilator lint_off UNUSEDSIGNAL */
    reg [39:0] acc;
    /* verilator lint_on UNUSEDSIGNAL */
    reg [7:0]  nbytes;   // payload bytes, saturating
    reg        ovr;

    // The record channels are the addresses 0..3 (set-up, line, triangle, clear): their
    // low two bits are the FIFO tag. The channel's kind is kept in flags, set with chan
    // from the address byte, so a payload byte's enables start at flip-flops; first: the
    // next byte is the address.
    reg  rec_c, two_c, rst_c, first;
    wire is_rec  = chan_valid & rec_c;
    wire is_two  = chan_valid & two_c;
    wire is_rst  = chan_valid & rst_c;
    // A record channel this build has: the address is 0..3 and not an absent unit's.
    function has_rec(input [7:0] a);
        has_rec = (a[7:2] == 6'd0) & ~((LINE_UNIT == 0) & (a == `FITKIT_ADDR_LINE))
                                   & ~((TRI_UNIT == 0) & (a == `FITKIT_ADDR_TRIANGLE));
    endfunction
    function has_two(input [7:0] a);
        has_two = ((LINE_UNIT != 0) & (a == `FITKIT_ADDR_LINE))
                | ((TRI_UNIT != 0) & (a == `FITKIT_ADDR_TRIANGLE));
    endfunction
    wire known   = has_rec(rx_byte) | (rx_byte == `FITKIT_ADDR_STATUS)
                 | (rx_byte == `FITKIT_ADDR_READ) | (rx_byte == `FITKIT_ADDR_RESET);

    // Checks at CS_n rise, on the final bytes (5-byte packets sit in acc[39:0]).
    wire [7:0] expect_n = is_two ? BYTES2 : (is_rst ? 8'd0 : BYTES1);
    // The payload byte now completing ends record 0 / record 1.
    wire       rec0_end = nbytes == BYTES1 - 8'd1;
    wire       rec1_end = nbytes == BYTES2 - 8'd1;
    wire       len_ok   = (nbytes == expect_n) & ~cs_partial;
    reg        pad_ok;
    always @* begin
        case (chan[1:0])
            2'd0:    pad_ok = acc[11:0] == 12'd0;   // 8 record bits + 4 byte bits
            2'd1:    pad_ok = acc[26:0] == 27'd0;   // 72 - 45
            2'd2:    pad_ok = acc[8:0] == 9'd0;     // 72 - 63
            default: pad_ok = acc[30:0] == 31'd0;   // 27 record bits + 4 byte bits
        endcase
    end
    wire cb_ok = (chan != `FITKIT_ADDR_CLEAR) | acc[39];

    always @(posedge clk) begin
        fifo_we      <= 1'b0;
        fifo_commit  <= 1'b0;
        fifo_discard <= 1'b0;
        err_valid    <= 1'b0;
        soft_rst     <= 1'b0;
        snap         <= 1'b0;
        if (rst) begin
            chan       <= 8'd0;
            chan_valid <= 1'b0;
            rec_c      <= 1'b0;
            two_c      <= 1'b0;
            rst_c      <= 1'b0;
            first      <= 1'b1;
            acc        <= 40'd0;
            nbytes     <= 8'd0;
            ovr        <= 1'b0;
            fifo_din   <= 38'd0;
            err_code   <= {`FITKIT_ERR_BITS{1'b0}};
            err_chan   <= 8'd0;
        end else if (cs_start) begin
            chan_valid <= 1'b0;
            first      <= 1'b1;
            acc        <= 40'd0;
            nbytes     <= 8'd0;
            ovr        <= 1'b0;
        end else if (rx_valid) begin
            first <= 1'b0;
            if (first) begin
                chan       <= rx_byte;
                chan_valid <= 1'b1;
                rec_c      <= has_rec(rx_byte);
                two_c      <= has_two(rx_byte);
                rst_c      <= rx_byte == `FITKIT_ADDR_RESET;
                snap       <= rx_byte == `FITKIT_ADDR_STATUS;
                if (!known) begin
                    err_valid <= 1'b1;
                    err_code  <= `FITKIT_ERR_UNKNOWN_ADDRESS;
                    err_chan  <= rx_byte;
                end
            end else if (is_rec | is_rst) begin
                acc <= {acc[31:0], rx_byte};
                if (nbytes != 8'hFF) nbytes <= nbytes + 8'd1;
                if (is_rec & (rec0_end | (is_two & rec1_end))) begin
                    fifo_din <= rec0_end ? {chan[1:0], acc[31:0], rx_byte[7:4]}
                                         : {chan[1:0], acc[27:0], rx_byte};
                    fifo_we  <= fifo_room;
                    if (!fifo_room) ovr <= 1'b1;
                end
            end
        end else if (cs_end & chan_valid & (is_rec | is_rst)) begin
            chan_valid <= 1'b0;
            if (!len_ok) begin
                err_code <= `FITKIT_ERR_LENGTH;
            end else if (is_rec & !pad_ok) begin
                err_code <= `FITKIT_ERR_PADDING;
            end else if (!cb_ok) begin
                err_code <= `FITKIT_ERR_CLEAR_WITHOUT_CB;
            end else if (ovr) begin
                err_code <= `FITKIT_ERR_OVERRUN;
            end
            err_chan <= chan;
            if (!len_ok | (is_rec & (!pad_ok | !cb_ok | ovr))) begin
                err_valid    <= 1'b1;
                fifo_discard <= is_rec;
            end else begin
                fifo_commit <= is_rec;
                soft_rst    <= is_rst;
            end
        end else if (cs_end) begin
            chan_valid <= 1'b0;
        end
    end

`ifdef FORMAL
    // The slave's contract (spi_slave proves its side): one event per cycle at most;
    // bytes and the end only inside a transaction, which begins with cs_start (none
    // after a reset before one).
    reg        f_in = 1'b0, reset_seen = 1'b0, f_end_d = 1'b0, f_part = 1'b0;
    reg [8:0]  f_n = 9'd0;   // bytes of the transaction, saturating at 511
    reg [7:0]  f_chan = 8'd0;
    reg [1:0]  f_w = 2'd0;
    // the transaction's channel: a two-record one, a record channel this build has (an
    // absent unit's address is none, so nothing of it reaches the FIFO)
    wire       f_two = f_chan == `FITKIT_ADDR_LINE || f_chan == `FITKIT_ADDR_TRIANGLE;
    wire       f_has_rec = f_chan[7:2] == 6'd0
                        && !(LINE_UNIT == 0 && f_chan == `FITKIT_ADDR_LINE)
                        && !(TRI_UNIT == 0 && f_chan == `FITKIT_ADDR_TRIANGLE);
    always @(*) begin
        assume (!(cs_start && cs_end) && !(cs_start && rx_valid) && !(cs_end && rx_valid));
        if (!f_in) assume (!rx_valid && !cs_end);
        if (f_in) assume (!cs_start);
        // the address byte is the transaction's first; the kind flags are the channel's
        if (reset_seen && f_in) assert (first == (f_n == 9'd0));
        if (reset_seen && chan_valid) assert (rec_c == f_has_rec
            && two_c == (f_has_rec && f_two) && rst_c == (chan == `FITKIT_ADDR_RESET));
    end
    always @(posedge clk) begin
        f_end_d <= !rst && cs_end;
        if (rst) begin
            reset_seen <= 1'b1;
            f_in <= 1'b0;
            f_n <= 9'd0;
            f_w <= 2'd0;
        end else begin
            if (cs_start) begin
                f_in <= 1'b1;
                f_n <= 9'd0;
                f_w <= 2'd0;
            end
            if (rx_valid) begin
                if (f_n == 9'd0) f_chan <= rx_byte;
                if (f_n != 9'h1FF) f_n <= f_n + 9'd1;
            end
            if (fifo_we && f_w != 2'd3) f_w <= f_w + 2'd1;
            if (cs_end) begin
                f_in <= 1'b0;
                f_part <= cs_partial;
            end
        end
    end
    // what the transaction that just ended was: a record channel's this build has, and
    // whole
    wire       f_rec = f_n != 9'd0 && f_has_rec;
    wire [8:0] f_bytes = 9'd1 + {1'b0, f_two ? BYTES2 : BYTES1};
    wire [1:0] f_recs = f_two ? 2'd2 : 2'd1;
    // records completed by the payload so far
    wire [2:0] f_done_recs = (nbytes >= BYTES1 ? 3'd1 : 3'd0)
                           + (is_two && nbytes >= BYTES2 ? 3'd1 : 3'd0);
    // From the first reset on:
    //  - a packet reaches the FIFO (COMMIT) only whole: the transaction that just ended was
    //    a record channel's, had its exact byte count and no partial byte, and every one
    //    of its records was written;
    //  - every record channel's transaction ends in exactly one COMMIT or DISCARD, the
    //    cycle after its end, and nothing else does; neither comes with a write (the
    //    FIFO's contract, which fifo36's proof assumes);
    //  - a record is written only on a record channel, at most as many as it has;
    //  - the block resets (soft_rst) only after an address-only 0x7F transaction.
    always @(*) begin
        if (reset_seen) begin
            if (fifo_commit)
                assert (f_end_d && f_rec && f_n == f_bytes && !f_part && f_w == f_recs);
            if (f_end_d && f_rec) assert (fifo_commit != fifo_discard);
            if (fifo_commit || fifo_discard) assert (f_end_d && f_rec);
            assert (!(fifo_we && (fifo_commit || fifo_discard)));
            if (fifo_we) assert (f_in && f_rec);
            assert (f_w <= f_recs || !f_rec);
            if (soft_rst)
                assert (f_end_d && f_chan == `FITKIT_ADDR_RESET && f_n == 9'd1 && !f_part);
            // an error report names an error (status.v's proof assumes it)
            if (err_valid) assert (err_code != {`FITKIT_ERR_BITS{1'b0}});
            // the decoder's view agrees with the transaction's
            if (chan_valid) assert (f_in && f_n != 9'd0 && chan == f_chan);
            if (f_in && f_n != 9'd0) assert (chan_valid && chan == f_chan);
            // its count of payload bytes, and the records written of those completed
            // (the last one's write may be on its way; a refused one sets ovr)
            if (chan_valid && (is_rec || is_rst))
                assert (nbytes == (f_n > 9'd256 ? 8'd255 : f_n[7:0] - 8'd1));
            if (chan_valid && is_rec) begin
                if (ovr) assert ({1'b0, f_w} + fifo_we <= f_done_recs);
                else assert ({1'b0, f_w} + fifo_we == f_done_recs);
            end
        end
    end
`endif
endmodule
`default_nettype wire
