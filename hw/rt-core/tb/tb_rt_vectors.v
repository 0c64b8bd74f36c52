// tb_rt_vectors -- the ray-casting core's device driven by `fpgfx vectors render` output
// over its AXI4-Lite bus, as a MicroBlaze drives ViRAY (seed 002): every write of
// axi_writes.hex (the scene image through the scene window, NUMERIC, AOVS, then AP_CTRL's
// ap_start) as an AXI4-Lite write, AP_CTRL polled until ap_done, and every pixel the
// memory port gives (its READY low on a pseudo-random third of the clocks) checked: its
// colour (RGB888 and the KCU116 word), depth and normal against the golden model's
// (expected_rgb888.hex, expected_kcu116.hex, expected_depth.hex, expected_normal.hex;
// docs/vectors.md). scene_regs.hex gives the frame's size. Writes the frame as
// actual_rgb888.hex beside them, for `fpgfx compare`.
//
// Usage (Icarus): iverilog -g2012 -I hw/rt-core/rtl -I hw/shared-tb -s tb_rt_vectors
//   -o tb.vvp hw/rt-core/tb/tb_rt_vectors.v hw/rt-core/rtl/*.v; vvp -n tb.vvp +vec=DIR
//   (+vcd=PATH as well: every signal's waveform to PATH, check.vh)
// Prints "tb_rt_vectors: N passed, M failed" (check.vh's counters), then
// "TB_RT_CORE PASS: <checks> checks, <cycles> cycles, <held> held" (RT_CYCLES,
// the frame's clocks as the device counted them, and the clocks the memory held the
// core) or "TB_RT_CORE FAIL ..."; a write answered SLVERR,
// a handshake that never comes and a frame that does not finish within its bound fail,
// naming the address or the pixels received.
// Depth and normal are compared as the model's f32 planes: each Q16.16 word converted to
// binary32, rounded to nearest even (the model's `to_f64() as f32`).
`timescale 1ns / 1ps
`default_nettype none
`include "rt_map.vh"
`include "rt_axi_map.vh"
module tb_rt_vectors;
    localparam integer MAXPIX = 1 << 16;
    localparam integer AW = `RT_AXI_ADDR_BITS;

    reg clk = 1'b0;
    always #5 clk = !clk;
    reg           rst = 1'b1;
    reg           awvalid = 1'b0, wvalid = 1'b0, bready = 1'b0, arvalid = 1'b0;
    reg           rready = 1'b0;
    reg  [AW-1:0] awaddr = 0, araddr = 0;
    reg  [31:0]   wdata = 32'd0;
    wire          awready, wready, bvalid, arready, rvalid, irq;
    wire [1:0]    bresp, rresp;
    wire [31:0]   rdata;
    reg           mem_ready = 1'b1;
    wire          mem_valid, mem_aovs;
    // this bench checks the frame on the write port; the read-back is the bridge's test
    wire          rd_valid;
    wire [31:0]   rd_index;
    wire [31:0]   mem_index, mem_t;
    wire [23:0]   mem_rgb;
    wire [15:0]   mem_kcu116;
    wire [7:0]    mem_obj;
    wire [95:0]   mem_n;
    rt_device dut (.clk(clk), .rst(rst), .s_axi_awvalid(awvalid), .s_axi_awready(awready),
        .s_axi_awaddr(awaddr), .s_axi_awprot(3'd0), .s_axi_wvalid(wvalid),
        .s_axi_wready(wready), .s_axi_wdata(wdata), .s_axi_wstrb(4'hf),
        .s_axi_bvalid(bvalid), .s_axi_bready(bready), .s_axi_bresp(bresp),
        .s_axi_arvalid(arvalid), .s_axi_arready(arready), .s_axi_araddr(araddr),
        .s_axi_arprot(3'd0), .s_axi_rvalid(rvalid), .s_axi_rready(rready),
        .s_axi_rdata(rdata), .s_axi_rresp(rresp), .irq(irq), .mem_valid(mem_valid),
        .mem_ready(mem_ready), .mem_index(mem_index), .mem_rgb(mem_rgb),
        .mem_kcu116(mem_kcu116), .mem_obj(mem_obj), .mem_t(mem_t), .mem_n(mem_n),
        .mem_aovs(mem_aovs), .rd_valid(rd_valid), .rd_ready(1'b1), .rd_index(rd_index),
        .rd_resp(1'b0), .rd_rgb(24'd0), .rd_obj(8'd0), .rd_t(32'd0), .rd_n(96'd0));


    // ---- an AXI4-Lite master: one access at a time, each a whole handshake ------------------
    localparam integer HANDSHAKE = 10000;  // clocks before a handshake counts as stuck
    integer waited;
    task axi_write(input [31:0] addr, input [31:0] data);
        begin
            @(negedge clk);
            awvalid = 1'b1;
            awaddr = addr[AW-1:0];
            wvalid = 1'b1;
            wdata = data;
            waited = 0;
            while (awvalid || wvalid) begin
                @(posedge clk);
                if (awready) awvalid <= 1'b0;
                if (wready) wvalid <= 1'b0;
                @(negedge clk);
                waited = waited + 1;
                if (waited > HANDSHAKE) begin
                    $display("TB_RT_CORE FAIL: write to %h: no AW/W handshake", addr);
                    $finish;
                end
            end
            bready = 1'b1;
            while (!bvalid) begin
                @(negedge clk);
                waited = waited + 1;
                if (waited > HANDSHAKE) begin
                    $display("TB_RT_CORE FAIL: write to %h: no response", addr);
                    $finish;
                end
            end
            if (bresp != 2'b00) begin
                $display("TB_RT_CORE FAIL: write of %h to %h answered SLVERR", data, addr);
                $finish;
            end
            @(posedge clk);
            bready <= 1'b0;
        end
    endtask
    task axi_read(input [31:0] addr, output [31:0] data);
        begin
            @(negedge clk);
            arvalid = 1'b1;
            araddr = addr[AW-1:0];
            waited = 0;
            while (arvalid) begin
                @(posedge clk);
                if (arready) arvalid <= 1'b0;
                @(negedge clk);
                waited = waited + 1;
            end
            rready = 1'b1;
            while (!rvalid) begin
                @(negedge clk);
                waited = waited + 1;
                if (waited > HANDSHAKE) begin
                    $display("TB_RT_CORE FAIL: read of %h: no response", addr);
                    $finish;
                end
            end
            if (rresp != 2'b00) begin
                $display("TB_RT_CORE FAIL: read of %h answered SLVERR", addr);
                $finish;
            end
            data = rdata;
            @(posedge clk);
            rready <= 1'b0;
        end
    endtask

    // the memory is busy on a pseudo-random third of the clocks
    reg [15:0] lfsr = 16'hace1;
    always @(posedge clk) begin
        lfsr <= {lfsr[14:0], lfsr[15] ^ lfsr[13] ^ lfsr[12] ^ lfsr[10]};
        mem_ready <= lfsr[1:0] != 2'b00 || lfsr[3];
    end

    reg [31:0] regs [0:`RT_SCENE_WORDS-1];
    reg [63:0] writes [0:`RT_AXI_SCENE_WORDS + 2];
    reg [23:0] exp_rgb [0:MAXPIX-1];
    reg [15:0] exp_kcu [0:MAXPIX-1];
    reg [31:0] exp_depth [0:MAXPIX-1];
    reg [31:0] exp_normal [0:3*MAXPIX-1];
    reg [23:0] got_rgb [0:MAXPIX-1];

    // a Q16.16 word as binary32, rounded to nearest even
    function [31:0] q16_to_f32(input [31:0] q);
        reg        s;
        reg [31:0] m, rem, half;
        reg [24:0] mant;
        reg [7:0]  ex;
        integer    msb, i, sh;
        begin
            if (q == 32'd0) begin
                q16_to_f32 = 32'd0;
            end else begin
                s = q[31];
                m = s ? 32'd0 - q : q;
                msb = 0;
                for (i = 0; i < 32; i = i + 1) if (m[i]) msb = i;
                ex = msb - 16 + 127;
                if (msb <= 23) begin
                    mant = m << (23 - msb);
                end else begin
                    sh = msb - 23;
                    mant = m >> sh;
                    rem = m & ((32'd1 << sh) - 1);
                    half = 32'd1 << (sh - 1);
                    if (rem > half || (rem == half && mant[0])) mant = mant + 1;
                    if (mant[24]) begin
                        mant = mant >> 1;
                        ex = ex + 1;
                    end
                end
                q16_to_f32 = {s, ex, mant[22:0]};
            end
        end
    endfunction

    reg [8*512-1:0] dir, path;
    // the counters `passed` and `failed`, and the waveform +vcd=PATH asks for
    `include "check.vh"
    integer w, h, n, i, cycles, bound, fd, nwrites, polls;
    reg [31:0] depth, nx, ny, nz, ctrl, hi;

    task check_word(input [8*16-1:0] what, input integer pix, input [31:0] got,
                    input [31:0] want);
        begin
            if (got === want) passed = passed + 1;
            else begin
                failed = failed + 1;
                if (failed <= 10)
                    $display("pixel (%0d, %0d) %0s: core %h, model %h", pix % w, pix / w, what,
                        got, want);
            end
        end
    endtask

    // every record the memory port gives, checked against the model as it arrives; the
    // clocks a record waited (each holds the core one clock)
    integer held = 0;
    always @(posedge clk) begin
        if (!rst && mem_valid && !mem_ready) held = held + 1;
        if (!rst && mem_valid && mem_ready) begin
            if (mem_index != n) begin
                failed = failed + 1;
                $display("pixel %0d came as record %0d", n, mem_index);
            end
            if (!mem_aovs) begin
                failed = failed + 1;
                $display("pixel %0d: the frame did not take AOVS", n);
            end
            got_rgb[n] = mem_rgb;
            check_word("colour", n, {8'd0, mem_rgb}, {8'd0, exp_rgb[n]});
            check_word("kcu116", n, {16'd0, mem_kcu116}, {16'd0, exp_kcu[n]});
            depth = mem_obj != 8'hff ? q16_to_f32(mem_t) : 32'h7f80_0000;
            check_word("depth", n, depth, exp_depth[n]);
            nx = mem_obj != 8'hff ? q16_to_f32(mem_n[31:0]) : 32'd0;
            ny = mem_obj != 8'hff ? q16_to_f32(mem_n[63:32]) : 32'd0;
            nz = mem_obj != 8'hff ? q16_to_f32(mem_n[95:64]) : 32'd0;
            check_word("normal x", n, nx, exp_normal[3 * n]);
            check_word("normal y", n, ny, exp_normal[3 * n + 1]);
            check_word("normal z", n, nz, exp_normal[3 * n + 2]);
            n = n + 1;
        end
    end

    initial begin
        if (!$value$plusargs("vec=%s", dir)) begin
            $display("TB_RT_CORE FAIL: no +vec=DIR (an `fpgfx vectors render` directory)");
            $finish;
        end
        $sformat(path, "%0s/scene_regs.hex", dir);
        $readmemh(path, regs);
        w = regs[`RT_HDR_WIDTH];
        h = regs[`RT_HDR_HEIGHT];
        if (w * h > MAXPIX || w * h == 0) begin
            $display("TB_RT_CORE FAIL: a %0dx%0d frame (this bench holds %0d pixels)", w, h,
                MAXPIX);
            $finish;
        end
        $sformat(path, "%0s/expected_rgb888.hex", dir);
        $readmemh(path, exp_rgb, 0, w * h - 1);
        $sformat(path, "%0s/expected_kcu116.hex", dir);
        $readmemh(path, exp_kcu, 0, w * h - 1);
        $sformat(path, "%0s/expected_depth.hex", dir);
        $readmemh(path, exp_depth, 0, w * h - 1);
        $sformat(path, "%0s/expected_normal.hex", dir);
        $readmemh(path, exp_normal, 0, 3 * w * h - 1);
        // the scene image, then NUMERIC, AOVS and AP_CTRL (docs/vectors.md)
        nwrites = `RT_AXI_SCENE_WORDS + 3;
        $sformat(path, "%0s/axi_writes.hex", dir);
        $readmemh(path, writes, 0, nwrites - 1);
        n = 0;
        repeat (4) @(posedge clk);
        rst <= 1'b0;
        for (i = 0; i < nwrites; i = i + 1) axi_write(writes[i][63:32], writes[i][31:0]);
        bound = w * h * `RT_OBJ_CAPACITY * `RT_LIGHT_CAPACITY + 10000;  // a slot is N (1 + L)
        ctrl = 32'd0;
        polls = 0;
        while (!ctrl[`RT_AXI_AP_DONE] && polls < bound) begin
            axi_read(`RT_AXI_AP_CTRL, ctrl);
            polls = polls + 1;
        end
        if (!ctrl[`RT_AXI_AP_DONE]) begin
            $display("TB_RT_CORE FAIL: AP_CTRL: no ap_done after %0d polls, %0d of %0d pixels",
                polls, n, w * h);
            $finish;
        end
        axi_read(`RT_AXI_SYS_RT_CYCLES, cycles);
        axi_read(`RT_AXI_SYS_RT_CYCLES + 4, hi);
        if (n != w * h) begin
            failed = failed + 1;
            $display("%0d pixels, expected %0d", n, w * h);
        end
        $sformat(path, "%0s/actual_rgb888.hex", dir);
        fd = $fopen(path, "w");
        $fdisplay(fd, "// fpgfx framebuffer %0dx%0d rgb888", w, h);
        for (i = 0; i < n; i = i + 1) $fdisplay(fd, "%h", got_rgb[i]);
        $fclose(fd);
        $display("tb_rt_vectors: %0d passed, %0d failed", passed, failed);
        if (failed == 0)
            $display("TB_RT_CORE PASS: %0d checks, %0d cycles, %0d held", passed, cycles,
                held);
        else
            $display("TB_RT_CORE FAIL: %0d of %0d checks failed, %0d cycles", failed,
                passed + failed, cycles);
        $finish;
    end
endmodule
`default_nettype wire
