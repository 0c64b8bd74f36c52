// tb_rt_vectors -- the ray-casting core driven by `fpgfx vectors render` output: the
// scene image (scene_regs.hex) through the configuration port, one frame, and every
// pixel's colour (RGB888 and the KCU116 word), depth and normal against the golden
// model's (expected_rgb888.hex, expected_kcu116.hex, expected_depth.hex,
// expected_normal.hex; docs/vectors.md). Writes the core's frame as
// actual_rgb888.hex beside them, for `fpgfx compare`.
//
// Usage (Icarus): iverilog -g2012 -I hw/rt-core/rtl -I hw/shared-tb -s tb_rt_vectors
//   -o tb.vvp hw/rt-core/tb/tb_rt_vectors.v hw/rt-core/rtl/*.v; vvp -n tb.vvp +vec=DIR
// Prints "TB_RT_CORE PASS: <checks> checks, <cycles> cycles" or "TB_RT_CORE FAIL ...";
// a frame that does not finish within its cycle bound fails naming the pixels received.
// Depth and normal are compared as the model's f32 planes: each Q16.16 word converted to
// binary32, rounded to nearest even (the model's `to_f64() as f32`).
`timescale 1ns / 1ps
`default_nettype none
`include "rt_map.vh"
module tb_rt_vectors;
    localparam integer MAXPIX = 1 << 16;

    reg clk = 1'b0;
    always #5 clk = !clk;
    reg        rst = 1'b1;
    reg        cfg_we = 1'b0;
    reg [8:0]  cfg_addr = 9'd0;
    reg [31:0] cfg_data = 32'd0;
    reg        start = 1'b0;
    wire       busy, done, pix_valid, pix_hit;
    wire [7:0] err, pix_obj;
    wire [15:0] pix_x, pix_y;
    wire [31:0] pix_t;
    wire [95:0] pix_n;
    wire [23:0] pix_rgb;
    wire [15:0] pix_kcu116;
    rt_cast dut (.clk(clk), .rst(rst), .cfg_we(cfg_we), .cfg_addr(cfg_addr),
        .cfg_data(cfg_data), .start(start), .hold(1'b0), .busy(busy), .done(done), .err(err),
        .pix_valid(pix_valid), .pix_x(pix_x), .pix_y(pix_y), .pix_hit(pix_hit),
        .pix_obj(pix_obj), .pix_t(pix_t), .pix_n(pix_n), .pix_rgb(pix_rgb),
        .pix_kcu116(pix_kcu116));

    reg [31:0] regs [0:`RT_SCENE_WORDS-1];
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
    integer w, h, n, i, k, fails, checks, cycles, bound, fd;
    reg [31:0] depth, nx, ny, nz;

    task check(input [8*16-1:0] what, input integer pix, input [31:0] got, input [31:0] want);
        begin
            checks = checks + 1;
            if (got !== want) begin
                fails = fails + 1;
                if (fails <= 10)
                    $display("pixel (%0d, %0d) %0s: core %h, model %h", pix % w, pix / w, what,
                        got, want);
            end
        end
    endtask

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
        fails = 0;
        checks = 0;
        repeat (4) @(posedge clk);
        rst <= 1'b0;
        for (i = 0; i < `RT_SCENE_WORDS; i = i + 1) begin
            @(posedge clk);
            cfg_we <= 1'b1;
            cfg_addr <= i;
            cfg_data <= regs[i];
        end
        @(posedge clk);
        cfg_we <= 1'b0;
        start <= 1'b1;
        @(posedge clk);
        start <= 1'b0;
        cycles = 1;
        n = 0;
        bound = w * h * `RT_OBJ_CAPACITY * `RT_LIGHT_CAPACITY + 10000;  // a slot is N (1 + L)
        while (!done && cycles < bound) begin
            @(posedge clk);
            cycles = cycles + 1;
            if (pix_valid) begin
                k = pix_y * w + pix_x;
                if (k != n) begin
                    fails = fails + 1;
                    $display("pixel %0d came as (%0d, %0d)", n, pix_x, pix_y);
                end
                got_rgb[n] = pix_rgb;
                check("colour", n, {8'd0, pix_rgb}, {8'd0, exp_rgb[n]});
                check("kcu116", n, {16'd0, pix_kcu116}, {16'd0, exp_kcu[n]});
                depth = pix_hit ? q16_to_f32(pix_t) : 32'h7f80_0000;
                check("depth", n, depth, exp_depth[n]);
                nx = q16_to_f32(pix_n[31:0]);
                ny = q16_to_f32(pix_n[63:32]);
                nz = q16_to_f32(pix_n[95:64]);
                check("normal x", n, nx, exp_normal[3 * n]);
                check("normal y", n, ny, exp_normal[3 * n + 1]);
                check("normal z", n, nz, exp_normal[3 * n + 2]);
                n = n + 1;
            end
        end
        if (!done) begin
            $display("TB_RT_CORE FAIL: no done within %0d cycles, %0d of %0d pixels", bound, n,
                w * h);
            $finish;
        end
        if (err != 0) begin
            fails = fails + 1;
            $display("the core refused the scene: err %b (rtl/rt_cast.v)", err);
        end
        if (n != w * h) begin
            fails = fails + 1;
            $display("%0d pixels, expected %0d", n, w * h);
        end
        $sformat(path, "%0s/actual_rgb888.hex", dir);
        fd = $fopen(path, "w");
        $fdisplay(fd, "// fpgfx framebuffer %0dx%0d rgb888", w, h);
        for (i = 0; i < n; i = i + 1) $fdisplay(fd, "%h", got_rgb[i]);
        $fclose(fd);
        if (fails == 0)
            $display("TB_RT_CORE PASS: %0d checks, %0d cycles", checks, cycles);
        else
            $display("TB_RT_CORE FAIL: %0d of %0d checks failed, %0d cycles", fails, checks,
                cycles);
        $finish;
    end
endmodule
`default_nettype wire
