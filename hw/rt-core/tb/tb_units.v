// tb_units -- the core's Q16.16 arithmetic units under a second simulator: random and
// edge operands through rt_math_top with the clock enable dropped at random, every result
// checked against a reference computed here from the operands with wide integer
// arithmetic (not read back from the RTL), and every unit's latency.
//
// The Rust differential tests (rt-core-rtl-sim) hold the same units to the golden model
// itself under Verilator; this bench shows Icarus reads the RTL the same way.
`timescale 1ns / 1ps
`default_nettype none
module tb_units;
    parameter integer N = 4000;   // operand sets (run-tests.sh's self-test runs fewer)

    reg clk = 1'b0;
    always #5 clk = ~clk;
    reg rst = 1'b1;
    reg ce = 1'b1;
    reg in_valid = 1'b0;
    reg [31:0] a0 = 0, a1 = 0, a2 = 0, b0 = 0, b1 = 0, b2 = 0;

    wire mul_v, mul_rn_v, dot2_v, dot3_v, div_v, sqrt_v, rsqrt_v;
    wire [31:0] mul_y, mul_rn_y, dot2_y, dot3_y, div_y, sqrt_y, rsqrt_y;
    wire mul_sat, mul_rn_sat, dot2_sat, dot3_sat, div_sat, rsqrt_sat;

    rt_math_top dut (
        .clk(clk), .rst(rst), .ce(ce), .in_valid(in_valid),
        .a0(a0), .a1(a1), .a2(a2), .b0(b0), .b1(b1), .b2(b2),
        .mul_v(mul_v), .mul_y(mul_y), .mul_sat(mul_sat),
        .mul_rn_v(mul_rn_v), .mul_rn_y(mul_rn_y), .mul_rn_sat(mul_rn_sat),
        .dot2_v(dot2_v), .dot2_y(dot2_y), .dot2_sat(dot2_sat),
        .dot3_v(dot3_v), .dot3_y(dot3_y), .dot3_sat(dot3_sat),
        .div_v(div_v), .div_y(div_y), .div_sat(div_sat),
        .sqrt_v(sqrt_v), .sqrt_y(sqrt_y),
        .rsqrt_v(rsqrt_v), .rsqrt_y(rsqrt_y), .rsqrt_sat(rsqrt_sat)
    );

    `include "check.vh"

    // the operands of every set, and the enabled cycle it went in
    reg [31:0] A0 [0:N-1], A1 [0:N-1], A2 [0:N-1], B0 [0:N-1], B1 [0:N-1], B2 [0:N-1];
    integer at [0:N-1];
    integer cyc = 0;

    // ---- references ----------------------------------------------------------------
    function [32:0] clamp(input signed [127:0] v);  // {sat, word}
        if (v > 128'sd2147483647) clamp = {1'b1, 32'h7fffffff};
        else if (v < -128'sd2147483648) clamp = {1'b1, 32'h80000000};
        else clamp = {1'b0, v[31:0]};
    endfunction

    function signed [127:0] w(input [31:0] x);
        w = {{96{x[31]}}, x};
    endfunction

    function [63:0] isqrt(input [63:0] n);
        reg [63:0] r, bit_;
        reg [63:0] m;
        begin
            m = n;
            r = 0;
            bit_ = 64'd1 << 62;
            while (bit_ > m) bit_ = bit_ >> 2;
            while (bit_ != 0) begin
                if (m >= r + bit_) begin
                    m = m - (r + bit_);
                    r = (r >> 1) + bit_;
                end else r = r >> 1;
                bit_ = bit_ >> 2;
            end
            isqrt = r;
        end
    endfunction

    function [32:0] ref_of(input integer unit, input integer i);
        reg signed [127:0] p;
        reg [63:0] r;
        begin
            case (unit)
                0: ref_of = clamp((w(A0[i]) * w(B0[i])) >>> 16);
                1: ref_of = clamp((w(A0[i]) * w(B0[i]) + 128'sd32768) >>> 16);
                2: ref_of = clamp((w(A0[i]) * w(B0[i]) + w(A1[i]) * w(B1[i]) + 128'sd32768) >>> 16);
                3: ref_of = clamp((w(A0[i]) * w(B0[i]) + w(A1[i]) * w(B1[i])
                                   + w(A2[i]) * w(B2[i]) + 128'sd32768) >>> 16);
                4: begin
                    if (B0[i] == 0) ref_of = A0[i][31] ? {1'b1, 32'h80000000} : {1'b1, 32'h7fffffff};
                    else begin
                        // Verilog's signed division truncates toward zero, as the model's
                        p = (w(A0[i]) <<< 16) / w(B0[i]);
                        ref_of = clamp(p);
                    end
                end
                5: begin
                    r = (isqrt({32'd0, A0[i]} << 18) + 1) >> 1;
                    ref_of = $signed(A0[i]) <= 0 ? 33'd0 : {1'b0, r[31:0]};
                end
                default: begin
                    r = $signed(A0[i]) <= 0 ? 64'd0 : (isqrt((64'd1 << 50) / A0[i]) + 1) >> 1;
                    ref_of = $signed(A0[i]) <= 0 ? {1'b1, 32'h7fffffff} : {1'b0, r[31:0]};
                end
            endcase
        end
    endfunction

    // ---- checking, per unit, as results come out -------------------------------------
    integer got_n [0:6];
    integer u;
    initial for (u = 0; u < 7; u = u + 1) got_n[u] = 0;
    reg [8*48-1:0] what;
    localparam [7*32-1:0] LAT = {32'd79, 32'd27, 32'd35, 32'd4, 32'd4, 32'd4, 32'd4};

    task take(input integer unit, input valid, input [31:0] y, input sat, input has_sat);
        reg [32:0] r;
        integer i;
        begin
            if (valid) begin
                i = got_n[unit];
                r = ref_of(unit, i);
                $sformat(what, "unit %0d set %0d: got %h sat %b, want %h sat %b, %0d cycles", unit, i, y, sat, r[31:0], r[32], cyc - at[i] + 1);
                check(y == r[31:0] && (!has_sat || sat == r[32])
                      && cyc - at[i] + 1 == LAT[32*unit +: 32], what);
                got_n[unit] = i + 1;
            end
        end
    endtask

    always @(posedge clk) begin
        if (!rst && ce) begin
            #1;
            cyc = cyc + 1;
            take(0, mul_v, mul_y, mul_sat, 1);
            take(1, mul_rn_v, mul_rn_y, mul_rn_sat, 1);
            take(2, dot2_v, dot2_y, dot2_sat, 1);
            take(3, dot3_v, dot3_y, dot3_sat, 1);
            take(4, div_v, div_y, div_sat, 1);
            take(5, sqrt_v, sqrt_y, 1'b0, 0);
            take(6, rsqrt_v, rsqrt_y, rsqrt_sat, 1);
        end
    end

    // ---- stimulus ----------------------------------------------------------------------
    integer seed = 7;
    function [31:0] word(input integer dummy);
        reg [31:0] r;
        begin
            r = $random(seed);
            case (r[2:0])
                0: word = 32'h80000000;
                1: word = 32'h7fffffff;
                2: word = {{16{r[31]}}, r[31:16]};
                3: word = 32'd1 << r[8:4];
                default: word = $random(seed);
            endcase
        end
    endfunction

    integer k;
    reg [31:0] rnd;
    initial begin
        repeat (4) @(negedge clk);
        rst = 1'b0;
        k = 0;
        while (k < N) begin
            @(negedge clk);
            rnd = $random(seed);
            ce = rnd[3:0] != 0;
            in_valid = rnd[6:4] != 0;
            A0[k] = word(0); A1[k] = word(0); A2[k] = word(0);
            B0[k] = word(0); B1[k] = word(0); B2[k] = word(0);
            if (rnd[10:8] == 0) B0[k] = 0;
            a0 = A0[k]; a1 = A1[k]; a2 = A2[k]; b0 = B0[k]; b1 = B1[k]; b2 = B2[k];
            at[k] = cyc + 1;
            if (ce && in_valid) k = k + 1;
        end
        @(negedge clk);
        in_valid = 1'b0;
        ce = 1'b1;
        repeat (100) @(negedge clk);
        for (u = 0; u < 7; u = u + 1) begin
            $sformat(what, "unit %0d: %0d results of %0d", u, got_n[u], N);
            check(got_n[u] == N, what);
        end
        $display("tb_units: %0d passed, %0d failed", passed, failed);
        if (failed != 0) $fatal(1, "tb_units failed");
        $finish;
    end
endmodule
`default_nettype wire
