// tb_fpgfx -- self-checking testbench for one set of fpgfx raster test vectors.
//
// Written by fpgfx @VERSION@ (`fpgfx vectors raster`) for @JOB@ (@JOB_HASH@):
// a @WIDTH@ x @HEIGHT@ frame, FITkit layout. docs/vectors.md describes every file.
//
// The DUT is module fitkit_raster with the ports of docs/rtl.md ("Top level"): SPI mode 0
// at f_SCK = f_clk / 8, CS_n high for 8 clk between transactions, every packet held until
// FIFO_FREE; the external memory is a synchronous 2^18 x 8 RAM in this file (a request is
// taken in a cycle with mem_wait low, read data the cycle after, power-on zero).
//
// Checks, in this order (each one counts as passed or failed):
//   1. every memory write against expected_fragments.hex, in order, while the job runs
//      (the address y * 512 + x and the colour), and their number;
//   2. the status block (SPI channel 0x20) once busy is low: no error, FIFO empty and
//      512 free, packets, fragments, and the line / triangle / clear unit cycles;
//   3. the memory's W x H frame against expected_framebuffer.hex, pixel by pixel;
//   4. rows read back over SPI channel 0x30 against the same frame, then the status
//      block again (no read-back underrun).
// The first mismatches of each check are printed with the pixel (x, y), expected and
// got; the end is "tb_fpgfx: N passed, M failed" and a line "TB_FPGFX PASS" or
// "TB_FPGFX FAIL". A DUT that never finishes fails at the cycle limit.
//
// Plusargs:
//   +mem_wait=D        mem_wait high in D of 256 cycles (xorshift32, seed 1; default 0);
//                      with D > 0 the unit cycle counters are checked as >= the model's
//   +readback_every=N  read back rows 0, N, 2N, ... and the last one (0: none; default
//                      HEIGHT - 1: the first and the last row)
//   +no_fragments      skip check 1 (an RTL that writes in another order)
//   +no_status         skip check 2 and the status read after check 4 (an RTL without
//                      channel 0x20)
//   +cycle_limit=N     give up after N clk cycles (default @CYCLE_LIMIT@, scaled up by
//                      256 / (256 - D) under +mem_wait=D)
//   +max_report=N      mismatches printed per check (default 10)
`timescale 1ns / 1ps
`include "fitkit_map.vh"
module tb_fpgfx;
    localparam integer WIDTH = @WIDTH@;
    localparam integer HEIGHT = @HEIGHT@;
    localparam integer SPI_BYTES = @SPI_BYTES@;
    localparam integer SPI_FRAMES = @SPI_FRAMES@;
    localparam integer FRAGMENTS = @FRAGMENTS@;
    // The status block's counters after the job, from the golden model (32-bit, wrapping).
    localparam [31:0] EXP_PACKETS = 32'd@EXP_PACKETS@;
    localparam [31:0] EXP_FRAGMENTS = 32'd@EXP_FRAGMENTS@;
    localparam [31:0] EXP_LINE_CYCLES = 32'd@EXP_LINE_CYCLES@;
    localparam [31:0] EXP_TRI_CYCLES = 32'd@EXP_TRI_CYCLES@;
    localparam [31:0] EXP_CLEAR_CYCLES = 32'd@EXP_CLEAR_CYCLES@;
    localparam [63:0] CYCLE_LIMIT = 64'd@CYCLE_LIMIT@;
    // clk has a period of 10 time units; SPI edges fall on clk's falling edges.
    localparam integer HALF = 40;       // SCK half period, 4 clk: f_SCK = f_clk / 8
    localparam integer CS_GAP = 80;     // 8 clk of CS_n high after each transaction

    reg clk = 1'b0;
    reg rst = 1'b1;
    reg spi_sck = 1'b0, spi_cs_n = 1'b1, spi_mosi = 1'b0;
    reg mem_wait = 1'b0;
    reg [7:0] mem_rdata = 8'd0;
    wire spi_miso, fifo_free, busy, mem_we, mem_re;
    wire [17:0] mem_addr;
    wire [7:0] mem_wdata;

    always #5 clk = ~clk;

    fitkit_raster dut (
        .clk(clk), .rst(rst), .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi),
        .spi_miso(spi_miso), .fifo_free(fifo_free), .busy(busy), .mem_addr(mem_addr),
        .mem_wdata(mem_wdata), .mem_we(mem_we), .mem_re(mem_re), .mem_rdata(mem_rdata),
        .mem_wait(mem_wait)
    );

    // ---- The vectors -------------------------------------------------------------------
    reg [7:0]  spi_bytes [0:SPI_BYTES-1];
    reg [31:0] spi_frames [0:SPI_FRAMES-1];
    reg [35:0] frags [0:FRAGMENTS-1];
    reg [7:0]  fb [0:WIDTH*HEIGHT-1];

    // ---- Options, counters, the end ----------------------------------------------------
    integer wait_duty = 0, readback_every = 1, max_report = 10;
    integer frag_n = 0, frag_bad = 0;   // writes seen, of them wrong
    reg check_frags = 1'b1, check_status = 1'b1;
    reg [63:0] cycle_limit = CYCLE_LIMIT;
    reg [63:0] cycle = 64'd0;
    reg [8*16-1:0] phase = "reset";
    integer passed = 0, failed = 0;

    task summary;
        begin
            $display("tb_fpgfx: %0d passed, %0d failed", passed, failed);
            if (failed == 0) $display("TB_FPGFX PASS");
            else $display("TB_FPGFX FAIL");
            $finish;
        end
    endtask

    // The cycle bound: a stuck DUT (busy forever, FIFO_FREE never high) fails here.
    always @(posedge clk) begin
        cycle = cycle + 64'd1;
        if (cycle == cycle_limit) begin
            $display("FAIL cycle limit: %0d clk cycles reached in phase \"%0s\" (busy %b, fifo_free %b, %0d of %0d writes seen): the DUT is stuck",
                     cycle_limit, phase, busy, fifo_free, frag_n, FRAGMENTS);
            failed = failed + 1;
            summary;
        end
    end

    // ---- External memory: synchronous RAM, as rtl/sim/sim_ram.v ------------------------
    reg [7:0] ram [0:262143];
    always @(posedge clk) begin
        if (mem_we && !mem_wait) ram[mem_addr] <= mem_wdata;
        if (mem_re && !mem_wait) mem_rdata <= ram[mem_addr];
    end

    function [31:0] xorshift(input [31:0] s);
        reg [31:0] t;
        begin
            t = s ^ (s << 13);
            t = t ^ (t >> 17);
            xorshift = t ^ (t << 5);
        end
    endfunction

    reg [31:0] rng = 32'd1;
    always @(posedge clk) begin
        rng <= xorshift(rng);
        mem_wait <= wait_duty > 0 && {24'd0, rng[7:0]} < wait_duty;
    end

    // ---- Check 1: the write stream ------------------------------------------------------
    // Entry k: [35:32] kind (1 fragment, 0 clear write), [31:20] y, [19:8] x, [7:0] colour.
    always @(posedge clk) begin
        if (!rst && mem_we && !mem_wait) begin
            if (check_frags) begin
                if (frag_n >= FRAGMENTS) begin
                    failed = failed + 1;
                    frag_bad = frag_bad + 1;
                    if (frag_bad <= max_report)
                        $display("FAIL fragment %0d: unexpected write to pixel (%0d, %0d) = 0x%02h, the vectors end at %0d writes",
                                 frag_n, mem_addr[8:0], mem_addr[17:9], mem_wdata, FRAGMENTS);
                end else if (mem_addr == {frags[frag_n][28:20], frags[frag_n][16:8]}
                             && mem_wdata == frags[frag_n][7:0]) begin
                    passed = passed + 1;
                end else begin
                    failed = failed + 1;
                    frag_bad = frag_bad + 1;
                    if (frag_bad <= max_report)
                        $display("FAIL fragment %0d: expected pixel (%0d, %0d) = 0x%02h, got pixel (%0d, %0d) = 0x%02h",
                                 frag_n, frags[frag_n][19:8], frags[frag_n][31:20], frags[frag_n][7:0],
                                 mem_addr[8:0], mem_addr[17:9], mem_wdata);
                end
            end
            frag_n = frag_n + 1;
        end
    end

    // ---- SPI master, mode 0 --------------------------------------------------------------
    reg [7:0] rx;
    `include "spi_tasks.vh"

    task wait_idle;
        integer quiet;
        begin
            quiet = 0;
            while (quiet < 4) begin
                @(posedge clk);
                quiet = busy ? 0 : quiet + 1;
            end
        end
    endtask

    // ---- Check 2: the status block -----------------------------------------------------
    reg [7:0] st [0:31];
    task read_status;
        integer k;
        begin
            spi_begin;
            spi_xfer(`FITKIT_ADDR_STATUS, rx);
            for (k = 0; k < 32; k = k + 1) begin
                spi_xfer(8'h00, rx);
                st[k] = rx;
            end
            spi_end;
        end
    endtask

    function [31:0] st32(input integer i);
        st32 = {st[i], st[i + 1], st[i + 2], st[i + 3]};
    endfunction

    task expect_field(input [8*24-1:0] what, input [31:0] got, input [31:0] want,
                      input at_least);
        begin
            if (got == want || (at_least && got > want)) passed = passed + 1;
            else begin
                failed = failed + 1;
                $display("FAIL status %0s: expected %0s%0d, got %0d", what,
                         at_least ? ">= " : "", want, got);
            end
        end
    endtask

    task expect_no_error;
        begin
            if (st[2][1] == 1'b0 && st[3] == 8'd0) passed = passed + 1;
            else begin
                failed = failed + 1;
                $display("FAIL status error: code %0d on channel 0x%02h at packet %0d (docs/rtl.md lists the codes)",
                         st[3], st[4], {st[5], st[6]});
            end
        end
    endtask

    // ---- Checks 3 and 4: the frame ---------------------------------------------------------
    integer pix_bad = 0;
    task expect_pixel(input [8*16-1:0] where, input integer x, input integer y,
                      input [7:0] got);
        begin
            if (got == fb[y * WIDTH + x]) passed = passed + 1;
            else begin
                failed = failed + 1;
                pix_bad = pix_bad + 1;
                if (pix_bad <= max_report)
                    $display("FAIL %0s pixel (%0d, %0d): expected 0x%02h, got 0x%02h", where, x, y,
                             fb[y * WIDTH + x], got);
            end
        end
    endtask

    task read_row(input integer y);
        integer x;
        reg [17:0] a;
        reg [7:0] px;
        begin
            a = y * 512;
            spi_begin;
            spi_xfer(`FITKIT_ADDR_READ, rx);
            spi_xfer({6'd0, a[17:16]}, rx);
            spi_xfer(a[15:8], rx);
            spi_xfer(a[7:0], rx);
            spi_xfer(8'h00, rx);   // turnaround
            for (x = 0; x < WIDTH; x = x + 1) begin
                spi_xfer(8'h00, px);
                expect_pixel("read-back", x, y, px);
            end
            spi_end;
        end
    endtask

    // ---- The run -----------------------------------------------------------------------
    integer f, k, x, y, start, len, shown;
    initial begin
        if ($value$plusargs("mem_wait=%d", wait_duty)) begin
            if (wait_duty < 0 || wait_duty > 255) begin
                $display("tb_fpgfx: +mem_wait=%0d is outside 0..255", wait_duty);
                wait_duty = 0;
                failed = failed + 1;
            end
        end
        if (!$value$plusargs("readback_every=%d", readback_every))
            readback_every = HEIGHT > 1 ? HEIGHT - 1 : 1;
        if (!$value$plusargs("max_report=%d", max_report)) max_report = 10;
        if ($test$plusargs("no_fragments")) check_frags = 1'b0;
        if ($test$plusargs("no_status")) check_status = 1'b0;
        if (!$value$plusargs("cycle_limit=%d", cycle_limit)) cycle_limit = CYCLE_LIMIT;
        if (wait_duty > 0) cycle_limit = (cycle_limit / (256 - wait_duty) + 1) * 256;

        for (k = 0; k < 262144; k = k + 1) ram[k] = 8'd0;
        $readmemh("spi_bytes.hex", spi_bytes);
        $readmemh("spi_frames.hex", spi_frames);
        $readmemh("expected_fragments.hex", frags);
        $readmemh("expected_framebuffer.hex", fb);
        $display("tb_fpgfx: @JOB@, @WIDTH@ x @HEIGHT@, %0d SPI transactions, %0d memory writes expected, mem_wait %0d/256",
                 SPI_FRAMES, FRAGMENTS, wait_duty);

        repeat (4) @(posedge clk);
        @(negedge clk);
        rst = 1'b0;
        repeat (4) @(negedge clk);

        phase = "spi";
        for (f = 0; f < SPI_FRAMES; f = f + 1) begin
            start = spi_frames[f][31:8];
            len = spi_frames[f][7:0];
            // Back-pressure: every transaction is one packet of at most 2 records.
            while (!fifo_free) @(negedge clk);
            spi_begin;
            for (k = 0; k < len; k = k + 1) spi_xfer(spi_bytes[start + k], rx);
            spi_end;
        end

        phase = "drawing";
        wait_idle;
        if (check_frags) begin
            if (frag_n == FRAGMENTS) passed = passed + 1;
            else begin
                failed = failed + 1;
                $display("FAIL fragments: %0d memory writes, expected %0d", frag_n, FRAGMENTS);
            end
            if (frag_bad > max_report)
                $display("  (%0d fragment mismatches in all)", frag_bad);
        end

        if (check_status) begin
            phase = "status";
            read_status;
            expect_no_error;
            expect_field("flags busy", {31'd0, st[2][0]}, 32'd0, 1'b0);
            expect_field("flags FIFO empty", {31'd0, st[2][2]}, 32'd1, 1'b0);
            expect_field("free records", {16'd0, st[0], st[1]}, 32'd512, 1'b0);
            expect_field("packets executed", st32(7), EXP_PACKETS, 1'b0);
            expect_field("fragments written", st32(11), EXP_FRAGMENTS, 1'b0);
            expect_field("line cycles", st32(15), EXP_LINE_CYCLES, wait_duty > 0);
            expect_field("triangle cycles", st32(19), EXP_TRI_CYCLES, wait_duty > 0);
            expect_field("clear cycles", st32(23), EXP_CLEAR_CYCLES, wait_duty > 0);
        end

        phase = "frame";
        for (y = 0; y < HEIGHT; y = y + 1)
            for (x = 0; x < WIDTH; x = x + 1)
                expect_pixel("frame", x, y, ram[y * 512 + x]);
        if (pix_bad > max_report) $display("  (%0d frame mismatches in all)", pix_bad);

        if (readback_every > 0) begin
            phase = "read-back";
            shown = pix_bad;
            pix_bad = 0;
            for (y = 0; y < HEIGHT; y = y + readback_every) read_row(y);
            if ((HEIGHT - 1) % readback_every != 0) read_row(HEIGHT - 1);
            if (pix_bad > max_report) $display("  (%0d read-back mismatches in all)", pix_bad);
            pix_bad = pix_bad + shown;
            if (check_status) begin
                read_status;
                expect_no_error;
            end
        end
        summary;
    end
endmodule
