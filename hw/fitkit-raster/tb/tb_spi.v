// tb_spi -- spi_slave (and spi_decoder + fifo36 behind it) driven by an SPI master.
//
// The master runs at f_SCK = f_clk / 8, the contract's limit, with its edges off the clk
// grid. Checks: every byte arrives with its index; MISO returns the byte the slave was
// given for each index (a function of the index here), 0 during the address byte; a
// transaction ending mid-byte reports cs_partial; the docs/protocol.md test vector (line,
// CB = 1, (1, 2) -> (300, 400), colour 0xA9) on channel 0x01 lands in the FIFO as the
// records 0x8_0405_2CC8 and 0x5_4800_0000 tagged 1, and a clear on 0x03 as one record
// tagged 3. Prints "N passed, M failed".
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_spi;
    parameter HALF = 40;         // 4 clk cycles
    parameter CS_GAP = 4 * HALF; // CS_n high after each transaction
    // A record's FIFO tag is the low two bits of its channel's address.
    localparam [7:0] A_LINE = `FITKIT_ADDR_LINE, A_CLEAR = `FITKIT_ADDR_CLEAR;
    localparam integer BYTES1 = (`FITKIT_RECORD_BITS + 7) / 8;   // a 1-record packet

    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;

    reg spi_sck = 1'b0, spi_cs_n = 1'b1, spi_mosi = 1'b0;
    wire spi_miso;
    wire cs_start, cs_end, cs_partial, rx_valid, tx_load, bit_start;
    wire [7:0] rx_byte, byte_index;
    // a completed byte's position: byte_index of the cycle before rx_valid
    reg  [7:0] rx_index = 8'd0;
    always @(posedge clk) rx_index <= byte_index;
    wire [7:0] tx_byte = (byte_index == 8'd0) ? 8'd0 : byte_index * 8'd37 + 8'd5;

    spi_slave dut (
        .clk(clk), .rst(rst), .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi),
        .spi_miso(spi_miso), .cs_start(cs_start), .cs_end(cs_end), .cs_partial(cs_partial),
        .rx_valid(rx_valid), .rx_byte(rx_byte), .byte_index(byte_index),
        .tx_load(tx_load), .tx_byte(tx_byte), .bit_start(bit_start)
    );

    wire [7:0]  chan, err_chan;
    wire        chan_valid, fwe, fcommit, fdiscard, err_valid, soft_rst, snap;
    wire [37:0] fdin, dout;
    wire [`FITKIT_ERR_BITS-1:0] err_code;
    wire        room, vld, ffree;
    wire [9:0]  free_count, occ;
    reg         next = 1'b0;
    spi_decoder dec (
        .clk(clk), .rst(rst), .cs_start(cs_start), .cs_end(cs_end), .cs_partial(cs_partial),
        .rx_valid(rx_valid), .rx_byte(rx_byte), .fifo_room(room),
        .chan(chan), .chan_valid(chan_valid), .fifo_din(fdin), .fifo_we(fwe),
        .fifo_commit(fcommit), .fifo_discard(fdiscard), .err_valid(err_valid),
        .err_code(err_code), .err_chan(err_chan), .soft_rst(soft_rst), .snap(snap)
    );
    fifo36 fifo (
        .clk(clk), .rst(rst), .DATA_IN(fdin), .DATA_WE(fwe), .COMMIT(fcommit),
        .DISCARD(fdiscard), .FIFO_NEXT(next), .DATA_OUT(dout), .DATA_VLD(vld),
        .FIFO_FREE(ffree), .room(room), .free_count(free_count), .occupancy(occ)
    );

    `include "spi_tasks.vh"

    `include "check.vh"

    // Bytes the slave received, by the monitor.
    reg [7:0] got [0:255];
    reg [7:0] got_idx [0:255];
    integer ngot = 0, nend = 0, partial = 0, nerr = 0;
    always @(posedge clk) begin
        if (err_valid) nerr <= nerr + 1;
        if (cs_start) ngot <= 0;
        if (rx_valid) begin
            got[ngot] <= rx_byte;
            got_idx[ngot] <= rx_index;
            ngot <= ngot + 1;
        end
        if (cs_end) begin
            nend <= nend + 1;
            partial <= cs_partial;
        end
    end

    reg [7:0] sent [0:255];
    reg [7:0] back [0:255];
    reg [7:0] rx;
    integer i, k, n, bad, e;
    initial begin
        repeat (3) @(posedge clk);
        rst = 1'b0;
        #3;   // the master's edges fall between clk edges from here on
        for (i = 0; i < 40; i = i + 1) begin
            n = 1 + ($unsigned($random) % 40);
            // The status channel keeps the decoder out of the FIFO.
            spi_begin;
            for (k = 0; k < n; k = k + 1) begin
                sent[k] = (k == 0) ? `FITKIT_ADDR_STATUS : $random;
                spi_xfer(sent[k], rx);
                back[k] = rx;
            end
            spi_end;
            bad = 0;
            if (ngot != n) bad = bad + 1;
            for (k = 0; k < n; k = k + 1) begin
                if (got[k] != sent[k] || got_idx[k] != k) bad = bad + 1;
                if (back[k] != ((k == 0) ? 0 : (k * 37 + 5) % 256)) bad = bad + 1;
            end
            check(bad == 0 && !partial, "bytes in and out of a transaction");
            if (bad != 0)
                for (k = 0; k < n && k < 4; k = k + 1)
                    $display("  byte %0d: sent %h got %h (index %0d) back %h, %0d of %0d arrived",
                             k, sent[k], got[k], got_idx[k], back[k], ngot, n);
        end
        // A transaction ending after 3 bits of its second byte.
        e = nend;
        spi_begin;
        spi_xfer(`FITKIT_ADDR_STATUS, rx);
        for (k = 0; k < 3; k = k + 1) begin
            spi_mosi = 1'b1;
            #(HALF) spi_sck = 1'b1;
            #(HALF) spi_sck = 1'b0;
        end
        spi_end;
        check(nend == e + 1 && partial && ngot == 1, "partial byte reported");

        // The test vector through the decoder into the FIFO.
        spi_begin;
        spi_xfer(`FITKIT_ADDR_LINE, rx);
        for (k = 0; k < `FITKIT_MAX_PACKET_BYTES; k = k + 1)
            spi_xfer(72'h8_0405_2CC8_5_4800_0000 >> (64 - 8 * k), rx);
        spi_end;
        check(vld && dout == {A_LINE[1:0], 36'h8_0405_2CC8}, "test vector record 0");
        @(negedge clk) next = 1'b1;
        @(negedge clk) next = 1'b0;
        #1;
        check(vld && dout == {A_LINE[1:0], 36'h5_4800_0000}, "test vector record 1");
        @(negedge clk) next = 1'b1;
        @(negedge clk) next = 1'b0;
        spi_begin;
        spi_xfer(`FITKIT_ADDR_CLEAR, rx);
        for (k = 0; k < BYTES1; k = k + 1) spi_xfer(40'hD4_8000_0000 >> (32 - 8 * k), rx);
        spi_end;
        check(vld && dout == {A_CLEAR[1:0], 36'hD_4800_0000}, "clear record");
        @(negedge clk) next = 1'b1;
        @(negedge clk) next = 1'b0;
        #1;
        check(!vld && occ == 0, "FIFO empty");

        // Reset while CS_n is low: the rest of that transaction is no packet. The tail
        // here is a whole clear packet (channel 0x03, D4 80 00 00 00) that would clear the
        // frame if the slave took the first byte after reset for an address.
        e = nend;
        n = nerr;
        spi_begin;
        spi_xfer(`FITKIT_ADDR_LINE, rx);
        spi_xfer(8'h80, rx);
        spi_xfer(8'h40, rx);
        @(negedge clk) rst = 1'b1;
        repeat (3) @(negedge clk);
        rst = 1'b0;
        #3;
        spi_xfer(`FITKIT_ADDR_CLEAR, rx);
        for (k = 0; k < BYTES1; k = k + 1) spi_xfer(40'hD4_8000_0000 >> (32 - 8 * k), rx);
        spi_end;
        check(!vld && occ == 0 && nend == e && ngot == 3 && nerr == n,
              "reset mid-transaction: its tail is no packet");
        if (vld || occ != 0 || nend != e)
            $display("  after the reset: FIFO %0d records (head %h), %0d transaction ends",
                     occ, dout, nend - e);
        // ... and the next transaction is whole again.
        spi_begin;
        spi_xfer(`FITKIT_ADDR_CLEAR, rx);
        for (k = 0; k < BYTES1; k = k + 1) spi_xfer(40'hD4_8000_0000 >> (32 - 8 * k), rx);
        spi_end;
        check(vld && dout == {A_CLEAR[1:0], 36'hD_4800_0000} && nend == e + 1,
              "a clear after the reset");
        @(negedge clk) next = 1'b1;
        @(negedge clk) next = 1'b0;

        $display("tb_spi: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_spi failed");
        $finish;
    end
endmodule
`default_nettype wire
