// tri_lane -- one edge function in one lane of the triangle traversal.
//
// Seed 000 ch. 6.5 (the edge functions, stepped incrementally across the bounding box;
// 8-pixel parallel evaluation). tri_unit keeps, per edge and lane, f (the edge's test
// value f = s * e + tl - 1 at the lane's pixel: covered when f >= 0, i.e. f's sign bit
// clear) and r, the same lane's value one row down at the row's first step, so that a
// row wrap is a copy and every clock has at most one carry chain.
//
// Ports: with en, f takes f_in (load), r (wrap: the traversal steps to the next row) or
// f + step (a column step: the caller's step register holds LANES columns in the
// traversal, 2^b columns in INIT's clock b, in which only the lanes with bit b set move);
// r takes f + rs at rinit (INIT's last clock) and r + rs when f wraps. step and rs are
// the caller's registers, shared by the lanes, so every adder's operands are registers.
// neg is f's sign bit (the lane's pixel is not covered by this edge).
// Timing: one clock per operation.
`default_nettype none
module tri_lane (
    input  wire               clk,
    input  wire               en,
    input  wire               load,
    input  wire               wrap,
    input  wire               rinit,
    input  wire signed [20:0] f_in,
    input  wire signed [20:0] step,
    input  wire signed [20:0] rs,
    output wire               neg
);
    reg signed [20:0] f, r;
    wire signed [20:0] fd = load ? f_in : wrap ? r : f + step;
    assign neg = f[20];

    always @(posedge clk) begin
        if (en) f <= fd;
        if (rinit || (en && wrap)) r <= (rinit ? f : r) + rs;
    end
endmodule
`default_nettype wire
