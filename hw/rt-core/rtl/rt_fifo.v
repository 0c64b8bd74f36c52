// rt_fifo -- a synchronous first-in first-out queue whose head is readable without a
// pop (show-ahead): where the frame core's fixed-latency pipelines meet at a time that
// is fixed too, but not the same for both sides (the shadow rays wait for their slot in
// the intersection unit; a pixel's light terms and its shadow bits wait for each other).
//
// Why no full flag to the writer: every writer here is a pipeline that cannot stall on
// its own, and every reader runs on the same fixed schedule, so the occupancy has a
// bound the instantiating module computes (rt_cast, rt_shade say how). A push into a
// full queue or a pop from an empty one is a design error, not back-pressure: `ovf` and
// `unf` stick high until reset, the simulation stops with a message, and the formal
// properties below prove that count, full and empty agree with the pushes and pops.
//
// Ports: push with din (ignored while full: ovf), pop (ignored while empty: unf), dout
// (the head, valid while !empty), empty, count, ovf, unf. A word pushed at one edge is
// the head after it, so it can be popped at the next. Push and pop in one clock keep the
// count.
// Timing: no latency beyond the write; one push and one pop per clock.
// Parameters: W >= 1 bits per word; AW >= 1, 2^AW words.
`default_nettype none
module rt_fifo #(
    parameter integer W = 32,
    parameter integer AW = 4
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         push,
    input  wire [W-1:0] din,
    input  wire         pop,
    output wire [W-1:0] dout,
    output wire         empty,
    output wire [AW:0]  count,
    output reg          ovf,
    output reg          unf
);
    generate
        if (W < 1 || AW < 1 || AW > 16) begin : bad_parameter
            rt_fifo_parameter_out_of_range unsupported();
        end
    endgenerate

    reg [W-1:0]  mem [0:(1 << AW) - 1];
    reg [AW:0]   wp, rp;  // one bit wider than the address: full when the tops differ
    wire         full = wp == {~rp[AW], rp[AW-1:0]};
    wire         do_push = push && !full;
    wire         do_pop = pop && !empty;
    assign empty = wp == rp;
    assign count = wp - rp;
    assign dout = mem[rp[AW-1:0]];

    always @(posedge clk) begin
        if (do_push) mem[wp[AW-1:0]] <= din;
        if (rst) begin
            wp <= {AW + 1{1'b0}};
            rp <= {AW + 1{1'b0}};
            ovf <= 1'b0;
            unf <= 1'b0;
        end else begin
            if (do_push) wp <= wp + 1'b1;
            if (do_pop) rp <= rp + 1'b1;
            if (push && full) ovf <= 1'b1;
            if (pop && empty) unf <= 1'b1;
        end
    end

`ifndef SYNTHESIS
`ifndef FORMAL
    always @(posedge clk) begin
        if (!rst && ((push && full) || (pop && empty))) begin
            $display("rt_fifo %m: %s at count %0d", push && full ? "push into a full queue"
                     : "pop from an empty queue", count);
            $stop;
        end
    end
`endif
`endif

`ifdef FORMAL
    // from the first reset on: the count never exceeds the depth, empty and full say
    // what the count says, a push and a pop move it by their difference, a word pushed
    // into an empty queue is its head, and the error flags stick
    reg reset_seen = 1'b0, past_valid = 1'b0;
    always @(posedge clk) begin
        past_valid <= 1'b1;
        if (rst) reset_seen <= 1'b1;
    end
    always @(*) begin
        if (reset_seen) begin
            assert (count <= (1 << AW));
            assert (empty == (count == 0));
            assert (full == (count == (1 << AW)));
        end
    end
    always @(posedge clk) begin
        if (reset_seen && !$past(rst)) begin
            assert (count == $past(count) + ($past(do_push) ? 1 : 0) - ($past(do_pop) ? 1 : 0));
            assert (ovf == ($past(ovf) || ($past(push) && $past(full))));
            assert (unf == ($past(unf) || ($past(pop) && $past(empty))));
            if ($past(do_push) && $past(empty)) assert (dout == $past(din));
        end
        if (past_valid && $past(rst)) assert (empty && !ovf && !unf);
    end
`endif
endmodule
`default_nettype wire
