// tb_line -- line_unit against a closed-form Bresenham reference.
//
// The reference does not step a decision variable: the canonical walk (from the end
// point with the smaller major coordinate) puts pixel k at minor offset
// floor((2k dn + dm) / 2dm), which is what p1 = 2dn - dm with "p >= 0 steps" gives. Checks
// per line: the unit emits exactly the reference's pixel set, each pixel once; busy lasts
// 3 set-up cycles + max(|dx|, |dy|) + 1 plus the cycles a fragment waited on frag_ready (toggled at
// random); done comes once. Cases: all octants and the diagonals, reversed end points,
// zero length, the frame's corners, random lines. Prints "N passed, M failed".
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_line;
    localparam integer SIDE = `FITKIT_FRAME_SIDE;   // the frame the coordinates address
    localparam integer SETUP = 3;                    // line_unit's set-up cycles
    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;

    reg        start = 1'b0;
    reg [8:0]  x0, y0, x1, y1;
    reg [7:0]  color;
    reg        ready = 1'b1;
    wire       busy, fv, done;
    wire [8:0] fx, fy;
    wire [7:0] fc;

    line_unit dut (
        .clk(clk), .rst(rst), .start(start), .x0(x0), .y0(y0), .x1(x1), .y1(y1),
        .color(color), .busy(busy), .frag_valid(fv), .frag_x(fx), .frag_y(fy), .frag_col(fc),
        .frag_ready(ready), .done(done)
    );

    `include "check.vh"
    reg [1:0] mark [0:SIDE * SIDE - 1];   // 1 expected, 2 expected and seen
    integer   list [0:1023];
    integer   nref;
    integer   random_ready = 0;

    task run(input integer ax, input integer ay, input integer bx, input integer by);
        integer dx, dy, xmaj, sw, sx, sy, ex, ey, dm, dn, sn, k, nk, px, py, a;
        integer cycles, stalls, bad, got, dones;
        begin
            // Reference.
            dx = bx > ax ? bx - ax : ax - bx;
            dy = by > ay ? by - ay : ay - by;
            xmaj = dx >= dy;
            sw = xmaj ? (bx < ax) : (by < ay);
            sx = sw ? bx : ax; sy = sw ? by : ay;
            ex = sw ? ax : bx; ey = sw ? ay : by;
            dm = xmaj ? ex - sx : ey - sy;
            dn = xmaj ? dy : dx;
            sn = xmaj ? (ey >= sy ? 1 : -1) : (ex >= sx ? 1 : -1);
            nref = dm + 1;
            for (k = 0; k <= dm; k = k + 1) begin
                nk = dm == 0 ? 0 : (2 * k * dn + dm) / (2 * dm);
                px = xmaj ? sx + k : sx + sn * nk;
                py = xmaj ? sy + sn * nk : sy + k;
                list[k] = py * SIDE + px;
                mark[py * SIDE + px] = 2'd1;
            end
            // The unit.
            @(negedge clk);
            x0 = ax; y0 = ay; x1 = bx; y1 = by; color = ax[7:0] ^ by[7:0];
            start = 1'b1;
            @(negedge clk);
            start = 1'b0;
            cycles = 0; stalls = 0; bad = 0; got = 0; dones = 0;
            while (busy) begin
                if (random_ready) ready = $random;
                #1;
                cycles = cycles + 1;
                if (fv && !ready) stalls = stalls + 1;
                if (fv && ready) begin
                    a = fy * SIDE + fx;
                    if (mark[a] != 2'd1 || fc != color) bad = bad + 1;
                    else mark[a] = 2'd2;
                    got = got + 1;
                end
                if (done) dones = dones + 1;
                @(negedge clk);
            end
            ready = 1'b1;
            for (k = 0; k < nref; k = k + 1) begin
                if (mark[list[k]] != 2'd2) bad = bad + 1;
                mark[list[k]] = 2'd0;
            end
            if (bad == 0 && got == nref && dones == 1 && cycles - stalls == SETUP + dm + 1)
                passed = passed + 1;
            else begin
                failed = failed + 1;
                $display("FAIL line (%0d,%0d)-(%0d,%0d): %0d bad, %0d/%0d pixels, %0d cycles (%0d stalled, want %0d), %0d done",
                         ax, ay, bx, by, bad, got, nref, cycles, stalls, SETUP + dm + 1, dones);
            end
        end
    endtask

    integer i, k;
    integer cx, cy;
    initial begin
        for (k = 0; k < SIDE * SIDE; k = k + 1) mark[k] = 2'd0;
        repeat (3) @(posedge clk);
        rst = 1'b0;
        // Octants around (100, 100), both directions, and the axes / diagonals.
        cx = 100; cy = 100;
        for (i = 0; i < 16; i = i + 1) begin
            run(cx, cy, cx + (i[0] ? 37 : 12) * (i[1] ? -1 : 1) * (i[2] ? 1 : 0) + (i[2] ? 0 : (i[1] ? -30 : 30)),
                cy + (i[3] ? 25 : -25));
        end
        run(100, 100, 140, 100); run(140, 100, 100, 100);
        run(100, 100, 100, 140); run(100, 140, 100, 100);
        run(100, 100, 140, 140); run(140, 140, 100, 100);
        run(100, 100, 60, 140);  run(60, 140, 100, 100);
        run(100, 100, 141, 120); run(141, 120, 100, 100);   // ties at p = 0
        run(100, 100, 110, 105); run(110, 105, 100, 100);
        run(7, 7, 7, 7);
        // The frame's corners (coordinates 0 and SIDE - 1).
        run(0, 0, SIDE - 1, SIDE - 1); run(SIDE - 1, 0, 0, SIDE - 1);
        run(0, SIDE - 1, SIDE - 1, SIDE - 2); run(SIDE - 1, SIDE - 1, 0, 0);
        run(0, 0, SIDE - 1, 1); run(3, SIDE - 1, 0, 0);
        for (i = 0; i < 400; i = i + 1) begin
            random_ready = i >= 200;
            run($unsigned($random) % SIDE, $unsigned($random) % SIDE,
                $unsigned($random) % SIDE, $unsigned($random) % SIDE);
        end
        for (i = 0; i < 200; i = i + 1) begin
            cx = $unsigned($random) % 500;
            cy = $unsigned($random) % 500;
            run(cx, cy, cx + $unsigned($random) % 12, cy + $unsigned($random) % 12);
        end
        $display("tb_line: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_line failed");
        $finish;
    end
endmodule
`default_nettype wire
