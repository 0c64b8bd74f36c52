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
//   5 unknown address.
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
module spi_decoder (
    input  wire        clk,
    input  wire        rst,
    input  wire        cs_start,
    input  wire        cs_end,
    input  wire        cs_partial,
    input  wire        rx_valid,
    input  wire [7:0]  rx_byte,
    input  wire [7:0]  rx_index,
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
    // low two bits are the FIFO tag.
    wire is_rec  = chan_valid & (chan[7:2] == 6'd0);
    wire is_two  = chan_valid
                 & ((chan == `FITKIT_ADDR_LINE) | (chan == `FITKIT_ADDR_TRIANGLE));
    wire is_rst  = chan_valid & (chan == `FITKIT_ADDR_RESET);
    wire known   = (rx_byte[7:2] == 6'd0) | (rx_byte == `FITKIT_ADDR_STATUS)
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
            acc        <= 40'd0;
            nbytes     <= 8'd0;
            ovr        <= 1'b0;
            fifo_din   <= 38'd0;
            err_code   <= {`FITKIT_ERR_BITS{1'b0}};
            err_chan   <= 8'd0;
        end else if (cs_start) begin
            chan_valid <= 1'b0;
            acc        <= 40'd0;
            nbytes     <= 8'd0;
            ovr        <= 1'b0;
        end else if (rx_valid) begin
            if (rx_index == 8'd0) begin
                chan       <= rx_byte;
                chan_valid <= 1'b1;
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
endmodule
`default_nettype wire
