// tb_fifo -- fifo36 against a queue model, and frag_fifo's order and full flag.
//
// fifo36: random packets of 1 or 2 records are written, then committed or discarded
// (about one in four discarded); the reader pops at random. Checks: records come out in
// order, tags and data intact, discarded records never appear, DATA_VLD only with
// committed data, room / free_count / occupancy / FIFO_FREE equal the model's counts
// (capacity exactly 512, the output register included), nothing lost at full.
// frag_fifo: 16 entries fit, the 17th waits, order kept. Prints "N passed, M failed".
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_fifo;
    localparam integer DEPTH  = `FITKIT_FIFO_RECORDS;
    // FIFO_FREE promises room for the widest packet.
    localparam integer PACKET = (`FITKIT_MAX_PACKET_BYTES * 8) / `FITKIT_RECORD_BITS;
    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;

    reg  [37:0] din = 38'd0;
    reg         we = 1'b0, commit = 1'b0, discard = 1'b0, next = 1'b0;
    wire [37:0] dout;
    wire        vld, ffree, room;
    wire [9:0]  free_count, occ;

    fifo36 dut (
        .clk(clk), .rst(rst), .DATA_IN(din), .DATA_WE(we), .COMMIT(commit),
        .DISCARD(discard), .FIFO_NEXT(next), .DATA_OUT(dout), .DATA_VLD(vld),
        .FIFO_FREE(ffree), .room(room), .free_count(free_count), .occupancy(occ)
    );

    `include "check.vh"
    integer errors = 0;
    reg [37:0] q [0:4095];
    integer head = 0, tail = 0;     // committed model queue [head, tail)
    integer tent = 0;               // records written since the last commit
    integer popped = 0, pushed = 0, lost = 0;
    integer pop_rate = 50;

    task note(input ok, input [8*40-1:0] what);
        if (!ok) begin
            errors = errors + 1;
            if (errors < 10) $display("FAIL at %0t: %0s", $time, what);
        end
    endtask

    // Reader: checks every popped record against the model.
    always @(posedge clk) if (!rst) begin
        if (next && vld) begin
            if (head >= tail || dout !== q[head % 4096]) note(0, "popped record");
            head <= head + 1;
            popped <= popped + 1;
        end
    end
    always @(negedge clk) next <= ($unsigned($random) % 100) < pop_rate;

    // Writer: one packet at a time.
    task packet(input integer n, input keep);
        integer k;
        reg [37:0] r;
        begin
            for (k = 0; k < n; k = k + 1) begin
                @(negedge clk);
                r = {$random, $random};
                din = r;
                we = 1'b1;
                // The model's tentative count includes the output register.
                if (room) begin
                    q[(tail + tent) % 4096] = r;
                    tent = tent + 1;
                end else lost = lost + 1;
                @(negedge clk);
                we = 1'b0;
            end
            @(negedge clk);
            if (keep) begin
                commit = 1'b1;
                tail = tail + tent;
                pushed = pushed + tent;
            end else discard = 1'b1;
            tent = 0;
            @(negedge clk);
            commit = 1'b0;
            discard = 1'b0;
        end
    endtask

    // Counts against the model, sampled where nothing moves (reader stopped).
    task counts(input [8*40-1:0] what);
        begin
            @(negedge clk);
            pop_rate = 0;
            repeat (3) @(negedge clk);
            note(occ == tail - head && free_count == DEPTH - (tail - head)
                 && ffree == (DEPTH - (tail - head) >= PACKET) && vld == (tail > head), what);
        end
    endtask

    // frag_fifo
    reg  [26:0] fdin = 27'd0;
    reg         fwe = 1'b0, fre = 1'b0;
    wire [26:0] fdout;
    wire        ffull, fempty;
    frag_fifo #(.W(27), .AW(4)) fdut (
        .clk(clk), .rst(rst), .din(fdin), .we(fwe), .full(ffull), .dout(fdout),
        .empty(fempty), .re(fre)
    );

    integer i, k, e0;
    initial begin
        repeat (3) @(posedge clk);
        rst = 1'b0;
        // Random traffic.
        for (i = 0; i < 600; i = i + 1) packet(1 + ($unsigned($random) % 2), ($unsigned($random) % 4) != 0);
        counts("counts after random traffic");
        pop_rate = 100;
        repeat (1100) @(negedge clk);
        counts("drained");
        // Fill without reading: exactly DEPTH records fit; a packet past that is refused.
        pop_rate = 0;
        lost = 0;
        for (i = 0; i < DEPTH / 2; i = i + 1) packet(2, 1);
        note(lost == 0 && !room && !ffree && free_count == 0 && occ == DEPTH, "full at DEPTH");
        e0 = errors;
        packet(2, 0);
        note(lost == 2, "writes refused when full");
        counts("counts at full");
        pop_rate = 100;
        repeat (1100) @(negedge clk);
        counts("drained after full");
        note(popped == pushed, "every committed record popped");
        if (errors == 0) passed = passed + 1; else failed = failed + 1;

        // frag_fifo: 17 writes, one refused while full, order kept.
        e0 = errors;
        for (k = 0; k < 17; k = k + 1) begin
            @(negedge clk);
            fdin = k;
            fwe = 1'b1;
            #1;
            note((k < 16) ? !ffull : ffull, "frag_fifo full flag");
        end
        @(negedge clk);
        fwe = 1'b0;
        for (k = 0; k < 16; k = k + 1) begin
            note(!fempty && fdout == k, "frag_fifo order");
            fre = 1'b1;
            @(negedge clk);
        end
        fre = 1'b0;
        #1;
        note(fempty, "frag_fifo empty after 16");
        if (errors == e0) passed = passed + 1; else failed = failed + 1;

        $display("tb_fifo: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_fifo failed");
        $finish;
    end
endmodule
`default_nettype wire
