// tb_tri -- tri_unit against the golden model's edge functions.
//
// The reference is sim-target raster::tri written out with integers: vertices in
// doubled units, orientation from the area, vertices 1 and 2 swapped for clockwise input,
// edges (1,2), (2,0), (0,1) with a = 2A, b = 2B, c = A(1 - Xp) + B(1 - Yp) - bias (bias 0
// on top-left edges) and pixel (i, j) covered iff a i + b j + c >= 0 for all three -- the
// model's form, not the unit's halved incremental one -- tested at every pixel of the
// vertices' bounding box within the frame. Checks per triangle: the same pixel set, each
// pixel once, colour, busy = 16 + clipped box area (18 + area for tri_small; 13 when
// degenerate, culled or off the frame) plus frag_ready stalls, done once. With LANES > 1 (tri_unit's parameter) the
// set-up is 16 + log2 LANES and a step of LANES pixels costs max(1, covered pixels)
// cycles instead of one per pixel. Cases: both windings,
// horizontal and vertical edges, edges through pixel centres, degenerate (points,
// collinear), culling both ways, triangles hanging off the frame, 512 x 512 frames,
// random triangles, and a jittered
// mesh whose triangles must cover every pixel of its rectangle exactly once (shared
// edges). Prints "N passed, M failed". QUICK = 1 stops after the small scripted cases.
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_tri;
    parameter LANES = 1;           // tri_unit's pixels per cycle (1, 2, 4, 8)
    parameter QUICK = 0;           // 1: the first small cases only (a broken copy's check)
    parameter SMALL = 0;           // 1: tri_small in place of tri_unit (LANES = 1's pixels)
    // the unit's set-up cycles and those of a rejected triangle (tri_unit's and
    // tri_small's Timing)
    localparam integer SETUP  = (SMALL != 0) ? 18
                              : 16 + ((LANES == 8) ? 3 : (LANES == 4) ? 2 : (LANES == 2) ? 1 : 0);
    localparam integer REJECT = 13;
    localparam integer SIDE = `FITKIT_FRAME_SIDE;   // the frame the coordinates address
    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;

    reg        start = 1'b0;
    reg [8:0]  vx0, vy0, vx1, vy1, vx2, vy2, wm1, hm1;
    reg [1:0]  cull = 2'd0;
    reg [7:0]  color;
    reg        ready = 1'b1;
    wire       busy, fv, done;
    wire [8:0] fx, fy;
    wire [7:0] fc;

    generate
        if (SMALL != 0) begin : g_small
            tri_small dut (
                .clk(clk), .rst(rst), .start(start), .x0(vx0), .y0(vy0), .x1(vx1),
                .y1(vy1), .x2(vx2), .y2(vy2), .color(color), .wm1(wm1), .hm1(hm1),
                .cull(cull), .busy(busy), .frag_valid(fv), .frag_x(fx), .frag_y(fy),
                .frag_col(fc), .frag_ready(ready), .done(done)
            );
        end else begin : g_unit
            tri_unit #(.LANES(LANES)) dut (
                .clk(clk), .rst(rst), .start(start), .x0(vx0), .y0(vy0), .x1(vx1),
                .y1(vy1), .x2(vx2), .y2(vy2), .color(color), .wm1(wm1), .hm1(hm1),
                .cull(cull), .busy(busy), .frag_valid(fv), .frag_x(fx), .frag_y(fy),
                .frag_col(fc), .frag_ready(ready), .done(done)
            );
        end
    endgenerate

    `include "check.vh"
    reg [1:0] mark [0:SIDE * SIDE - 1];   // 1 expected, 2 expected and seen
    reg [7:0] hits [0:SIDE * SIDE - 1];   // mesh coverage counts
    integer   list [0:SIDE * SIDE - 1];
    integer   nref;
    integer   random_ready = 0;
    integer   fw = SIDE, fh = SIDE;

    task run(input integer x0, input integer y0, input integer x1, input integer y1,
             input integer x2, input integer y2);
        integer area, cw, px [0:2], py [0:2], a [0:2], b [0:2], c [0:2];
        integer e, f, t, A, B, bias, i, j, minx, maxx, miny, maxy, bw, bh, want, k, adr;
        integer cycles, stalls, bad, got, dones;
        begin
            area = (x2 - x0) * (y1 - y0) - (y2 - y0) * (x1 - x0);
            cw = area < 0;
            minx = x0 < x1 ? (x0 < x2 ? x0 : x2) : (x1 < x2 ? x1 : x2);
            maxx = x0 > x1 ? (x0 > x2 ? x0 : x2) : (x1 > x2 ? x1 : x2);
            miny = y0 < y1 ? (y0 < y2 ? y0 : y2) : (y1 < y2 ? y1 : y2);
            maxy = y0 > y1 ? (y0 > y2 ? y0 : y2) : (y1 > y2 ? y1 : y2);
            if (maxx > fw) maxx = fw;
            if (maxy > fh) maxy = fh;
            bw = maxx - minx; bh = maxy - miny;
            nref = 0;
            if (area == 0 || (cw && cull[0]) || (!cw && cull[1]) || bw <= 0 || bh <= 0)
                want = REJECT;
            else begin
                want = SETUP + bw * bh;
                px[0] = 2 * x0; py[0] = 2 * y0;
                px[1] = cw ? 2 * x2 : 2 * x1; py[1] = cw ? 2 * y2 : 2 * y1;
                px[2] = cw ? 2 * x1 : 2 * x2; py[2] = cw ? 2 * y1 : 2 * y2;
                for (e = 0; e < 3; e = e + 1) begin
                    f = (e + 1) % 3; t = (e + 2) % 3;
                    A = py[t] - py[f];
                    B = -(px[t] - px[f]);
                    bias = (A > 0 || (A == 0 && B > 0)) ? 0 : 1;
                    a[e] = 2 * A; b[e] = 2 * B;
                    c[e] = A * (1 - px[f]) + B * (1 - py[f]) - bias;
                end
                for (j = miny; j < maxy; j = j + 1)
                    for (i = minx; i < maxx; i = i + 1)
                        if (a[0] * i + b[0] * j + c[0] >= 0 && a[1] * i + b[1] * j + c[1] >= 0
                            && a[2] * i + b[2] * j + c[2] >= 0) begin
                            list[nref] = j * SIDE + i;
                            mark[j * SIDE + i] = 2'd1;
                            nref = nref + 1;
                        end
                // LANES pixels per step; a step takes one cycle per covered pixel, at least 1.
                if (LANES > 1) begin
                    want = SETUP;
                    for (j = miny; j < maxy; j = j + 1)
                        for (i = minx; i < maxx; i = i + LANES) begin
                            f = 0;
                            for (t = i; t < i + LANES && t < maxx; t = t + 1)
                                if (mark[j * SIDE + t] == 2'd1) f = f + 1;
                            want = want + (f > 1 ? f : 1);
                        end
                end
            end
            @(negedge clk);
            vx0 = x0; vy0 = y0; vx1 = x1; vy1 = y1; vx2 = x2; vy2 = y2;
            wm1 = fw - 1; hm1 = fh - 1; color = x0[7:0] + y2[7:0];
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
                    adr = fy * SIDE + fx;
                    if (mark[adr] != 2'd1 || fc != color) bad = bad + 1;
                    else mark[adr] = 2'd2;
                    hits[adr] = hits[adr] + 1;
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
            if (bad == 0 && got == nref && dones == 1 && cycles - stalls == want)
                passed = passed + 1;
            else begin
                failed = failed + 1;
                $display("FAIL tri (%0d,%0d) (%0d,%0d) (%0d,%0d) frame %0dx%0d cull %0d: %0d bad, %0d/%0d pixels, %0d cycles (%0d stalled, want %0d), %0d done",
                         x0, y0, x1, y1, x2, y2, fw, fh, cull, bad, got, nref, cycles, stalls,
                         want, dones);
            end
        end
    endtask

    // Both windings of one triangle.
    task both(input integer x0, input integer y0, input integer x1, input integer y1,
              input integer x2, input integer y2);
        begin
            run(x0, y0, x1, y1, x2, y2);
            run(x0, y0, x2, y2, x1, y1);
        end
    endtask

    integer gx [0:8][0:8];
    integer gy [0:8][0:8];
    integer i, j, k, n, ok;
    initial begin
        for (k = 0; k < SIDE * SIDE; k = k + 1) begin
            mark[k] = 2'd0;
            hits[k] = 8'd0;
        end
        repeat (3) @(posedge clk);
        rst = 1'b0;

        both(10, 10, 40, 12, 20, 35);
        both(10, 10, 40, 10, 25, 30);     // horizontal top edge
        both(10, 30, 40, 30, 25, 5);      // horizontal bottom edge
        both(10, 10, 10, 40, 30, 25);     // vertical left edge
        both(30, 10, 30, 40, 5, 25);      // vertical right edge
        both(0, 0, 8, 0, 0, 8);           // edges through pixel centres
        both(1, 1, 9, 5, 3, 9);
        if (QUICK != 0) begin
            $display("tb_tri: %0d passed, %0d failed", passed, failed);
            if (failed != 0) $fatal(1, "tb_tri failed");
            $finish;
        end
        both(0, 0, SIDE - 1, 0, 0, SIDE - 1);
        both(SIDE - 1, SIDE - 1, 0, SIDE - 1, SIDE - 1, 0);
        both(2, 2, 2, 2, 2, 2);           // degenerate: a point
        both(2, 2, 20, 20, 40, 40);       // degenerate: collinear
        both(5, 5, 6, 5, 5, 6);           // tiny
        both(100, 3, 101, 400, 102, 7);   // thin
        fw = 64; fh = 48;
        both(50, 40, 200, 45, 60, 300);   // off the frame right and bottom
        both(70, 10, 90, 20, 80, 30);     // entirely outside
        both(0, 47, 63, 47, 30, 0);
        cull = 2'd1;
        both(10, 10, 40, 12, 20, 35);
        cull = 2'd2;
        both(10, 10, 40, 12, 20, 35);
        cull = 2'd3;
        both(10, 10, 40, 12, 20, 35);
        cull = 2'd0;
        // Random triangles, small frames with clipping and full frames.
        for (i = 0; i < 300; i = i + 1) begin
            random_ready = i >= 150;
            run($unsigned($random) % 90, $unsigned($random) % 70, $unsigned($random) % 90,
                $unsigned($random) % 70, $unsigned($random) % 90, $unsigned($random) % 70);
        end
        fw = SIDE; fh = SIDE;
        for (i = 0; i < 12; i = i + 1)
            run($unsigned($random) % SIDE, $unsigned($random) % SIDE, $unsigned($random) % SIDE,
                $unsigned($random) % SIDE, $unsigned($random) % SIDE, $unsigned($random) % SIDE);
        // Jittered mesh over [8, 72) x [8, 72): interior grid points move by up to 2 (every
        // quad stays convex), the boundary stays.
        fw = 96; fh = 96;
        for (k = 0; k < SIDE * SIDE; k = k + 1) hits[k] = 8'd0;
        for (i = 0; i <= 8; i = i + 1)
            for (j = 0; j <= 8; j = j + 1) begin
                gx[i][j] = 8 + 8 * i + ((i > 0 && i < 8) ? $signed($unsigned($random) % 5) - 2 : 0);
                gy[i][j] = 8 + 8 * j + ((j > 0 && j < 8) ? $signed($unsigned($random) % 5) - 2 : 0);
            end
        for (i = 0; i < 8; i = i + 1)
            for (j = 0; j < 8; j = j + 1) begin
                if ((i + j) % 2 == 0) begin
                    run(gx[i][j], gy[i][j], gx[i+1][j], gy[i+1][j], gx[i+1][j+1], gy[i+1][j+1]);
                    run(gx[i][j], gy[i][j], gx[i][j+1], gy[i][j+1], gx[i+1][j+1], gy[i+1][j+1]);
                end else begin
                    run(gx[i+1][j], gy[i+1][j], gx[i][j], gy[i][j], gx[i][j+1], gy[i][j+1]);
                    run(gx[i+1][j], gy[i+1][j], gx[i+1][j+1], gy[i+1][j+1], gx[i][j+1], gy[i][j+1]);
                end
            end
        ok = 1;
        n = 0;
        for (j = 0; j < 96; j = j + 1)
            for (i = 0; i < 96; i = i + 1) begin
                k = (i >= 8 && i < 72 && j >= 8 && j < 72) ? 1 : 0;
                if (hits[j * SIDE + i] != k) begin
                    ok = 0;
                    if (n < 5) $display("mesh pixel (%0d, %0d) covered %0d times", i, j, hits[j * SIDE + i]);
                    n = n + 1;
                end
            end
        if (ok) passed = passed + 1;
        else failed = failed + 1;
        $display("tb_tri: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_tri failed");
        $finish;
    end
endmodule
`default_nettype wire
