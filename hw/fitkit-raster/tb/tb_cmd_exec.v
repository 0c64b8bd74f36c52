// tb_cmd_exec -- cmd_exec between a packet FIFO and three unit models, cycle by cycle.
//
// The testbench plays the input FIFO (show-ahead, a packet's records pushed together, so
// the FIFO is primed as fifo36 is once a packet is committed), the clear, line and
// triangle units (each answers its start with a done strobe a random 1..40 cycles
// later) and the pipeline's pipe_idle (random, and held low for a while when a set-up
// waits on it). Every cycle's strobes and outputs are logged; the log is then walked
// packet by packet against the sequence cmd_exec's header promises, with these cycle
// offsets from the cycle a packet's first record is popped (p):
//   clear              clr_start at p + 2 with the packet's colour;
//   line / triangle    second record popped at p + 1; the unit's start at p + 4 with
//                      packet bits 70..9; with CB, first clr_start at p + 3 with the
//                      background, then the unit's start 2 cycles after clr_done;
//   set-up             waits for pipe_idle from p + 2: cnt_clr 1 cycle after the first
//                      such cycle q, width - 1 / height - 1 / cull latched from then,
//                      clr_start with the background at q + 2;
//   every packet       done (pkt_done and any_done; any_done alone for a set-up) the
//                      cycle after its last unit's done strobe (two cycles after a line's
//                      or triangle's, which cmd_exec registers); busy from p + 1 to then;
//                      no other start, cnt_clr or done strobe in between; the next
//                      packet popped in that same cycle when it is already queued;
//                      setup_done rises with a set-up's done and stays until rst.
// Before the first set-up (and after rst) the frame is 512 x 512, background 0, no
// culling. Cases: every channel, CB on and off, set-ups with different frames,
// backgrounds and culling, packets queued back to back and one at a time, rst in the
// middle of a packet. Prints "N passed, M failed".
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_cmd_exec;
    localparam integer SIDE = `FITKIT_FRAME_SIDE;
    localparam [7:0]   A_SETUP = `FITKIT_ADDR_SETUP, A_LINE = `FITKIT_ADDR_LINE,
                       A_TRI = `FITKIT_ADDR_TRIANGLE, A_CLEAR = `FITKIT_ADDR_CLEAR;
    localparam integer MAXC = 200000;   // cycles logged
    localparam integer MAXP = 2000;     // packets

    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;

    // Input FIFO: 38-bit records {tag, record}, show-ahead. The head is a register of its
    // own (not a continuous read of the array, which Verilator does not re-evaluate when
    // an element is written).
    reg  [37:0] fq [0:4095];
    integer     qhead = 0, qtail = 0;
    reg  [37:0] data_out = 38'd0;
    wire        data_vld = qhead != qtail;
    wire        fifo_next;
    always @(posedge clk) if (fifo_next && data_vld) begin
        qhead    <= qhead + 1;
        data_out <= fq[(qhead + 1) % 4096];
    end

    reg         pipe_idle = 1'b1;
    reg         clr_done = 1'b0, line_done = 1'b0, tri_done = 1'b0;
    wire [8:0]  wm1, hm1;
    wire [1:0]  cull;
    wire [7:0]  clr_color;
    wire [70:9] packet;
    wire        setup_done, cnt_clr, clr_start, line_start, tri_start, pkt_done, any_done;
    wire        busy;

    cmd_exec dut (
        .clk(clk), .rst(rst), .DATA_OUT(data_out), .DATA_VLD(data_vld),
        .FIFO_NEXT(fifo_next), .pipe_idle(pipe_idle), .wm1(wm1), .hm1(hm1), .cull(cull),
        .setup_done(setup_done), .cnt_clr(cnt_clr), .clr_start(clr_start),
        .clr_color(clr_color), .clr_done(clr_done), .line_start(line_start),
        .line_done(line_done), .tri_start(tri_start), .tri_done(tri_done), .packet(packet),
        .pkt_done(pkt_done), .any_done(any_done), .busy(busy)
    );

    `include "check.vh"

    // A broken unit must fail the run, not hang it: the summary counts the timeout.
    initial begin
        repeat (180000) @(posedge clk);
        $display("tb_cmd_exec: no end after 180000 cycles");
        $display("tb_cmd_exec: %0d passed, %0d failed", passed, failed + 1);
        $fatal(1, "tb_cmd_exec timed out");
    end

    // ---- The log: one entry per cycle, sampled before the clock edge ending it ---------
    integer    cyc = 0;
    reg        l_pop [0:MAXC-1];
    reg        l_vld [0:MAXC-1];
    reg        l_idle [0:MAXC-1];
    reg        l_cntclr [0:MAXC-1];
    reg        l_cs [0:MAXC-1];   // clr_start
    reg        l_ls [0:MAXC-1];
    reg        l_ts [0:MAXC-1];
    reg        l_cd [0:MAXC-1];   // clr_done
    reg        l_ld [0:MAXC-1];
    reg        l_td [0:MAXC-1];
    reg        l_pd [0:MAXC-1];   // pkt_done
    reg        l_ad [0:MAXC-1];   // any_done
    reg        l_busy [0:MAXC-1];
    reg        l_sd [0:MAXC-1];   // setup_done
    reg [7:0]  l_col [0:MAXC-1];
    reg [61:0] l_pkt [0:MAXC-1];
    reg [19:0] l_frame [0:MAXC-1];   // {cull, hm1, wm1}
    integer    e_pop_empty = 0;

    // The unit models: done a random 1..40 cycles after start.
    integer cd_at = -1, ld_at = -1, td_at = -1;
    integer idle_low = 0;   // cycles pipe_idle stays low from now

    always @(negedge clk) if (!rst) begin
        clr_done = cyc == cd_at;
        line_done = cyc == ld_at;
        tri_done = cyc == td_at;
        if (idle_low > 0) begin
            pipe_idle = 1'b0;
            idle_low = idle_low - 1;
        end else pipe_idle = ($unsigned($random) % 4) != 0;
        #1;
        if (fifo_next && !data_vld) e_pop_empty = e_pop_empty + 1;
        if (clr_start) cd_at = cyc + 1 + $unsigned($random) % 40;
        if (line_start) ld_at = cyc + 1 + $unsigned($random) % 40;
        if (tri_start) td_at = cyc + 1 + $unsigned($random) % 40;
        if (cyc < MAXC) begin
            l_pop[cyc] = fifo_next && data_vld;
            l_vld[cyc] = data_vld;
            l_idle[cyc] = pipe_idle;
            l_cntclr[cyc] = cnt_clr;
            l_cs[cyc] = clr_start;
            l_ls[cyc] = line_start;
            l_ts[cyc] = tri_start;
            l_cd[cyc] = clr_done;
            l_ld[cyc] = line_done;
            l_td[cyc] = tri_done;
            l_pd[cyc] = pkt_done;
            l_ad[cyc] = any_done;
            l_busy[cyc] = busy;
            l_sd[cyc] = setup_done;
            l_col[cyc] = clr_color;
            l_pkt[cyc] = packet;
            l_frame[cyc] = {cull, hm1, wm1};
        end
    end
    always @(posedge clk) cyc <= cyc + 1;

    // ---- Packets -----------------------------------------------------------------------
    // What was queued, in order: kind (0 set-up, 1 line, 2 triangle, 3 clear), CB, the
    // 72 packet bits, the set-up's fields; and the first cycle after which it may start
    // (the first log cycle of its segment).
    integer    pk_kind [0:MAXP-1];
    reg        pk_cb [0:MAXP-1];
    reg [71:0] pk_bits [0:MAXP-1];
    integer    npk = 0;

    task push_rec(input [7:0] addr, input [35:0] r);
        begin
            fq[qtail % 4096] = {addr[1:0], r};
            if (qhead == qtail) data_out = fq[qtail % 4096];
            qtail = qtail + 1;
        end
    endtask

    task setup(input integer w, input integer h, input integer bg, input integer cl);
        reg [35:0] r;
        begin
            r = {w[8:0] - 9'd1, h[8:0] - 9'd1, bg[7:0], cl[1:0], 8'd0};
            pk_kind[npk] = 0; pk_cb[npk] = 1'b0; pk_bits[npk] = {r, 36'd0};
            npk = npk + 1;
            push_rec(A_SETUP, r);
        end
    endtask

    // A line (kind 1) or triangle (kind 2): random fields and padding, CB as given.
    task draw(input integer kind, input cb);
        reg [71:0] b;
        begin
            b = {$random, $random, $random};
            b[71] = cb;
            pk_kind[npk] = kind; pk_cb[npk] = cb; pk_bits[npk] = b;
            npk = npk + 1;
            push_rec(kind == 1 ? A_LINE : A_TRI, b[71:36]);
            push_rec(kind == 1 ? A_LINE : A_TRI, b[35:0]);
        end
    endtask

    task clear(input integer c);
        reg [35:0] r;
        begin
            r = {1'b1, c[7:0], 27'd0};
            pk_kind[npk] = 3; pk_cb[npk] = 1'b1; pk_bits[npk] = {r, 36'd0};
            npk = npk + 1;
            push_rec(A_CLEAR, r);
        end
    endtask

    // Queue n random packets; queued: all at once, else each after the last one ended.
    task random_packets(input integer n, input queued);
        integer k, t;
        begin
            for (k = 0; k < n; k = k + 1) begin
                t = $unsigned($random) % 16;
                if (t == 0) setup(1 + $unsigned($random) % SIDE, 1 + $unsigned($random) % SIDE,
                                  $random, $unsigned($random) % 4);
                else if (t < 6) draw(1, t == 1);
                else if (t < 14) draw(2, t == 6);
                else clear($random);
                if (!queued) wait_idle;
            end
        end
    endtask

    task wait_idle;
        integer quiet;
        begin
            quiet = 0;
            while (quiet < 3) begin
                @(negedge clk);
                #2;
                quiet = (!busy && !data_vld) ? quiet + 1 : 0;
            end
            @(negedge clk);   // callers push next: before this cycle is sampled
        end
    endtask

    // ---- The walk ----------------------------------------------------------------------
    integer e_seq = 0;
    task fail(input integer i, input integer c, input [8*40-1:0] what);
        begin
            if (e_seq < 5) $display("  packet %0d (kind %0d, CB %0d), cycle %0d: %0s", i,
                                    pk_kind[i], pk_cb[i], c, what);
            e_seq = e_seq + 1;
        end
    endtask

    // First cycle >= c with the flag of `which` set in the log, or -1 before `lim`.
    function integer find(input integer which, input integer c, input integer lim);
        integer k;
        begin
            find = -1;
            for (k = c; k < lim && find < 0; k = k + 1)
                case (which)
                    0: if (l_pop[k]) find = k;
                    1: if (l_cd[k]) find = k;
                    2: if (l_ld[k]) find = k;
                    3: if (l_td[k]) find = k;
                    4: if (l_idle[k]) find = k;
                    default: ;
                endcase
        end
    endfunction

    // Counts a strobe over [a, b].
    function integer count(input integer which, input integer a, input integer b);
        integer k;
        begin
            count = 0;
            for (k = a; k <= b; k = k + 1)
                case (which)
                    0: count = count + l_cs[k];
                    1: count = count + l_ls[k];
                    2: count = count + l_ts[k];
                    3: count = count + l_cntclr[k];
                    4: count = count + l_pd[k];
                    5: count = count + l_ad[k];
                    6: count = count + l_pop[k];
                    default: ;
                endcase
        end
    endfunction

    // Walks packets [first, last) from cycle c0 to cycle lim; the frame state before them
    // is {cull, hm1, wm1} = frame, background bg, setup_done sd.
    task walk(input integer first, input integer last, input integer c0, input integer lim,
              input [19:0] frame0, input [7:0] bg0, input sd0);
        integer i, c, p, q, d, d1, s, e, ncs, nls, nts, ncc, npops, e0;
        reg [19:0] frame;
        reg [7:0]  bg;
        reg        sd;
        begin
            c = c0; frame = frame0; bg = bg0; sd = sd0;
            for (i = first; i < last; i = i + 1) begin
                e0 = e_seq;
                e = -1;
                p = find(0, c, lim);
                if (p < 0) fail(i, c, "never popped");
                else begin
                    if (p != c && l_vld[c] && !l_busy[c]) fail(i, c, "queued but not popped at once");
                    // (c is the last packet's done cycle, checked with it.)
                    if (count(0, c + 1, p) + count(1, c + 1, p) + count(2, c + 1, p)
                        + count(3, c + 1, p) + count(4, c + 1, p) + count(5, c + 1, p) != 0)
                        fail(i, p, "strobes while idle");
                    if (l_busy[p]) fail(i, p, "busy when popped");
                    ncs = 0; nls = 0; nts = 0; ncc = 0; npops = 1;
                    case (pk_kind[i])
                        0: begin
                            q = find(4, p + 2, lim);
                            if (q < 0) fail(i, p, "pipe never idle");
                            else begin
                                if (!l_cntclr[q + 1]) fail(i, q + 1, "no cnt_clr after pipe_idle");
                                if (l_frame[q] != frame) fail(i, q, "frame changed before cnt_clr");
                                frame = {pk_bits[i][45:44], pk_bits[i][62:54], pk_bits[i][71:63]};
                                bg = pk_bits[i][53:46];
                                if (l_frame[q + 1] != frame) fail(i, q + 1, "frame not latched");
                                if (!l_cs[q + 2] || l_col[q + 2] != bg)
                                    fail(i, q + 2, "no set-up clear with the background");
                                d = find(1, q + 3, lim);
                                e = d + 1;
                                if (d < 0 || !l_ad[e] || l_pd[e]) fail(i, d, "set-up done");
                                if (d >= 0 && (l_sd[d] != sd || !l_sd[e])) fail(i, e, "setup_done");
                                sd = 1'b1;
                                ncs = 1; ncc = 1;
                            end
                        end
                        3: begin
                            if (!l_cs[p + 2] || l_col[p + 2] != pk_bits[i][70:63])
                                fail(i, p + 2, "no clear start with its colour");
                            d = find(1, p + 3, lim);
                            e = d + 1;
                            if (d < 0 || !l_ad[e] || !l_pd[e]) fail(i, d, "clear done");
                            ncs = 1;
                        end
                        default: begin
                            if (!l_pop[p + 1]) fail(i, p + 1, "second record not popped at once");
                            npops = 2;
                            s = p + 4;
                            if (pk_cb[i]) begin
                                if (!l_cs[p + 3] || l_col[p + 3] != bg)
                                    fail(i, p + 3, "no CB clear with the background");
                                d1 = find(1, p + 4, lim);
                                s = d1 + 2;
                                ncs = 1;
                            end
                            if (pk_kind[i] == 1 ? !l_ls[s] : !l_ts[s]) fail(i, s, "unit not started");
                            if (l_pkt[s] != pk_bits[i][70:9]) fail(i, s, "packet bits");
                            d = find(pk_kind[i] == 1 ? 2 : 3, s + 1, lim);
                            e = d + 2;
                            if (d < 0 || !l_ad[e] || !l_pd[e]) fail(i, d, "draw done");
                            if (pk_kind[i] == 1) nls = 1; else nts = 1;
                        end
                    endcase
                    if (e > 0) begin
                        // Exactly the strobes above, busy throughout, idle at the end.
                        if (count(0, p, e) != ncs || count(1, p, e) != nls
                            || count(2, p, e) != nts || count(3, p, e) != ncc
                            || count(4, p + 1, e - 1) != 0 || count(5, p + 1, e - 1) != 0
                            || count(6, p, e - 1) != npops)
                            fail(i, e, "extra strobes");
                        for (d = p + 1; d < e; d = d + 1)
                            if (!l_busy[d]) begin
                                fail(i, d, "not busy while executing");
                                d = e;
                            end
                        if (l_busy[e]) fail(i, e, "busy after done");
                        c = e;
                    end
                end
                case (pk_kind[i])
                    0: check(e_seq == e0, "set-up: drain, latch, cnt_clr, clear, done");
                    3: check(e_seq == e0, "clear packet: colour, timing, done");
                    default: check(e_seq == e0, "draw: records, CB clear, start, done");
                endcase
                if (e < 0) i = last;
            end
        end
    endtask

    integer c0, i, k, before_rst, ok, e0;
    initial begin
        repeat (3) @(posedge clk);
        @(negedge clk);
        rst = 1'b0;
        @(negedge clk);
        c0 = cyc;

        // Before any set-up: 512 x 512, background 0, no culling.
        draw(1, 1'b1);
        draw(2, 1'b0);
        clear(8'h5A);
        wait_idle;
        setup(40, 30, 8'h12, 1);
        draw(2, 1'b1);
        wait_idle;
        // The set-up waits for the pipeline: pipe_idle held low after it is reached.
        draw(1, 1'b0);
        setup(64, 48, 8'hC3, 2);
        idle_low = 60;
        clear(8'h0F);
        draw(1, 1'b1);
        wait_idle;
        // Packets one at a time, then back to back.
        random_packets(40, 0);
        random_packets(300, 1);
        wait_idle;
        random_packets(200, 1);
        wait_idle;

        walk(0, npk, c0, cyc, {2'd0, 9'd511, 9'd511}, 8'd0, 1'b0);
        check(e_pop_empty == 0, "FIFO_NEXT only with a record");
        $display("tb_cmd_exec: %0d packets walked over %0d cycles", npk, cyc - c0);

        // A reset in the middle of a packet: idle, defaults, setup_done low.
        setup(100, 80, 8'h44, 3);
        draw(2, 1'b1);
        repeat (30) @(negedge clk);
        before_rst = setup_done;
        rst = 1'b1;
        qhead = qtail;      // the FIFO and the units are reset with the block
        cd_at = -1; ld_at = -1; td_at = -1;
        @(negedge clk);
        rst = 1'b0;
        #1;
        check(before_rst && !busy && !setup_done && wm1 == SIDE - 1 && hm1 == SIDE - 1
              && cull == 2'd0, "rst: idle, 512 x 512, set-up not done");
        ok = 1;
        for (k = 0; k < 10; k = k + 1) begin
            @(negedge clk);
            #1;
            if (busy || clr_start || line_start || tri_start || pkt_done || any_done) ok = 0;
        end
        check(ok, "rst: nothing runs on");
        // After the reset: a CB draw clears with background 0 again.
        @(negedge clk);
        c0 = cyc;
        i = npk;
        draw(1, 1'b1);
        clear(8'h21);
        wait_idle;
        e0 = e_seq;
        walk(i, npk, c0, cyc, {2'd0, 9'd511, 9'd511}, 8'd0, 1'b0);
        check(e_seq == e0, "after rst: the power-on frame and background");

        $display("tb_cmd_exec: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_cmd_exec failed");
        $finish;
    end
endmodule
`default_nettype wire
