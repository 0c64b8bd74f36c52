// tb_readback -- readback behind an SPI master, in front of a read port with latency.
//
// The SPI side is the real spi_slave driven by spi_tasks.vh at f_SCK = f_clk / 8 (the
// contract's limit, one byte every 64 clk cycles), with chan / chan_valid as spi_decoder
// gives them. The memory side plays fb_writer's read port: rd_ack when it grants (at
// random, never more than 10 cycles late), the byte on rd_valid / rd_data a chosen number
// of cycles after the ack (2 at the least, as fb_writer). The reference is a random
// 2^18-byte memory: pixel i of a read-back from start address A is mem[(A + i) mod 2^18].
// Checks per transaction: MISO is 0 during the address, start address and turnaround
// bytes; the pixels are the reference's; reads go out at A, A + 1, ... (the top 6 of the
// 24 address bits ignored, wrapping at 2^18), only after the last start-address byte,
// one at a time. Underruns: none while every read completes within a byte time; with a
// memory that never answers each pixel byte is 0 and one underrun strobe; with one that
// answers only the first read, the first pixel is right and each later one an underrun.
// A read still in flight when the next transaction starts is dropped (the next one's
// pixels are its own). Other channels and a read-back cut short before its start address
// is whole issue no read and no underrun. Prints "N passed, M failed".
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_readback;
    parameter HALF = 40;   // SCK half period: 4 clk cycles (f_SCK = f_clk / 8)
    parameter CS_GAP = 4 * HALF; // CS_n high after each transaction
    localparam integer ABYTES = `FITKIT_READ_HEADER_BYTES - `FITKIT_READ_TURNAROUND - 1;

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
    wire [7:0] rb_tx;
    reg  [7:0] chan = 8'd0;
    reg        chan_valid = 1'b0;
    // The top gives the slave readback's byte only on the read-back channel.
    wire [7:0] slave_tx = (chan_valid && chan == `FITKIT_ADDR_READ) ? rb_tx : 8'd0;

    spi_slave u_spi (
        .clk(clk), .rst(rst), .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi),
        .spi_miso(spi_miso), .cs_start(cs_start), .cs_end(cs_end), .cs_partial(cs_partial),
        .rx_valid(rx_valid), .rx_byte(rx_byte), .byte_index(byte_index),
        .tx_load(tx_load), .tx_byte(slave_tx), .bit_start(bit_start)
    );

    // chan / chan_valid as spi_decoder drives them: the address byte, from when it
    // completes until the transaction ends.
    always @(posedge clk) begin
        if (rst || cs_start || cs_end) chan_valid <= 1'b0;
        else if (rx_valid && rx_index == 8'd0) begin
            chan       <= rx_byte;
            chan_valid <= 1'b1;
        end
    end

    wire        rd_req, underrun;
    wire [17:0] rd_addr;
    wire        rd_ack;
    reg         rd_valid = 1'b0;
    reg  [7:0]  rd_data = 8'd0;

    readback dut (
        .clk(clk), .rst(rst), .cs_start(cs_start), .rx_valid(rx_valid), .rx_byte(rx_byte),
        .chan(chan), .chan_valid(chan_valid), .tx_load(tx_load),
        .byte_index(byte_index), .bit_start(bit_start), .tx_byte(rb_tx), .rd_req(rd_req),
        .rd_addr(rd_addr), .rd_ack(rd_ack), .rd_valid(rd_valid), .rd_data(rd_data),
        .underrun(underrun)
    );

    `include "spi_tasks.vh"

    `include "check.vh"

    // A broken unit must fail the run, not hang it: the summary counts the timeout.
    initial begin
        repeat (500000) @(posedge clk);
        $display("tb_readback: no end after 500000 cycles");
        $display("tb_readback: %0d passed, %0d failed", passed, failed + 1);
        $fatal(1, "tb_readback timed out");
    end

    // ---- The read port ---------------------------------------------------------------
    reg [7:0] mem [0:262143];
    reg       grant = 1'b1;
    assign rd_ack = rd_req & grant;

    integer    cyc = 0;
    integer    grant_pct = 100;   // cycles the port takes a read
    integer    lat_min = 2, lat_span = 1, lat_first = 0;
    integer    answer = 2;        // 0 never, 1 the transaction's first read only, 2 all
    integer    waited = 0;
    reg        inflight = 1'b0;
    reg        fl_first = 1'b0;   // the in-flight read is its transaction's first
    reg [17:0] fl_addr = 18'd0;
    integer    due = 0;
    // Per transaction: reads acked and answered, the next expected address, errors.
    integer    nack = 0, nunder = 0;
    reg [17:0] next_addr = 18'd0;
    integer    e_addr = 0, e_two = 0, e_early = 0;
    reg        addr_done = 1'b0;
    integer    txn = 0, fl_txn = 0;   // transaction number, and the in-flight read's
    integer    stale = 0;             // answers during a later transaction than their ack

    always @(negedge clk) begin
        grant = ($unsigned($random) % 100) < grant_pct || waited >= 10;
        waited = (rd_req && !grant) ? waited + 1 : 0;
    end

    always @(posedge clk) begin
        cyc <= cyc + 1;
        rd_valid <= 1'b0;
        if (!rst) begin
            if (underrun) nunder <= nunder + 1;
            if (rx_valid && chan_valid && chan == `FITKIT_ADDR_READ && rx_index == ABYTES)
                addr_done <= 1'b1;
            if (cs_start) addr_done <= 1'b0;
            if (rd_req && !addr_done) e_early <= e_early + 1;
            if (rd_ack) begin
                if (inflight) e_two <= e_two + 1;
                if (rd_addr != next_addr) begin
                    if (e_addr < 3) $display("  read %0d at %h, want %h", nack, rd_addr, next_addr);
                    e_addr <= e_addr + 1;
                end
                next_addr <= next_addr + 18'd1;
                inflight <= 1'b1;
                fl_addr  <= rd_addr;
                fl_txn   <= txn;
                fl_first <= nack == 0;
                due      <= cyc + ((nack == 0 && lat_first != 0) ? lat_first
                                   : lat_min + $unsigned($random) % lat_span);
                nack     <= nack + 1;
            end else if (inflight && cyc + 1 >= due && (answer == 2 || (answer == 1 && fl_first)))
            begin
                rd_valid <= 1'b1;
                rd_data  <= mem[fl_addr];
                inflight <= 1'b0;
                if (fl_txn != txn) stale <= stale + 1;
            end
        end
    end

    // ---- Transactions ----------------------------------------------------------------
    reg [7:0] rx;
    reg [7:0] got [0:255];
    integer   hdr_bad;

    // Starts a transaction: per-transaction counters restart.
    task begin_txn(input [17:0] start);
        begin
            @(negedge clk);
            nack = 0; nunder = 0; next_addr = start;
            txn = txn + 1;
            stale = 0;
            spi_begin;   // master edges on falling clk edges, away from the sampling ones
        end
    endtask

    // A read-back of n pixels from start (24 bits); the pixels go to got[].
    task read_back(input [23:0] start, input integer n);
        integer k;
        begin
            hdr_bad = 0;
            begin_txn(start[17:0]);
            spi_xfer(`FITKIT_ADDR_READ, rx);
            if (rx != 8'd0) hdr_bad = hdr_bad + 1;
            for (k = ABYTES - 1; k >= 0; k = k - 1) begin
                spi_xfer(start >> (8 * k), rx);
                if (rx != 8'd0) hdr_bad = hdr_bad + 1;
            end
            for (k = 0; k < `FITKIT_READ_TURNAROUND; k = k + 1) begin
                spi_xfer($random, rx);
                if (rx != 8'd0) hdr_bad = hdr_bad + 1;
            end
            for (k = 0; k < n; k = k + 1) begin
                spi_xfer($random, rx);
                got[k] = rx;
            end
            spi_end;
        end
    endtask

    // got[] against the reference: pixels [0, good) from memory, the rest 0.
    function integer mismatches(input [17:0] start, input integer n, input integer good);
        integer k, bad;
        reg [17:0] a;
        begin
            bad = 0;
            for (k = 0; k < n; k = k + 1) begin
                a = start + k;
                if (got[k] != ((k < good) ? mem[a] : 8'd0)) begin
                    if (bad < 3) $display("  pixel %0d (address %h): %h, want %h", k, a, got[k],
                                          (k < good) ? mem[a] : 8'd0);
                    bad = bad + 1;
                end
            end
            mismatches = bad;
        end
    endfunction

    // Waits until readback has stopped prefetching (it goes on after CS_n rises, until
    // two bytes are queued) and no read is in flight, so the next transaction's counts
    // are its own.
    task quiesce;
        integer q;
        begin
            q = 0;
            while (q < 4) begin
                @(negedge clk);
                q = (!inflight && !rd_req) ? q + 1 : 0;
            end
        end
    endtask

    integer keep_in_flight = 0;   // let the next transaction start with a read in flight

    // One read-back, checked: good pixels from memory then zeros, `under` underruns.
    task run(input [23:0] start, input integer n, input integer good, input integer under,
             input [8*48-1:0] what);
        integer bad;
        begin
            e_addr = 0; e_two = 0; e_early = 0;
            read_back(start, n);
            repeat (4) @(negedge clk);
            bad = mismatches(start[17:0], n, good);
            check(bad == 0 && hdr_bad == 0 && nunder == under && e_addr == 0 && e_two == 0
                  && e_early == 0, what);
            if (bad != 0 || hdr_bad != 0 || nunder != under || e_addr != 0 || e_two != 0
                || e_early != 0)
                $display("  start %h, %0d pixels: %0d wrong, %0d header bytes not 0, %0d underruns (want %0d), %0d bad addresses, %0d reads overlapped, %0d early",
                         start, n, bad, hdr_bad, nunder, under, e_addr, e_two, e_early);
            if (answer == 2 && !keep_in_flight) quiesce;
        end
    endtask

    // The memory answers everything again; waits for the reads left in flight.
    task settle;
        begin
            answer = 2;
            quiesce;
        end
    endtask

    integer i, k, n, reads0, bad;
    reg [23:0] a24;
    initial begin
        for (k = 0; k < 262144; k = k + 1) mem[k] = $random;
        repeat (3) @(posedge clk);
        rst = 1'b0;

        // A memory that answers at once.
        run(24'h000000, 8, 8, 0, "fast memory: pixels, header zeros");
        run(24'hFC_0123, 16, 16, 0, "top 6 address bits ignored");
        run(24'h03FFFC, 9, 9, 0, "addresses wrap at 2^18");
        run(24'h012345, 1, 1, 0, "a single pixel");
        run(24'h000100, 0, 0, 0, "header only");
        for (i = 0; i < 8; i = i + 1) begin
            a24 = $random;
            n = 1 + $unsigned($random) % 40;
            run(a24, n, n, 0, "random start and length");
        end
        // Slow grants and latencies, every read within a byte time.
        grant_pct = 50; lat_min = 2; lat_span = 39;
        for (i = 0; i < 10; i = i + 1) begin
            a24 = $random;
            n = 1 + $unsigned($random) % 40;
            run(a24, n, n, 0, "slow memory within a byte time: no underrun");
        end
        grant_pct = 100; lat_min = 2; lat_span = 1;
        // A memory that never answers: each pixel byte is 0 and an underrun.
        answer = 0;
        run(24'h000040, 6, 0, 6, "no answer: zeros, one underrun per pixel");
        settle;
        // Only the first read answered.
        answer = 1;
        run(24'h000080, 5, 1, 4, "first pixel, then underruns");
        settle;
        // A byte that comes late is sent as 0 and the stream stays on its addresses:
        // pixel k is the byte at start + k or, if it missed its slot, 0 (the first read
        // answers after three byte times here, then every read at once).
        lat_first = 200;
        e_addr = 0; e_two = 0; e_early = 0;
        read_back(24'h000300, 16);
        repeat (4) @(negedge clk);
        bad = 0;
        for (k = 0; k < 16; k = k + 1)
            if (got[k] != ((k < nunder) ? 8'd0 : mem[18'h00300 + k])) begin
                if (bad < 3) $display("  pixel %0d: %h, want %h (%0d underruns)", k, got[k],
                                      (k < nunder) ? 8'd0 : mem[18'h00300 + k], nunder);
                bad = bad + 1;
            end
        check(bad == 0 && nunder >= 1 && nunder < 16 && e_addr == 0 && e_two == 0,
              "a late byte: 0 in its slot, the rest aligned");
        lat_first = 0;
        quiesce;
        // A read in flight across the end of a transaction is dropped: the stale byte
        // arrives during the next transaction, whose pixels are still its own.
        lat_first = 200;
        keep_in_flight = 1;
        run(24'h001000, 0, 0, 0, "a read-back ending with a read in flight");
        keep_in_flight = 0;
        lat_first = 0;
        run(24'h002000, 12, 12, 0, "the next read-back's pixels are its own");
        check(stale == 1, "the stale byte came during the next one");
        // Other channels and a cut-short read-back issue no read.
        reads0 = nack;
        begin_txn(18'd0);
        spi_xfer(`FITKIT_ADDR_STATUS, rx);
        for (k = 0; k < 12; k = k + 1) spi_xfer($random, rx);
        spi_end;
        repeat (4) @(negedge clk);
        check(nack == 0 && nunder == 0, "no read on the status channel");
        begin_txn(18'd0);
        spi_xfer(`FITKIT_ADDR_READ, rx);
        for (k = 0; k < ABYTES - 1; k = k + 1) spi_xfer(8'h00, rx);
        spi_end;
        repeat (4) @(negedge clk);
        check(nack == 0 && nunder == 0, "no read before the start address is whole");
        begin_txn(18'd0);
        spi_xfer(8'h55, rx);
        for (k = 0; k < 8; k = k + 1) spi_xfer($random, rx);
        spi_end;
        repeat (4) @(negedge clk);
        check(nack == 0 && nunder == 0, "no read on an unknown channel");
        // And a read-back right after them is whole.
        run(24'h03FFFF, 20, 20, 0, "read-back after other channels");

        $display("tb_readback: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_readback failed");
        $finish;
    end
endmodule
`default_nettype wire
