// mul_seq -- a signed multiplier that takes the multiplier's bits one per clock.
//
// Seed 000 ch. 6.5 (the triangle set-up's edge products). The seed's Spartan-3 has four
// MULT18X18 blocks, an iCE40 none: eight combinational 10 x 11 products cost the
// triangle unit about 1 000 LUTs and the longest paths of the block. One product per
// set-up is all a triangle needs, so each product is built by shift and add, one bit of
// b per clock, with an adder as wide as a.
//
// Arithmetic: p = a * b, a AW bits and b BW bits, both two's complement; the product's
// AW + BW bits are exact for every pair. Right-shift form: the accumulator acc (AW + 1
// bits) adds b's bit k times a (its last bit, the sign, times -a), then shifts right
// arithmetically, its low bit entering the top of lo, where b's used bits leave.
//
// Ports: load (one clock) takes b and does the first step (acc = b[0] ? a : 0, no adder);
// each later clock with step high does the next bit, neg marking the last one (b's sign
// bit); a must hold its value from load to the last step (the caller's registers do).
// p is the product after load and BW - 1 steps, and holds while load and step are low.
// Timing: BW clocks from load to p (load included); one carry chain of AW + 1 bits per
// clock.
`default_nettype none
module mul_seq #(
    parameter integer AW = 10,   // bits of a
    parameter integer BW = 11    // bits of b
) (
    input  wire                 clk,
    input  wire                 load,
    input  wire                 step,
    input  wire                 neg,
    input  wire signed [AW-1:0] a,
    input  wire signed [BW-1:0] b,
    output wire signed [AW+BW-1:0] p
);
    generate
        if (AW < 2 || BW < 2) begin : bad_parameter
            mul_seq_needs_operands_of_at_least_2_bits unsupported();
        end
    endgenerate

    reg signed [AW:0]   acc;
    reg        [BW-1:0] lo;

    // the step's sum, one bit wider than acc: acc + a, acc - a (neg) or acc
    wire signed [AW+1:0] ax  = {{2{a[AW-1]}}, a};
    wire signed [AW+1:0] sum = {acc[AW], acc} + (lo[0] ? (neg ? ~ax : ax) : {(AW+2){1'b0}})
                             + {{(AW+1){1'b0}}, lo[0] & neg};
    wire signed [AW+1:0] first = b[0] ? ax : {(AW+2){1'b0}};

    assign p = {acc[AW-1:0], lo};

    always @(posedge clk) begin
        if (load) begin
            acc <= first[AW+1:1];
            lo  <= {first[0], b[BW-1:1]};
        end else if (step) begin
            acc <= sum[AW+1:1];
            lo  <= {sum[0], lo[BW-1:1]};
        end
    end

`ifdef FORMAL
    // After load and BW - 1 steps, the last with neg, p is a * b for any a and b, and it
    // holds while load and step stay low. The caller's contract: a is held from load to
    // the last step, the steps follow load clock after clock, neg marks the last. rst is
    // the proof's own (the unit has no reset): it starts the tracking, nothing else.
    (* anyseq *) reg rst;
    reg f_past = 1'b0;
    reg [$clog2(BW+1):0] f_k;           // bits taken since the last load
    reg signed [AW-1:0]  f_a;
    reg signed [BW-1:0]  f_b;
    always @(posedge clk) begin
        f_past <= 1'b1;
        if (rst) f_k <= 0;
        else if (load) begin
            f_k <= 1;
            f_a <= a;
            f_b <= b;
        end else if (step) f_k <= f_k + 1'b1;
    end
    always @(*) begin
        if (f_k != 0 && f_k < BW && !load) assume (step && a == f_a && neg == (f_k == BW - 1));
        if (step && !load) assume (f_k != 0 && f_k < BW);
    end
    wire signed [AW+BW-1:0] f_want = f_a * f_b;
    always @(*) if (f_past && f_k == BW) assert (p == f_want);
`endif
endmodule
`default_nettype wire
