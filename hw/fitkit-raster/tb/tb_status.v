// tb_status -- the status block against a behavioural model of its contract.
//
// The model keeps the counters, the cycle count, the maximum occupancy and the sticky
// error as the header of status.v states them, and snapshots them (with the inputs the
// block reports directly: free records, the flags) in the cycle snap is high. The
// expected bytes are assembled from the model's fields at the generated map's offsets,
// big-endian. Every input is driven at random every cycle; after a snap the whole block
// is read back over several cycles through byte_index while the counters keep moving,
// so a byte that was not captured with the others shows. Checks: every byte of every
// snapshot (tx_byte a cycle after its byte_index: it is registered), 0 at byte_index 0
// and past the block; scripted cases for the first error
// (kept until rst; later errors, a set-up and cnt_clr do not touch it), a decoder error
// beating an underrun in the same cycle, an underrun's own code and channel, the packet
// index (commits before the error, the error's own cycle excluded, 16 bits wrapping),
// the occupancy maximum (halved, saturating at 255, restarted by cnt_clr from the
// current occupancy), cnt_clr zeroing the counters while a snap in that cycle still sees
// the old values, and rst. Prints "N passed, M failed".
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_status;
    localparam integer BYTES = `FITKIT_STATUS_BYTES;
    localparam integer RECS  = `FITKIT_FIFO_RECORDS;

    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;

    reg        cnt_clr = 1'b0, pkt_done = 1'b0, any_done = 1'b0, frag_written = 1'b0;
    reg        line_busy = 1'b0, tri_busy = 1'b0, clr_busy = 1'b0, commit = 1'b0;
    reg  [9:0] fifo_free = RECS, fifo_occ = 10'd0;
    reg        busy = 1'b0, setup_done = 1'b0, dec_err = 1'b0, underrun = 1'b0, snap = 1'b0;
    reg  [`FITKIT_ERR_BITS-1:0] dec_code = 0;
    reg  [7:0] dec_chan = 8'd0, byte_index = 8'd0;
    wire [7:0] tx_byte;

    status dut (
        .clk(clk), .rst(rst), .cnt_clr(cnt_clr), .pkt_done(pkt_done), .any_done(any_done),
        .frag_written(frag_written), .line_busy(line_busy), .tri_busy(tri_busy),
        .clr_busy(clr_busy), .commit(commit), .fifo_free(fifo_free), .fifo_occ(fifo_occ),
        .busy(busy), .setup_done(setup_done), .dec_err(dec_err), .dec_code(dec_code),
        .dec_chan(dec_chan), .underrun(underrun), .snap(snap), .byte_index(byte_index),
        .tx_byte(tx_byte)
    );

    `include "check.vh"

    // A broken unit must fail the run, not hang it: the summary counts the timeout.
    initial begin
        repeat (2000000) @(posedge clk);
        $display("tb_status: no end after 2000000 cycles");
        $display("tb_status: %0d passed, %0d failed", passed, failed + 1);
        $fatal(1, "tb_status timed out");
    end

    // ---- Model -----------------------------------------------------------------------
    reg [31:0] m_packets, m_frags, m_line, m_tri, m_clr, m_cycle, m_last;
    integer    m_maxocc, m_commits;
    reg        m_err;
    integer    m_code, m_chan, m_pkt;
    // The snapshot: the fields as captured.
    reg [31:0] s_packets, s_frags, s_line, s_tri, s_clr, s_last;
    integer    s_free, s_pairs, s_code, s_chan, s_pkt;
    reg [7:0]  s_flags;

    task model_reset;
        begin
            m_packets = 0; m_frags = 0; m_line = 0; m_tri = 0; m_clr = 0; m_cycle = 0;
            m_last = 0; m_maxocc = 0; m_commits = 0; m_err = 0; m_code = 0; m_chan = 0;
            m_pkt = 0;
            s_packets = 0; s_frags = 0; s_line = 0; s_tri = 0; s_clr = 0; s_last = 0;
            s_free = 0; s_pairs = 0; s_code = 0; s_chan = 0; s_pkt = 0; s_flags = 0;
        end
    endtask

    // The model sees the inputs of a cycle as the clock edge ends it.
    always @(posedge clk) begin
        if (rst) model_reset;
        else begin
            if (snap) begin
                // Captured: the registers as they are, the direct inputs as they are now.
                s_packets = m_packets; s_frags = m_frags; s_line = m_line; s_tri = m_tri;
                s_clr = m_clr; s_last = m_last;
                s_pairs = (m_maxocc / 2 > 255) ? 255 : m_maxocc / 2;
                s_free = fifo_free;
                s_code = m_code; s_chan = m_chan; s_pkt = m_pkt;
                s_flags = 8'd0;
                s_flags[`FITKIT_FLAG_BUSY] = busy;
                s_flags[`FITKIT_FLAG_ERROR] = m_err;
                s_flags[`FITKIT_FLAG_FIFO_EMPTY] = fifo_occ == 0;
                s_flags[`FITKIT_FLAG_SETUP_DONE] = setup_done;
            end
            if (!m_err && (dec_err || underrun)) begin
                m_err = 1;
                m_code = dec_err ? dec_code : `FITKIT_ERR_READ_UNDERRUN;
                m_chan = dec_err ? dec_chan : `FITKIT_ADDR_READ;
                m_pkt = m_commits % 65536;
            end
            if (commit) m_commits = m_commits + 1;
            if (cnt_clr) begin
                // A set-up starting: counters and the cycle count from 0, strobes lost.
                m_packets = 0; m_frags = 0; m_line = 0; m_tri = 0; m_clr = 0; m_cycle = 0;
                m_last = 0; m_maxocc = fifo_occ;
            end else begin
                if (any_done) m_last = m_cycle;
                m_cycle = m_cycle + 1;
                if (pkt_done) m_packets = m_packets + 1;
                if (frag_written) m_frags = m_frags + 1;
                if (line_busy) m_line = m_line + 1;
                if (tri_busy) m_tri = m_tri + 1;
                if (clr_busy) m_clr = m_clr + 1;
                if (fifo_occ > m_maxocc) m_maxocc = fifo_occ;
            end
        end
    end

    // Byte k of the expected block.
    function [7:0] field(input [31:0] v, input integer k, input integer off, input integer n);
        field = v >> (8 * (n - 1 - (k - off)));
    endfunction

    function [7:0] exp_byte(input integer k);
        begin
            exp_byte = 8'd0;
            if (k >= `FITKIT_STATUS_FREE && k < `FITKIT_STATUS_FREE + 2)
                exp_byte = field(s_free, k, `FITKIT_STATUS_FREE, 2);
            if (k == `FITKIT_STATUS_FLAGS) exp_byte = s_flags;
            if (k == `FITKIT_STATUS_ERROR_CODE) exp_byte = s_code;
            if (k == `FITKIT_STATUS_ERROR_CHANNEL) exp_byte = s_chan;
            if (k >= `FITKIT_STATUS_ERROR_PACKET && k < `FITKIT_STATUS_ERROR_PACKET + 2)
                exp_byte = field(s_pkt, k, `FITKIT_STATUS_ERROR_PACKET, 2);
            if (k >= `FITKIT_STATUS_PACKETS && k < `FITKIT_STATUS_PACKETS + 4)
                exp_byte = field(s_packets, k, `FITKIT_STATUS_PACKETS, 4);
            if (k >= `FITKIT_STATUS_FRAGMENTS && k < `FITKIT_STATUS_FRAGMENTS + 4)
                exp_byte = field(s_frags, k, `FITKIT_STATUS_FRAGMENTS, 4);
            if (k >= `FITKIT_STATUS_LINE_CYCLES && k < `FITKIT_STATUS_LINE_CYCLES + 4)
                exp_byte = field(s_line, k, `FITKIT_STATUS_LINE_CYCLES, 4);
            if (k >= `FITKIT_STATUS_TRIANGLE_CYCLES && k < `FITKIT_STATUS_TRIANGLE_CYCLES + 4)
                exp_byte = field(s_tri, k, `FITKIT_STATUS_TRIANGLE_CYCLES, 4);
            if (k >= `FITKIT_STATUS_CLEAR_CYCLES && k < `FITKIT_STATUS_CLEAR_CYCLES + 4)
                exp_byte = field(s_clr, k, `FITKIT_STATUS_CLEAR_CYCLES, 4);
            if (k >= `FITKIT_STATUS_END_CYCLE && k < `FITKIT_STATUS_END_CYCLE + 4)
                exp_byte = field(s_last, k, `FITKIT_STATUS_END_CYCLE, 4);
            if (k == `FITKIT_STATUS_FIFO_MAX_PAIRS) exp_byte = s_pairs;
        end
    endfunction

    // ---- Stimulus --------------------------------------------------------------------
    // Percentages of cycles each strobe is high; the busy levels come in runs.
    integer p_done = 10, p_frag = 30, p_commit = 5, p_err = 0, p_under = 0, p_clr = 0;
    integer hold = 0;     // 1: the random drive stands still (scripted cases)

    always @(negedge clk) if (!rst && !hold) begin
        pkt_done = ($unsigned($random) % 100) < p_done;
        any_done = pkt_done || (($unsigned($random) % 100) < 2);
        frag_written = ($unsigned($random) % 100) < p_frag;
        if (($unsigned($random) % 16) == 0) line_busy = !line_busy;
        if (($unsigned($random) % 16) == 0) tri_busy = !tri_busy;
        if (($unsigned($random) % 16) == 0) clr_busy = !clr_busy;
        commit = ($unsigned($random) % 100) < p_commit;
        // Occupancy: a random walk over 0..RECS, now and then a jump.
        case ($unsigned($random) % 8)
            0: fifo_occ = ($unsigned($random) % 8 == 0) ? RECS : $unsigned($random) % (RECS + 1);
            1, 2: if (fifo_occ < RECS) fifo_occ = fifo_occ + 1;
            3, 4: if (fifo_occ > 0) fifo_occ = fifo_occ - 1;
            default: ;
        endcase
        fifo_free = RECS - fifo_occ;
        busy = $random;
        if (($unsigned($random) % 64) == 0) setup_done = !setup_done;
        dec_err = ($unsigned($random) % 1000) < p_err;
        dec_code = $random;
        dec_chan = $random;
        underrun = ($unsigned($random) % 1000) < p_under;
        cnt_clr = ($unsigned($random) % 1000) < p_clr;
    end

    // Snaps, then reads every byte (and some past the block) over the following cycles.
    integer nsnaps = 0, nbytes = 0, e_bytes = 0;
    task snap_and_read;
        integer k;
        reg [7:0] want;
        begin
            @(negedge clk);
            snap = 1'b1;
            @(negedge clk);
            snap = 1'b0;
            for (k = 0; k <= BYTES + 2; k = k + 1) begin
                byte_index = k;
                @(posedge clk);   // tx_byte is registered: the byte of the last cycle's index
                #1;
                want = (k >= 1 && k <= BYTES) ? exp_byte(k - 1) : 8'd0;
                if (tx_byte !== want) begin
                    if (e_bytes < 5)
                        $display("  snapshot %0d byte %0d: %h, want %h", nsnaps, k - 1, tx_byte,
                                 want);
                    e_bytes = e_bytes + 1;
                end
                nbytes = nbytes + 1;
                if (($unsigned($random) % 2) == 0) @(negedge clk);
            end
            byte_index = 8'd255;
            @(posedge clk);
            #1;
            if (tx_byte !== 8'd0) e_bytes = e_bytes + 1;
            nsnaps = nsnaps + 1;
        end
    endtask

    // Drives one scripted cycle: the given strobes high, the random drive paused.
    task strobe(input d_err, input [7:0] d_code, input [7:0] d_chan, input und, input cmt,
                input clr, input [9:0] occ);
        begin
            @(negedge clk);
            pkt_done = 1'b0; any_done = 1'b0; frag_written = 1'b0; snap = 1'b0;
            dec_err = d_err; dec_code = d_code; dec_chan = d_chan; underrun = und;
            commit = cmt; cnt_clr = clr; fifo_occ = occ; fifo_free = RECS - occ;
            @(negedge clk);
            dec_err = 1'b0; underrun = 1'b0; commit = 1'b0; cnt_clr = 1'b0;
        end
    endtask

    task reset_block;
        begin
            @(negedge clk);
            rst = 1'b1;
            @(negedge clk);
            rst = 1'b0;
        end
    endtask

    // Snapshot and one byte of it.
    task expect_bytes(input integer code, input integer chan, input integer pkt,
                      input integer pairs, input [8*48-1:0] what);
        reg ok;
        integer e;
        begin
            e = e_bytes;
            snap_and_read;
            ok = s_code == code && s_chan == chan && s_pkt == pkt
                 && (pairs < 0 || s_pairs == pairs);
            check(ok && e_bytes == e, what);
            if (!ok)
                $display("  model: code %0d chan %h packet %0d pairs %0d", s_code, s_chan, s_pkt,
                         s_pairs);
        end
    endtask

    integer i, k, e0;
    initial begin
        repeat (3) @(posedge clk);   // rst resets the model too
        @(negedge clk);
        rst = 1'b0;

        // Random traffic, no errors: counters, flags, free records, occupancy.
        for (i = 0; i < 40; i = i + 1) begin
            repeat ($unsigned($random) % 300) @(negedge clk);
            e0 = e_bytes;
            snap_and_read;
            check(e_bytes == e0, "snapshot bytes, random traffic");
        end
        // With set-ups (cnt_clr) and errors now and then.
        p_clr = 5; p_err = 3; p_under = 3;
        for (i = 0; i < 40; i = i + 1) begin
            repeat ($unsigned($random) % 300) @(negedge clk);
            e0 = e_bytes;
            snap_and_read;
            check(e_bytes == e0, "snapshot bytes, with cnt_clr and errors");
        end
        for (k = 0; k < 6; k = k + 1) begin
            reset_block;
            p_err = 20 * k;
            for (i = 0; i < 10; i = i + 1) begin
                repeat ($unsigned($random) % 100) @(negedge clk);
                e0 = e_bytes;
                snap_and_read;
                check(e_bytes == e0, "snapshot bytes after rst, errors 0..10 %");
            end
        end

        // Scripted cases: the random drive stands still.
        p_err = 0; p_under = 0; p_clr = 0;
        hold = 1;
        e0 = e_bytes;
        reset_block;
        strobe(0, 0, 0, 0, 1, 0, 10'd0);
        strobe(0, 0, 0, 0, 1, 0, 10'd0);
        strobe(0, 0, 0, 0, 1, 0, 10'd0);
        // A decoder error and an underrun together: the decoder's wins; it happens with
        // a commit, which is not yet counted in its packet index.
        strobe(1, `FITKIT_ERR_PADDING, `FITKIT_ADDR_TRIANGLE, 1, 1, 0, 10'd0);
        expect_bytes(`FITKIT_ERR_PADDING, `FITKIT_ADDR_TRIANGLE, 3, -1,
                     "decoder error beats an underrun");
        strobe(1, `FITKIT_ERR_LENGTH, `FITKIT_ADDR_LINE, 0, 0, 0, 10'd0);
        strobe(0, 0, 0, 1, 0, 0, 10'd0);
        strobe(0, 0, 0, 0, 0, 1, 10'd0);
        expect_bytes(`FITKIT_ERR_PADDING, `FITKIT_ADDR_TRIANGLE, 3, -1,
                     "first error kept over errors and cnt_clr");
        reset_block;
        expect_bytes(0, 0, 0, 0, "rst clears the error");
        strobe(0, 0, 0, 1, 0, 0, 10'd0);
        strobe(1, `FITKIT_ERR_OVERRUN, `FITKIT_ADDR_LINE, 0, 0, 0, 10'd0);
        expect_bytes(`FITKIT_ERR_READ_UNDERRUN, `FITKIT_ADDR_READ, 0, -1,
                     "an underrun's code and channel");
        // The packet index wraps at 16 bits.
        reset_block;
        @(negedge clk);
        commit = 1'b1;
        repeat (65536 + 4) @(negedge clk);
        commit = 1'b0;
        strobe(1, `FITKIT_ERR_UNKNOWN_ADDRESS, 8'h55, 0, 0, 0, 10'd0);
        expect_bytes(`FITKIT_ERR_UNKNOWN_ADDRESS, 8'h55, 4, -1, "packet index wraps at 16 bits");
        // Occupancy: the maximum halved, saturating at 255; cnt_clr restarts it.
        reset_block;
        strobe(0, 0, 0, 0, 0, 0, 10'd509);
        expect_bytes(0, 0, 0, 254, "occupancy 509: 254 pairs");
        strobe(0, 0, 0, 0, 0, 0, 10'd511);
        expect_bytes(0, 0, 0, 255, "occupancy 511: 255 pairs");
        reset_block;
        strobe(0, 0, 0, 0, 0, 0, RECS);
        strobe(0, 0, 0, 0, 0, 0, 10'd3);
        expect_bytes(0, 0, 0, 255, "a full FIFO saturates at 255, kept");
        strobe(0, 0, 0, 0, 0, 1, 10'd100);
        strobe(0, 0, 0, 0, 0, 0, 10'd20);
        expect_bytes(0, 0, 0, 50, "cnt_clr restarts from the occupancy");
        // cnt_clr with a snap in the same cycle: the snapshot has the old counts.
        hold = 0;
        repeat (200) @(negedge clk);
        hold = 1;
        @(negedge clk);
        pkt_done = 1'b0; any_done = 1'b0; frag_written = 1'b0;
        line_busy = 1'b0; tri_busy = 1'b0; clr_busy = 1'b0;
        dec_err = 1'b0; underrun = 1'b0; commit = 1'b0;
        cnt_clr = 1'b1;
        snap = 1'b1;
        @(negedge clk);
        cnt_clr = 1'b0;
        snap = 1'b0;
        check(s_line != 0 && s_clr != 0 && s_last != 0, "a snap with cnt_clr: the old counts");
        for (k = 0; k <= BYTES + 2; k = k + 1) begin
            byte_index = k;
            @(posedge clk);
            #1;
            if (tx_byte !== ((k >= 1 && k <= BYTES) ? exp_byte(k - 1) : 8'd0))
                e_bytes = e_bytes + 1;
        end
        snap_and_read;
        check(s_packets == 0 && s_line == 0 && s_last == 0, "and then zeros");
        check(e_bytes == e0, "scripted cases: every byte");
        $display("tb_status: %0d snapshots, %0d bytes read", nsnaps, nbytes);

        $display("tb_status: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_status failed");
        $finish;
    end
endmodule
`default_nettype wire
