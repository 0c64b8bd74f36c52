// frag_fifo -- the 16-deep fragment FIFO between the raster units and the writer.
//
// Seed 000 ch. 6.3 (the fragment FIFO in front of the SDRAM controller: it hides the
// memory's short stalls -- refresh, VGA priority -- from the units). Show-ahead read:
// dout is the oldest entry while empty is low; re pops it. A write into a full FIFO is
// ignored (producers wait for ~full).
//
// Ports: din / we, full; dout / empty / re. Parameters: W bits per entry, AW log2 depth.
// Timing: an entry written in cycle t is visible at dout in cycle t + 1; one write and
// one read per cycle. full and empty are registers (kept beside the pointers from the
// cycle's write and read), so a producer's clock enable and the reader's choice start at
// a flip-flop, not at a comparison of the pointers.
`default_nettype none
module frag_fifo #(
    parameter W  = 27,
    parameter AW = 4
) (
    input  wire         clk,
    input  wire         rst,
    input  wire [W-1:0] din,
    input  wire         we,
    output wire         full,
    output wire [W-1:0] dout,
    output wire         empty,
    input  wire         re
);
    generate
        if (AW < 1 || W < 1) begin : bad_parameter
            frag_fifo_needs_at_least_2_entries_of_1_bit unsupported();
        end
    endgenerate

    reg [W-1:0] mem [0:(1<<AW)-1];
    reg [AW:0]  wp, rp;
    reg         full_r, empty_r;

    wire do_w = we & ~full_r;
    wire do_r = re & ~empty_r;
    // entries held: one short of full, or one
    wire [AW:0] count  = wp - rp;
    wire        nearly = count == (1 << AW) - 1;
    wire        single = count == 1;

    assign empty = empty_r;
    assign full  = full_r;
    assign dout  = mem[rp[AW-1:0]];

    always @(posedge clk) begin
        if (do_w) mem[wp[AW-1:0]] <= din;
    end

    always @(posedge clk) begin
        if (rst) begin
            wp      <= {(AW+1){1'b0}};
            rp      <= {(AW+1){1'b0}};
            full_r  <= 1'b0;
            empty_r <= 1'b1;
        end else begin
            if (do_w) wp <= wp + 1'b1;
            if (do_r) rp <= rp + 1'b1;
            if (do_w != do_r) begin
                full_r  <= do_w & nearly;
                empty_r <= do_r & single;
            end
        end
    end

`ifdef FORMAL
    // From the first reset on: the count (wp - rp) never exceeds the depth, full and
    // empty say what it says, a write into a full FIFO and a read of an empty one change
    // nothing, and any entry comes out as written, in order (an arbitrary pointer f_ptr
    // is followed: every entry written there is f_data).
    reg reset_seen = 1'b0, past_valid = 1'b0;
    always @(posedge clk) begin
        past_valid <= 1'b1;
        if (rst) reset_seen <= 1'b1;
    end
    wire [AW:0] f_count = wp - rp;
    (* anyconst *) reg [AW:0]  f_ptr;
    (* anyconst *) reg [W-1:0] f_data;
    always @(*) if (do_w && wp == f_ptr) assume (din == f_data);
    always @(*) begin
        if (reset_seen) begin
            assert (f_count <= (1 << AW));
            assert (empty == (f_count == 0));
            assert (full == (f_count == (1 << AW)));
            if ((f_ptr - rp) < f_count) assert (mem[f_ptr[AW-1:0]] == f_data);
            if (!empty && rp == f_ptr) assert (dout == f_data);
        end
    end
    always @(posedge clk) begin
        if (reset_seen && past_valid && !$past(rst)) begin
            assert (wp == $past(wp) + ($past(do_w) ? 1'b1 : 1'b0));
            assert (rp == $past(rp) + ($past(do_r) ? 1'b1 : 1'b0));
        end
        if (past_valid && $past(rst)) assert (empty && !full);
    end
`endif
endmodule
`default_nettype wire
