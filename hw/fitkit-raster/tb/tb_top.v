// tb_top -- fitkit_sim_top driven over SPI, frames checked against a reference.
//
// Self-checking mode (default): set-up, lines (the docs/protocol.md test vector among
// them), triangles, clears, CB, read-back, the status block's counters, every error code
// and recovery after it. The reference frame is computed here independently of the RTL:
// lines in closed form (minor offset floor((2k dn + dm) / 2dm) of the canonical walk),
// triangles with the golden model's doubled-unit edge functions tested at every pixel of
// the frame. Prints "N passed, M failed" and ends with $fatal on any failure.
//
// File mode (+tx=FILE [+dump=FILE]): FILE is $readmemh words, one per line:
//   1bb  send byte bb (the first byte after a 200 or the start opens a transaction)
//   200  end the transaction (CS_n high)
//   300  wait until busy is low
//   40v  set mem_wait to v (0 or 1)
//   000  stop
// then the 2^18-byte RAM is written with $writememh to the dump file (default
// rtl-frame.hex).
`default_nettype none
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_top;
    parameter HALF = 50;           // SCK half period: 5 clk cycles (f_SCK = f_clk / 10)
    // the units' set-up cycles (line_unit's and tri_unit's Timing, TRI_LANES = 1)
    localparam integer LINE_SETUP = 3, TRI_SETUP = 16, TRI_REJECT = 13;
    parameter CS_GAP = 4 * HALF; // CS_n high after each transaction
    // Addresses, codes, the status layout and packet lengths are the generated map's, as
    // the host uses them.
    localparam integer SIDE     = `FITKIT_FRAME_SIDE;
    localparam integer ST_BYTES = `FITKIT_STATUS_BYTES;
    localparam integer BYTES1   = (`FITKIT_RECORD_BITS + 7) / 8;   // set-up, clear
    localparam integer BYTES2   = `FITKIT_MAX_PACKET_BYTES;        // line, triangle

    reg clk = 1'b0;
    reg rst = 1'b1;
    reg spi_sck = 1'b0, spi_cs_n = 1'b1, spi_mosi = 1'b0;
    reg mem_wait = 1'b0;
    reg [17:0] bd_addr = 18'd0;
    wire spi_miso, fifo_free, busy;
    wire [7:0] bd_data;

    always #5 clk = ~clk;

    fitkit_sim_top u_top (
        .clk(clk), .rst(rst), .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi),
        .spi_miso(spi_miso), .fifo_free(fifo_free), .busy(busy), .mem_wait(mem_wait),
        .bd_addr(bd_addr), .bd_data(bd_data)
    );

    `include "spi_tasks.vh"

    `include "check.vh"

    // ---- Reference model -------------------------------------------------------------
    reg [7:0] refm [0:SIDE * SIDE - 1];
    integer fw = SIDE, fh = SIDE, fbg = 0, fcull = 0;
    integer r_frags = 0, r_line = 0, r_tri = 0, r_clear = 0, r_pkts = 0;

    task ref_fill(input integer c);
        integer x, y;
        begin
            for (y = 0; y < fh; y = y + 1)
                for (x = 0; x < fw; x = x + 1) refm[y * SIDE + x] = c;
            r_clear = r_clear + fw * fh;
        end
    endtask

    task ref_put(input integer x, input integer y, input integer c);
        begin
            if (x >= 0 && x < fw && y >= 0 && y < fh) begin
                refm[y * SIDE + x] = c;
                r_frags = r_frags + 1;
            end
        end
    endtask

    task ref_line(input integer x0, input integer y0, input integer x1, input integer y1,
                  input integer c);
        integer dx, dy, xmaj, sw, sx, sy, ex, ey, dm, dn, sn, k, nk, m0, n0;
        begin
            dx = x1 > x0 ? x1 - x0 : x0 - x1;
            dy = y1 > y0 ? y1 - y0 : y0 - y1;
            xmaj = dx >= dy;
            sw = xmaj ? (x1 < x0) : (y1 < y0);
            sx = sw ? x1 : x0; sy = sw ? y1 : y0;
            ex = sw ? x0 : x1; ey = sw ? y0 : y1;
            dm = xmaj ? ex - sx : ey - sy;
            dn = xmaj ? dy : dx;
            m0 = xmaj ? sx : sy;
            n0 = xmaj ? sy : sx;
            sn = xmaj ? (ey >= sy ? 1 : -1) : (ex >= sx ? 1 : -1);
            for (k = 0; k <= dm; k = k + 1) begin
                nk = dm == 0 ? 0 : (2 * k * dn + dm) / (2 * dm);
                if (xmaj) ref_put(m0 + k, n0 + sn * nk, c);
                else ref_put(n0 + sn * nk, m0 + k, c);
            end
            r_line = r_line + LINE_SETUP + dm + 1;
        end
    endtask

    task ref_tri(input integer x0, input integer y0, input integer x1, input integer y1,
                 input integer x2, input integer y2, input integer c);
        integer area, cw, px [0:2], py [0:2], a [0:2], b [0:2], cc [0:2];
        integer e, f, t, A, B, bias, i, j, minx, maxx, miny, maxy, bw, bh;
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
            if (area == 0 || (cw && (fcull & 1)) || (!cw && (fcull & 2)) || bw <= 0 || bh <= 0)
                r_tri = r_tri + TRI_REJECT;
            else begin
                r_tri = r_tri + TRI_SETUP + bw * bh;
                px[0] = 2 * x0; py[0] = 2 * y0;
                px[1] = cw ? 2 * x2 : 2 * x1; py[1] = cw ? 2 * y2 : 2 * y1;
                px[2] = cw ? 2 * x1 : 2 * x2; py[2] = cw ? 2 * y1 : 2 * y2;
                for (e = 0; e < 3; e = e + 1) begin
                    f = (e + 1) % 3; t = (e + 2) % 3;
                    A = py[t] - py[f];
                    B = -(px[t] - px[f]);
                    bias = (A > 0 || (A == 0 && B > 0)) ? 0 : 1;
                    a[e] = 2 * A; b[e] = 2 * B;
                    cc[e] = A * (1 - px[f]) + B * (1 - py[f]) - bias;
                end
                for (j = 0; j < fh; j = j + 1)
                    for (i = 0; i < fw; i = i + 1)
                        if (a[0] * i + b[0] * j + cc[0] >= 0 && a[1] * i + b[1] * j + cc[1] >= 0
                            && a[2] * i + b[2] * j + cc[2] >= 0)
                            ref_put(i, j, c);
            end
        end
    endtask

    // ---- Packets -----------------------------------------------------------------------
    reg [7:0] rx;
    task send(input [7:0] chan, input integer n, input [71:0] bits);
        integer k;
        begin
            spi_begin;
            spi_xfer(chan, rx);
            for (k = 0; k < n; k = k + 1) spi_xfer(bits[71 - 8 * k -: 8], rx);
            spi_end;
        end
    endtask

    task setup(input integer w, input integer h, input integer bg, input integer cull);
        begin
            send(`FITKIT_ADDR_SETUP, BYTES1,
                 {w[8:0] - 9'd1, h[8:0] - 9'd1, bg[7:0], cull[1:0], 8'd0, 4'd0, 32'd0});
            fw = w; fh = h; fbg = bg; fcull = cull;
            r_frags = 0; r_line = 0; r_tri = 0; r_clear = 0; r_pkts = 0;
            ref_fill(bg);
        end
    endtask

    task line(input cb, input integer x0, input integer y0, input integer x1, input integer y1,
              input integer c);
        begin
            send(`FITKIT_ADDR_LINE, BYTES2,
                 {cb, x0[8:0], y0[8:0], x1[8:0], y1[8:0], c[7:0], 27'd0});
            if (cb) ref_fill(fbg);
            ref_line(x0, y0, x1, y1, c);
            r_pkts = r_pkts + 1;
        end
    endtask

    task triangle(input cb, input integer x0, input integer y0, input integer x1, input integer y1,
             input integer x2, input integer y2, input integer c);
        begin
            send(`FITKIT_ADDR_TRIANGLE, BYTES2,
                 {cb, x0[8:0], y0[8:0], x1[8:0], y1[8:0], x2[8:0], y2[8:0], c[7:0], 9'd0});
            if (cb) ref_fill(fbg);
            ref_tri(x0, y0, x1, y1, x2, y2, c);
            r_pkts = r_pkts + 1;
        end
    endtask

    task clear(input integer c);
        begin
            send(`FITKIT_ADDR_CLEAR, BYTES1, {1'b1, c[7:0], 31'd0, 32'd0});
            ref_fill(c);
            r_pkts = r_pkts + 1;
        end
    endtask

    task wait_idle;
        integer quiet;
        begin
            quiet = 0;
            while (quiet < 4) begin
                @(posedge clk);
                quiet = busy ? 0 : quiet + 1;
            end
            @(negedge clk);   // callers change inputs next: not at a sampling edge
        end
    endtask

    reg [7:0] st [0:ST_BYTES + 1];   // the block and two bytes past it
    task read_status;
        integer k;
        begin
            spi_begin;
            spi_xfer(`FITKIT_ADDR_STATUS, rx);
            for (k = 0; k < ST_BYTES + 2; k = k + 1) begin
                spi_xfer(8'h00, rx);
                st[k] = rx;
            end
            spi_end;
        end
    endtask

    function [31:0] st32(input integer k);
        st32 = {st[k], st[k + 1], st[k + 2], st[k + 3]};
    endfunction

    function [15:0] st16(input integer k);
        st16 = {st[k], st[k + 1]};
    endfunction

    function flag(input integer b);
        flag = st[`FITKIT_STATUS_FLAGS][b];
    endfunction

    task check_counters;
        begin
            read_status;
            check(st[`FITKIT_STATUS_ERROR_CODE] == 0, "no error");
            check(flag(`FITKIT_FLAG_SETUP_DONE) == 1'b1, "set-up done");
            check(flag(`FITKIT_FLAG_BUSY) == 1'b0 && flag(`FITKIT_FLAG_FIFO_EMPTY) == 1'b1,
                  "idle, FIFO empty");
            check(st16(`FITKIT_STATUS_FREE) == `FITKIT_FIFO_RECORDS, "every record free");
            check(st32(`FITKIT_STATUS_PACKETS) == r_pkts, "packets executed");
            check(st32(`FITKIT_STATUS_FRAGMENTS) == r_frags, "fragments written");
            check(st32(`FITKIT_STATUS_LINE_CYCLES) == r_line, "line cycles");
            check(st32(`FITKIT_STATUS_TRIANGLE_CYCLES) == r_tri, "triangle cycles");
            check(st32(`FITKIT_STATUS_CLEAR_CYCLES) == r_clear, "clear cycles");
            check(st[ST_BYTES] == 0 && st[ST_BYTES + 1] == 0, "zeros past the block");
            if (st32(`FITKIT_STATUS_LINE_CYCLES) != r_line
                || st32(`FITKIT_STATUS_TRIANGLE_CYCLES) != r_tri
                || st32(`FITKIT_STATUS_CLEAR_CYCLES) != r_clear
                || st32(`FITKIT_STATUS_FRAGMENTS) != r_frags
                || st32(`FITKIT_STATUS_PACKETS) != r_pkts)
                $display("  status: pk %0d/%0d fr %0d/%0d line %0d/%0d tri %0d/%0d clr %0d/%0d",
                         st32(`FITKIT_STATUS_PACKETS), r_pkts, st32(`FITKIT_STATUS_FRAGMENTS),
                         r_frags, st32(`FITKIT_STATUS_LINE_CYCLES), r_line,
                         st32(`FITKIT_STATUS_TRIANGLE_CYCLES), r_tri,
                         st32(`FITKIT_STATUS_CLEAR_CYCLES), r_clear);
        end
    endtask

    task check_frame(input [8*48-1:0] what);
        integer k, bad;
        begin
            bad = 0;
            for (k = 0; k < SIDE * SIDE; k = k + 1)
                if (u_top.u_ram.mem[k] !== refm[k]) begin
                    if (bad < 5)
                        $display("  pixel (%0d, %0d): rtl %h, ref %h", k % SIDE, k / SIDE,
                                 u_top.u_ram.mem[k], refm[k]);
                    bad = bad + 1;
                end
            check(bad == 0, what);
        end
    endtask

    task expect_error(input integer code, input integer chan, input integer pkt,
                      input [8*48-1:0] what);
        begin
            read_status;
            check(flag(`FITKIT_FLAG_ERROR) == 1'b1 && st[`FITKIT_STATUS_ERROR_CODE] == code
                  && st[`FITKIT_STATUS_ERROR_CHANNEL] == chan
                  && st16(`FITKIT_STATUS_ERROR_PACKET) == pkt, what);
            if (st[`FITKIT_STATUS_ERROR_CODE] != code
                || st[`FITKIT_STATUS_ERROR_CHANNEL] != chan
                || st16(`FITKIT_STATUS_ERROR_PACKET) != pkt)
                $display("  error code %0d chan %h packet %0d", st[`FITKIT_STATUS_ERROR_CODE],
                         st[`FITKIT_STATUS_ERROR_CHANNEL], st16(`FITKIT_STATUS_ERROR_PACKET));
        end
    endtask

    task soft_reset;
        begin
            send(`FITKIT_ADDR_RESET, 0, 72'd0);
            repeat (4) @(posedge clk);
        end
    endtask

    // ---- File mode -------------------------------------------------------------------
    reg [11:0] words [0:1048575];
    reg [8*256-1:0] txfile, dumpfile;
    task run_file;
        integer k, open;
        begin
            for (k = 0; k < 1048576; k = k + 1) words[k] = 12'h000;
            $readmemh(txfile, words);
            open = 0;
            k = 0;
            while (words[k] != 12'h000) begin
                case (words[k][11:8])
                    4'h1: begin
                        if (!open) begin
                            spi_begin;
                            open = 1;
                        end
                        spi_xfer(words[k][7:0], rx);
                    end
                    4'h2: if (open) begin
                        spi_end;
                        open = 0;
                    end
                    4'h3: wait_idle;
                    4'h4: mem_wait = words[k][0];
                    default: ;
                endcase
                k = k + 1;
            end
            if (open) spi_end;
            wait_idle;
            if (!$value$plusargs("dump=%s", dumpfile)) dumpfile = "rtl-frame.hex";
            $writememh(dumpfile, u_top.u_ram.mem);
        end
    endtask

    // ---- Tests -----------------------------------------------------------------------
    integer k, n;
    reg [7:0] rb [0:63];
    initial begin
        repeat (5) @(negedge clk);
        rst = 1'b0;
        repeat (5) @(posedge clk);
        if ($value$plusargs("tx=%s", txfile)) begin
            run_file;
            $finish;
        end

        for (k = 0; k < SIDE * SIDE; k = k + 1) refm[k] = 8'd0;

        // Power-on status.
        read_status;
        check(st[`FITKIT_STATUS_FLAGS] == 8'd1 << `FITKIT_FLAG_FIFO_EMPTY
              && st[`FITKIT_STATUS_ERROR_CODE] == 0
              && st16(`FITKIT_STATUS_FREE) == `FITKIT_FIFO_RECORDS, "power-on status");

        // Set-up and the test vector of docs/protocol.md (CB = 1).
        setup(40, 30, 8'h12, 0);
        wait_idle;
        check_frame("set-up clear");
        read_status;
        check(st32(`FITKIT_STATUS_END_CYCLE) == 40 * 30 + 1
              && st32(`FITKIT_STATUS_CLEAR_CYCLES) == 40 * 30
              && st32(`FITKIT_STATUS_PACKETS) == 0,
              "a set-up alone completes at cycle W*H + 1");
        send(`FITKIT_ADDR_LINE, BYTES2, 72'h8_0405_2CC8_5_4800_0000);
        ref_fill(fbg);
        ref_line(1, 2, 300, 400, 8'hA9);
        r_pkts = r_pkts + 1;
        wait_idle;
        check_frame("protocol test vector line");
        check_counters;

        // Lines: all octants, reversed, zero length, partly outside.
        setup(64, 48, 8'h00, 0);
        line(0, 32, 24, 60, 30, 8'h01);
        line(0, 32, 24, 40, 47, 8'h02);
        line(0, 32, 24, 25, 47, 8'h03);
        line(0, 32, 24, 2, 30, 8'h04);
        line(0, 32, 24, 2, 18, 8'h05);
        line(0, 32, 24, 28, 0, 8'h06);
        line(0, 32, 24, 39, 0, 8'h07);
        line(0, 32, 24, 63, 20, 8'h08);
        line(0, 60, 30, 32, 24, 8'h09);
        line(0, 10, 10, 10, 10, 8'h0A);
        line(0, 5, 5, 45, 25, 8'h0B);
        line(0, 45, 25, 5, 5, 8'h0C);
        line(0, 0, 0, 300, 100, 8'h0D);
        line(0, 500, 10, 3, 40, 8'h0E);
        line(0, 70, 70, 100, 90, 8'h0F);
        wait_idle;
        check_frame("lines");
        check_counters;

        // Triangles: both windings, shared edges, centres on edges, degenerate, clipped.
        setup(64, 48, 8'h33, 0);
        triangle(0, 2, 2, 30, 5, 10, 40, 8'hE0);
        triangle(0, 40, 2, 40, 30, 60, 30, 8'h1C);
        triangle(0, 40, 2, 60, 30, 60, 2, 8'h03);
        triangle(0, 10, 10, 20, 10, 15, 10, 8'hFF);
        triangle(0, 30, 20, 200, 30, 50, 300, 8'h92);
        triangle(0, 100, 100, 120, 100, 110, 120, 8'h49);
        wait_idle;
        check_frame("triangles");
        check_counters;

        // Culling, CB on a triangle, a clear packet.
        setup(32, 32, 8'h01, 1);
        triangle(0, 2, 2, 20, 4, 6, 20, 8'hAA);   // clockwise? both orders, one is culled
        triangle(0, 2, 2, 6, 20, 20, 4, 8'hBB);
        wait_idle;
        check_frame("cull clockwise");
        setup(32, 32, 8'h01, 2);
        triangle(0, 2, 2, 20, 4, 6, 20, 8'hAA);
        triangle(0, 2, 2, 6, 20, 20, 4, 8'hBB);
        triangle(1, 4, 4, 30, 9, 9, 30, 8'hCC);
        line(1, 0, 31, 31, 0, 8'hDD);
        clear(8'h5A);
        line(0, 0, 0, 31, 31, 8'hEE);
        wait_idle;
        check_frame("cull ccw, CB, clear");
        check_counters;

        // Read-back of 64 bytes from address 20 (rows 0 and 1), mem_wait toggling at random.
        fork
            begin
                spi_begin;
                spi_xfer(`FITKIT_ADDR_READ, rx);
                spi_xfer(8'h00, rx);      // start address 20, 24 bits
                spi_xfer(8'h00, rx);
                spi_xfer(8'd20, rx);
                for (k = 0; k < `FITKIT_READ_TURNAROUND; k = k + 1) spi_xfer(8'h00, rx);
                for (k = 0; k < 64; k = k + 1) begin
                    spi_xfer(8'h00, rx);
                    rb[k] = rx;
                end
                spi_end;
            end
            begin
                repeat (6000) begin
                    @(negedge clk);   // not at the edge the design samples it
                    mem_wait = $random;
                end
                mem_wait = 1'b0;
            end
        join
        n = 0;
        for (k = 0; k < 64; k = k + 1)
            if (rb[k] !== refm[20 + k]) begin
                if (n < 5) $display("  read-back byte %0d: %h, want %h", k, rb[k], refm[20 + k]);
                n = n + 1;
            end
        check(n == 0, "read-back bytes");
        read_status;
        check(st[`FITKIT_STATUS_ERROR_CODE] == 0, "read-back without error");
        if (st[`FITKIT_STATUS_ERROR_CODE] != 0)
            $display("  error code %0d", st[`FITKIT_STATUS_ERROR_CODE]);

        // Drawing with mem_wait toggling gives the same frame.
        setup(48, 40, 8'h07, 0);
        fork
            begin
                triangle(0, 1, 1, 47, 9, 20, 39, 8'h71);
                line(0, 0, 39, 47, 0, 8'h72);
            end
            begin
                repeat (3000) begin
                    @(negedge clk);   // not at the edge the design samples it
                    mem_wait = $random;
                end
                mem_wait = 1'b0;
            end
        join
        wait_idle;
        check_frame("frame under mem_wait");

        // Random packets back to back (several queued at once), random mem_wait.
        setup(72, 56, 8'h24, 0);
        fork
            for (k = 0; k < 60; k = k + 1) begin
                n = $unsigned($random) % 16;
                if (n < 7)
                    line(n == 0, $unsigned($random) % 90, $unsigned($random) % 70,
                         $unsigned($random) % 90, $unsigned($random) % 70, $random);
                else if (n < 15)
                    triangle(n == 7, $unsigned($random) % 90, $unsigned($random) % 70,
                             $unsigned($random) % 90, $unsigned($random) % 70,
                             $unsigned($random) % 90, $unsigned($random) % 70, $random);
                else clear($random);
            end
            begin
                repeat (40000) begin
                    @(negedge clk);
                    mem_wait = ($unsigned($random) % 4) == 0;
                end
                mem_wait = 1'b0;
            end
        join
        wait_idle;
        check_frame("random packets under mem_wait");
        read_status;
        check(st32(`FITKIT_STATUS_PACKETS) == r_pkts
              && st32(`FITKIT_STATUS_FRAGMENTS) == r_frags, "random packets: packets, fragments");

        // Errors: each sets the sticky error; status, reset and set-up still work after it.
        soft_reset;
        send(`FITKIT_ADDR_LINE, BYTES2 - 1, 72'h8_0405_2CC8_5_4800_0000);
        expect_error(`FITKIT_ERR_LENGTH, `FITKIT_ADDR_LINE, 0, "length error");
        send(`FITKIT_ADDR_LINE, BYTES2, 72'h8_0405_2CC8_5_4800_0001);
        expect_error(`FITKIT_ERR_LENGTH, `FITKIT_ADDR_LINE, 0, "first error kept");
        soft_reset;
        read_status;
        check(st[`FITKIT_STATUS_ERROR_CODE] == 0 && flag(`FITKIT_FLAG_ERROR) == 1'b0
              && flag(`FITKIT_FLAG_SETUP_DONE) == 1'b0, "reset clears the error");
        setup(16, 16, 8'h10, 0);
        send(`FITKIT_ADDR_LINE, BYTES2, 72'h8_0405_2CC8_5_4800_0001);
        expect_error(`FITKIT_ERR_PADDING, `FITKIT_ADDR_LINE, 1, "padding error");
        soft_reset;
        send(`FITKIT_ADDR_CLEAR, BYTES1, {1'b0, 8'h44, 31'd0, 32'd0});
        expect_error(`FITKIT_ERR_CLEAR_WITHOUT_CB, `FITKIT_ADDR_CLEAR, 0, "clear without CB");
        soft_reset;
        send(8'h55, 2, 72'd0);
        expect_error(`FITKIT_ERR_UNKNOWN_ADDRESS, 8'h55, 0, "unknown address");
        soft_reset;
        send(`FITKIT_ADDR_SETUP, BYTES1, {9'd15, 9'd15, 8'd0, 2'd0, 8'd1, 4'd0, 32'd0});
        expect_error(`FITKIT_ERR_PADDING, `FITKIT_ADDR_SETUP, 0, "set-up padding");
        soft_reset;
        // Read underrun: the memory never answers.
        mem_wait = 1'b1;
        spi_begin;
        for (k = 0; k < `FITKIT_READ_HEADER_BYTES + 2; k = k + 1)
            spi_xfer(k == 0 ? `FITKIT_ADDR_READ : 8'h00, rx);
        spi_end;
        mem_wait = 1'b0;
        expect_error(`FITKIT_ERR_READ_UNDERRUN, `FITKIT_ADDR_READ, 0, "read underrun");
        soft_reset;
        // Overrun: the memory stalls the first clear, the FIFO fills up.
        setup(16, 16, 8'h10, 0);
        wait_idle;
        mem_wait = 1'b1;
        clear(8'h20);
        for (k = 0; k < `FITKIT_FIFO_RECORDS / 2; k = k + 1) line(0, 0, 0, 15, 15, 8'h30);
        read_status;
        check(st16(`FITKIT_STATUS_FREE) == 16'd0 && !fifo_free, "FIFO full");
        check(st[`FITKIT_STATUS_FIFO_MAX_PAIRS] == 8'd255, "max occupancy saturates");
        send(`FITKIT_ADDR_LINE, BYTES2, {1'b0, 9'd0, 9'd0, 9'd1, 9'd1, 8'h40, 27'd0});
        // Committed so far: the set-up, the clear and the lines.
        expect_error(`FITKIT_ERR_OVERRUN, `FITKIT_ADDR_LINE, 2 + `FITKIT_FIFO_RECORDS / 2,
                     "overrun");
        mem_wait = 1'b0;
        wait_idle;
        check_frame("frame after overrun");
        setup(16, 16, 8'h11, 0);
        line(0, 0, 0, 15, 3, 8'h22);
        wait_idle;
        check_frame("set-up after errors");
        read_status;
        check(st[`FITKIT_STATUS_ERROR_CODE] == `FITKIT_ERR_OVERRUN
              && flag(`FITKIT_FLAG_SETUP_DONE) == 1'b1, "error stays, set-up done");

        $display("tb_top: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_top failed");
        $finish;
    end
endmodule
`default_nettype wire
