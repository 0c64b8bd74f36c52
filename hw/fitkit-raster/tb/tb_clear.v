// tb_clear -- clear_unit against its contract: the W x H rectangle, in raster order.
//
// The reference is the testbench's own walk of the rectangle (x fastest, from (0, 0) to
// (W - 1, H - 1)). Checks per clear: the first fragment is offered the cycle after start;
// every handed-over fragment is the walk's next pixel with the latched colour, each
// pixel once and none outside the rectangle; done comes once, with the last fragment's
// hand-over; busy lasts exactly W * H cycles plus the cycles frag_ready was low; the unit
// is idle afterwards. Cases: 1 x 1, single rows and columns, the full 512 x 512 frame
// and its 512 x 1 / 1 x 512 edges, random rectangles with and without random
// frag_ready, inputs changed and start pulsed while busy (both ignored), and a reset in
// the middle of a clear. Prints "N passed, M failed".
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_clear;
    localparam integer SIDE = `FITKIT_FRAME_SIDE;   // the largest rectangle

    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;

    reg        start = 1'b0;
    reg [8:0]  wm1 = 9'd0, hm1 = 9'd0;
    reg [7:0]  color = 8'd0;
    reg        ready = 1'b1;
    wire       busy, fv, done;
    wire [8:0] fx, fy;
    wire [7:0] fc;

    clear_unit dut (
        .clk(clk), .rst(rst), .start(start), .wm1(wm1), .hm1(hm1), .color(color),
        .busy(busy), .frag_valid(fv), .frag_x(fx), .frag_y(fy), .frag_col(fc),
        .frag_ready(ready), .done(done)
    );

    `include "check.vh"

    // A broken unit must fail the run, not hang it: the summary counts the timeout.
    initial begin
        repeat (2000000) @(posedge clk);
        $display("tb_clear: no end after 2000000 cycles");
        $display("tb_clear: %0d passed, %0d failed", passed, failed + 1);
        $fatal(1, "tb_clear timed out");
    end

    // One clear of w x h in colour c. stall: percent of cycles frag_ready is low;
    // disturb: change the inputs and pulse start while the clear runs.
    task run(input integer w, input integer h, input integer c, input integer stall,
             input integer disturb);
        integer ex, ey, cycles, stalls, bad, got, dones, first, quiet, k;
        begin
            @(negedge clk);
            wm1 = w - 1; hm1 = h - 1; color = c;
            start = 1'b1;
            @(negedge clk);
            start = 1'b0;
            #1;
            first = busy && fv && fx == 0 && fy == 0 && fc == c[7:0];
            ex = 0; ey = 0; cycles = 0; stalls = 0; bad = 0; got = 0; dones = 0;
            while (busy) begin
                if (disturb && cycles == 1) begin
                    wm1 = $random; hm1 = $random; color = $random;
                    start = 1'b1;
                end else start = 1'b0;
                ready = ($unsigned($random) % 100) >= stall;
                #1;
                cycles = cycles + 1;
                if (!fv) bad = bad + 1;                  // offered every busy cycle
                if (!ready) stalls = stalls + 1;
                if (ready) begin
                    if (ey >= h || fx != ex || fy != ey || fc != c[7:0]) begin
                        if (bad < 3 && ey >= h)
                            $display("  clear %0dx%0d: got (%0d, %0d) past the last pixel",
                                     w, h, fx, fy);
                        else if (bad < 3)
                            $display("  clear %0dx%0d: got (%0d, %0d) col %h, want (%0d, %0d) col %h",
                                     w, h, fx, fy, fc, ex, ey, c[7:0]);
                        bad = bad + 1;
                    end
                    if (done != (ex == w - 1 && ey == h - 1)) bad = bad + 1;
                    got = got + 1;
                    ex = ex + 1;
                    if (ex == w) begin
                        ex = 0;
                        ey = ey + 1;
                    end
                end else if (done) bad = bad + 1;    // done only with a hand-over
                if (done) dones = dones + 1;
                @(negedge clk);
            end
            start = 1'b0;
            ready = 1'b1;
            // Nothing more comes, whatever the inputs do.
            quiet = 1;
            for (k = 0; k < 4; k = k + 1) begin
                wm1 = $random; hm1 = $random; color = $random;
                #1;
                if (busy || fv || done) quiet = 0;
                @(negedge clk);
            end
            check(first, "first fragment the cycle after start");
            check(bad == 0 && got == w * h, "the rectangle in raster order, colour");
            check(dones == 1, "done once, with the last fragment");
            check(cycles - stalls == w * h, "busy W * H cycles plus stalls");
            check(quiet, "idle after the clear");
            if (got != w * h || dones != 1 || cycles - stalls != w * h)
                $display("  clear %0dx%0d: %0d fragments, %0d done, %0d cycles (%0d stalled)",
                         w, h, got, dones, cycles, stalls);
        end
    endtask

    integer i, k, ok;
    initial begin
        repeat (3) @(posedge clk);
        rst = 1'b0;

        run(1, 1, 8'h5A, 0, 0);
        run(1, 7, 8'h01, 0, 0);
        run(9, 1, 8'h02, 0, 0);
        run(3, 5, 8'h03, 0, 0);
        run(40, 30, 8'h12, 0, 1);
        run(40, 30, 8'hE3, 40, 1);
        run(1, 1, 8'hFF, 60, 0);
        run(SIDE, 1, 8'h81, 0, 0);
        run(1, SIDE, 8'h18, 25, 0);
        run(SIDE, SIDE, 8'hA5, 0, 0);
        for (i = 0; i < 30; i = i + 1)
            run(1 + $unsigned($random) % 48, 1 + $unsigned($random) % 48, $random,
                (i % 3) * 30, i % 2);

        // A reset in the middle of a clear stops it; the next clear starts from (0, 0).
        @(negedge clk);
        wm1 = 9'd19; hm1 = 9'd19; color = 8'h77;
        start = 1'b1;
        @(negedge clk);
        start = 1'b0;
        repeat (50) @(negedge clk);
        rst = 1'b1;
        @(negedge clk);
        rst = 1'b0;
        ok = 1;
        for (k = 0; k < 3; k = k + 1) begin
            #1;
            if (busy || fv || done) ok = 0;
            @(negedge clk);
        end
        check(ok, "reset stops a clear");
        run(6, 4, 8'h3C, 10, 0);

        $display("tb_clear: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_clear failed");
        $finish;
    end
endmodule
`default_nettype wire
