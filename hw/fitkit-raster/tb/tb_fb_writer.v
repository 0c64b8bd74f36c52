// tb_fb_writer -- fb_writer between a fragment queue, a read requester and a memory.
//
// The testbench plays fb_writer's three neighbours: a show-ahead fragment queue (as
// frag_fifo), a read requester that keeps one read in flight (as readback) and a
// synchronous memory that takes a request in a cycle where mem_wait is low and answers
// a read the cycle after (as sim_ram), with mem_wait toggled at random. The reference
// is the fragment list itself: the in-frame fragments (x <= wm1, y <= hm1) in order, at
// address y * SIDE + x. Checks, every cycle: the accepted writes are exactly that list in
// order (address, data), none for a clipped fragment; frag_written marks exactly the
// accepted writes of counted fragments; a request waiting on mem_wait is held unchanged;
// never a write and a read together; write_pending is "a write is on the port"; a read
// request is acked whenever the request register is free or being accepted, before any
// fragment, and no fragment is popped in that cycle; otherwise a fragment is popped
// whenever the register can take one; a popped fragment is on the port the next cycle
// (or, clipped, leaves it empty); each read is accepted at its address and rd_valid /
// rd_data bring the memory's byte the cycle after, and only then. At the end the memory
// holds the reference frame. A burst without mem_wait retires one fragment per cycle.
// Prints "N passed, M failed".
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_fb_writer;
    localparam integer SIDE = `FITKIT_FRAME_SIDE;   // the framebuffer's row stride
    localparam integer QN   = 65536;                // fragment queue entries

    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;

    // Fragment queue: {counted, col, y, x}, show-ahead. The head is a register of its own
    // (not a continuous read of the array, which Verilator does not re-evaluate when an
    // element is written).
    reg  [26:0] fq [0:QN-1];
    integer     qhead = 0, qtail = 0;
    reg  [26:0] frag_dout = 27'd0;
    wire        frag_empty = qhead == qtail;
    wire        frag_re;

    reg  [8:0]  wm1 = 9'd0, hm1 = 9'd0;
    reg         rd_req = 1'b0;
    reg  [17:0] rd_addr = 18'd0;
    wire        rd_ack, rd_valid, frag_written, write_pending;
    wire [7:0]  rd_data;
    wire [17:0] mem_addr;
    wire [7:0]  mem_wdata;
    wire        mem_we, mem_re;
    reg  [7:0]  mem_rdata = 8'd0;
    reg         mem_wait = 1'b0;

    fb_writer dut (
        .clk(clk), .rst(rst), .wm1(wm1), .hm1(hm1), .frag_dout(frag_dout),
        .frag_empty(frag_empty), .frag_re(frag_re), .rd_req(rd_req), .rd_addr(rd_addr),
        .rd_ack(rd_ack), .rd_valid(rd_valid), .rd_data(rd_data),
        .frag_written(frag_written), .write_pending(write_pending), .mem_addr(mem_addr),
        .mem_wdata(mem_wdata), .mem_we(mem_we), .mem_re(mem_re), .mem_rdata(mem_rdata),
        .mem_wait(mem_wait)
    );

    `include "check.vh"

    // A broken unit must fail the run, not hang it: the summary counts the timeout.
    initial begin
        repeat (500000) @(posedge clk);
        $display("tb_fb_writer: no end after 500000 cycles");
        $display("tb_fb_writer: %0d passed, %0d failed", passed, failed + 1);
        $fatal(1, "tb_fb_writer timed out");
    end

    // Memory: a request is taken where mem_wait is low, read data comes the cycle after.
    reg [7:0] ram [0:SIDE * SIDE - 1];
    reg [7:0] refm [0:SIDE * SIDE - 1];
    always @(posedge clk) begin
        if (mem_we && !mem_wait) ram[mem_addr] <= mem_wdata;
        if (mem_re && !mem_wait) mem_rdata <= ram[mem_addr];
    end
    always @(posedge clk) if (!rst && frag_re && !frag_empty) begin
        qhead     <= qhead + 1;
        frag_dout <= fq[(qhead + 1) % QN];
    end

    // Expected writes, in order: address, data, counted.
    reg [17:0] xa [0:QN-1];
    reg [7:0]  xd [0:QN-1];
    reg        xc [0:QN-1];
    integer    nexp = 0, nwr = 0;

    // Pushes a fragment; the reference takes it if it lies in the frame set now (the frame
    // is only changed while the writer is idle).
    task push(input integer x, input integer y, input integer c, input cnt);
        begin
            fq[qtail % QN] = {cnt, c[7:0], y[8:0], x[8:0]};
            if (qhead == qtail) frag_dout = fq[qtail % QN];
            qtail = qtail + 1;
            if (x <= wm1 && y <= hm1) begin
                xa[nexp % QN] = y * SIDE + x;
                xd[nexp % QN] = c;
                xc[nexp % QN] = cnt;
                refm[y * SIDE + x] = c;
                nexp = nexp + 1;
            end
        end
    endtask

    // Error counts per property, and the stimulus knobs.
    integer e_stream = 0, e_written = 0, e_hold = 0, e_both = 0, e_pending = 0, e_ack = 0;
    integer e_pop = 0, e_port = 0, e_read = 0, e_valid = 0;
    integer wait_pct = 0, read_pct = 0;
    integer reads = 0;
    integer cyc = 0;

    // Read requester state: 0 idle, 1 requesting, 2 acked (in the writer), 3 accepted.
    integer    rstate = 0;
    reg [17:0] raddr;
    reg [7:0]  rexp;
    // Last cycle's port and pop, for the hold and "on the port next cycle" checks.
    reg        p_req = 1'b0, p_we = 1'b0, p_re = 1'b0, p_wait = 1'b0, p_pop = 1'b0;
    reg [17:0] p_addr = 18'd0;
    reg [7:0]  p_data = 8'd0;
    reg [26:0] p_frag = 27'd0;
    reg        p_in = 1'b0;
    reg        free, acc_w, acc_r;

    always @(posedge clk) cyc <= cyc + 1;

    always @(negedge clk) if (!rst) begin
        // Drive this cycle's inputs.
        mem_wait = ($unsigned($random) % 100) < wait_pct;
        if (rstate != 1) rd_req = 1'b0;   // held until the cycle it is acked
        if (rstate == 0 && ($unsigned($random) % 100) < read_pct) begin
            rstate = 1;
            raddr = $random;
            rd_addr = raddr;
            rd_req = 1'b1;
        end
        #1;
        free  = !(mem_we || mem_re) || !mem_wait;   // the request register can load
        acc_w = mem_we && !mem_wait;
        acc_r = mem_re && !mem_wait;
        if (mem_we && mem_re) e_both = e_both + 1;
        if (write_pending != mem_we) e_pending = e_pending + 1;
        // Held while waiting.
        if (p_req && p_wait
            && (mem_we != p_we || mem_re != p_re || mem_addr != p_addr
                || (mem_we && mem_wdata != p_data)))
            e_hold = e_hold + 1;
        // Last cycle's pop is on the port now, or the port is empty if it was clipped.
        if (p_pop) begin
            if (p_in && !(mem_we && mem_addr == p_frag[17:9] * SIDE + p_frag[8:0]
                          && mem_wdata == p_frag[25:18]))
                e_port = e_port + 1;
            if (!p_in && (mem_we || mem_re)) e_port = e_port + 1;
        end
        // Arbitration: a read first, else a fragment whenever the register is free.
        if (rd_ack != (rd_req && free)) e_ack = e_ack + 1;
        if (frag_re != (free && !rd_req && !frag_empty)) e_pop = e_pop + 1;
        // Accepted writes against the reference list.
        if (acc_w) begin
            if (nwr >= nexp || mem_addr != xa[nwr % QN] || mem_wdata != xd[nwr % QN]) begin
                if (e_stream < 3)
                    $display("  write %0d at cycle %0d: addr %0d data %h, want addr %0d data %h",
                             nwr, cyc, mem_addr, mem_wdata, xa[nwr % QN], xd[nwr % QN]);
                e_stream = e_stream + 1;
            end
            if (frag_written != (nwr < nexp && xc[nwr % QN])) e_written = e_written + 1;
            nwr = nwr + 1;
        end else if (frag_written) e_written = e_written + 1;
        // The read: acked, accepted at its address, its byte the cycle after.
        if (rstate == 3) begin
            if (!rd_valid || rd_data != rexp) e_valid = e_valid + 1;
            rstate = 0;
            reads = reads + 1;
        end else if (rd_valid) e_valid = e_valid + 1;
        if (acc_r) begin
            if (rstate != 2 || mem_addr != raddr) e_read = e_read + 1;
            rexp = ram[mem_addr];
            rstate = 3;
        end
        if (rstate == 1 && rd_ack) rstate = 2;
        p_req = mem_we || mem_re; p_we = mem_we; p_re = mem_re; p_wait = mem_wait;
        p_addr = mem_addr; p_data = mem_wdata;
        p_pop = frag_re && !frag_empty;
        p_frag = frag_dout;
        p_in = frag_dout[8:0] <= wm1 && frag_dout[17:9] <= hm1;
    end

    // Waits until every fragment is written and no read is left.
    task drain;
        integer quiet;
        begin
            quiet = 0;
            read_pct = 0;
            while (quiet < 4) begin
                @(negedge clk);
                #2;
                quiet = (frag_empty && !mem_we && !mem_re && rstate == 0) ? quiet + 1 : 0;
            end
        end
    endtask

    // n fragments in the frame's neighbourhood (coordinates to xr, yr), the frame edges
    // among them, a third of them not counted.
    task burst(input integer n, input integer xr, input integer yr);
        integer k, x, y;
        begin
            for (k = 0; k < n; k = k + 1) begin
                case ($unsigned($random) % 8)
                    0: begin x = wm1; y = $unsigned($random) % yr; end
                    1: begin x = wm1 + 1; y = $unsigned($random) % yr; end
                    2: begin x = $unsigned($random) % xr; y = hm1; end
                    3: begin x = $unsigned($random) % xr; y = hm1 + 1; end
                    default: begin x = $unsigned($random) % xr; y = $unsigned($random) % yr; end
                endcase
                push(x % SIDE, y % SIDE, $random, ($unsigned($random) % 3) != 0);
                if (($unsigned($random) % 4) == 0) @(negedge clk);
            end
        end
    endtask

    // After each phase: the frame so far and every property, then the counts restart.
    task phase_end(input [8*32-1:0] phase);
        integer k, bad, f0;
        begin
            f0 = failed;
            bad = 0;
            for (k = 0; k < SIDE * SIDE; k = k + 1)
                if (ram[k] !== refm[k]) begin
                    if (bad < 3) $display("  pixel (%0d, %0d): %h, want %h", k % SIDE, k / SIDE,
                                          ram[k], refm[k]);
                    bad = bad + 1;
                end
            check(bad == 0 && nwr == nexp, "the memory holds the reference frame");
            check(e_stream == 0, "writes: the in-frame fragments in order");
            check(e_written == 0, "frag_written with counted writes only");
            check(e_hold == 0, "a request waiting on mem_wait is held");
            check(e_both == 0 && e_pending == 0, "no write and read together, write_pending");
            check(e_ack == 0, "a read is acked first whenever it can be");
            check(e_pop == 0, "a fragment popped whenever the port can take it");
            check(e_port == 0, "a popped fragment on the port the next cycle");
            check(e_read == 0 && e_valid == 0, "read at its address, byte the cycle after");
            if (e_stream + e_written + e_hold + e_both + e_pending + e_ack + e_pop + e_port
                + e_read + e_valid != 0)
                $display("  errors: stream %0d written %0d hold %0d both %0d pending %0d ack %0d pop %0d port %0d read %0d valid %0d",
                         e_stream, e_written, e_hold, e_both, e_pending, e_ack, e_pop,
                         e_port, e_read, e_valid);
            if (failed != f0) $display("  (phase: %0s)", phase);
            e_stream = 0; e_written = 0; e_hold = 0; e_both = 0; e_pending = 0; e_ack = 0;
            e_pop = 0; e_port = 0; e_read = 0; e_valid = 0;
        end
    endtask

    integer k, t0, t1, r0;
    initial begin
        for (k = 0; k < SIDE * SIDE; k = k + 1) begin
            ram[k] = $random;
            refm[k] = ram[k];
        end
        repeat (3) @(posedge clk);
        @(negedge clk);
        rst = 1'b0;
        @(negedge clk);

        // A burst without mem_wait or reads: one fragment retired per cycle.
        wm1 = SIDE - 1; hm1 = SIDE - 1;
        for (k = 0; k < 200; k = k + 1)
            push($unsigned($random) % SIDE, $unsigned($random) % SIDE, $random, 1'b1);
        t0 = cyc;
        while (nwr < nexp && cyc - t0 < 1000) @(negedge clk);
        t1 = cyc;
        check(nwr == 200 && t1 - t0 <= 201, "a write per cycle without mem_wait");
        if (nwr != 200 || t1 - t0 > 201) $display("  %0d writes took %0d cycles", nwr, t1 - t0);
        drain;
        phase_end("burst");

        // A small frame: clipping at its edges, reads, mem_wait.
        wm1 = 9'd63; hm1 = 9'd47;
        wait_pct = 30; read_pct = 5;
        burst(3000, 80, 60);
        drain;
        phase_end("64 x 48, 30 % mem_wait");
        // Heavy stalls and many reads in a thin frame.
        wm1 = 9'd99; hm1 = 9'd6;
        wait_pct = 70; read_pct = 25;
        burst(2000, 120, 12);
        drain;
        phase_end("100 x 7, 70 % mem_wait");
        // The full frame, reads only.
        wm1 = SIDE - 1; hm1 = SIDE - 1;
        wait_pct = 10; read_pct = 50;
        burst(2000, SIDE, SIDE);
        drain;
        phase_end("full frame, reads");
        // Reads alone, mem_wait toggling: each one read, each read's byte.
        r0 = reads;
        wait_pct = 50; read_pct = 100;
        repeat (400) @(negedge clk);
        drain;
        check(reads - r0 > 50, "reads without fragments");
        phase_end("reads alone");

        check(reads > 200, "reads interleaved with the fragments");
        $display("tb_fb_writer: %0d writes, %0d reads checked", nwr, reads);

        $display("tb_fb_writer: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_fb_writer failed");
        $finish;
    end
endmodule
`default_nettype wire
