// fifo36 -- the 512 x 36 input FIFO (+2 tag bits), with packet commit / discard.
//
// Seed 000 ch. 6.2 (FIFO36: RAMB16_S36_S36 between the SPI decoder and the units). The
// seed's interface is kept: DATA_IN / DATA_WE write, DATA_OUT / DATA_VLD / FIFO_NEXT is a
// show-ahead read (DATA_OUT is the oldest record while DATA_VLD is high; FIFO_NEXT pops
// it), FIFO_FREE is the back-pressure flag the MCU polls. Added for whole packets: writes
// go to a tentative write pointer and become visible to the reader only on COMMIT;
// DISCARD drops everything written since the last COMMIT. A bad packet therefore never
// reaches a unit.
//
// Ports
//   DATA_IN[37:36] tag (the SPI channel, 0 set-up, 1 line, 2 triangle, 3 clear),
//   DATA_IN[35:0] the record. DATA_WE is ignored while `room` is low (the caller counts
//   that as an overrun). COMMIT and DISCARD must not come in the same cycle as DATA_WE.
//   FIFO_FREE: at least 2 committed-free records (one whole packet).
//   free_count: 512 - occupancy (0..512). occupancy: committed records, the one in the
//   output register included.
//
// Storage: `mem` is written and read only by the two clocked blocks below (synchronous
// read, no reset), so yosys maps it to block RAM (five 512 x 8 EBRs on iCE40).
// Timing: a committed record reaches DATA_OUT 2 cycles after COMMIT (pointer, RAM read);
// back-to-back records come one per cycle.
// Depth, record width and the FIFO_FREE threshold are the generated map's
// (fitkit_map.vh): the host sizes its writes by them.
`default_nettype none
`include "fitkit_map.vh"
module fifo36 #(
    // records held; the block uses the map's, a proof a small power of two (the
    // properties hold for any)
    parameter integer DEPTH = `FITKIT_FIFO_RECORDS
) (
    input  wire        clk,
    input  wire        rst,
    input  wire [`FITKIT_RECORD_BITS+1:0] DATA_IN,
    input  wire        DATA_WE,
    input  wire        COMMIT,
    input  wire        DISCARD,
    input  wire        FIFO_NEXT,
    output wire [`FITKIT_RECORD_BITS+1:0] DATA_OUT,
    output wire        DATA_VLD,
    output wire        FIFO_FREE,
    output wire        room,
    output wire [$clog2(DEPTH):0] free_count,
    output wire [$clog2(DEPTH):0] occupancy
);
    localparam W     = `FITKIT_RECORD_BITS + 2;         // record + tag
    localparam AW    = $clog2(DEPTH);                    // pointers carry one more bit
    localparam [AW:0] DEPTH_C  = DEPTH[AW:0];
    // Records of the widest packet: what FIFO_FREE promises room for.
    localparam [AW:0] PACKET_C = (`FITKIT_MAX_PACKET_BYTES * 8) / `FITKIT_RECORD_BITS;
    generate
        if (DEPTH < 4 || (1 << AW) != DEPTH) begin : bad_parameter
            fifo36_depth_not_a_power_of_two_of_at_least_4 unsupported();
        end
    endgenerate

    reg [W-1:0] mem [0:DEPTH-1];
    reg [AW:0]  wr_ptr;     // tentative
    reg [AW:0]  wr_commit;  // visible to the reader
    reg [AW:0]  rd_ptr;     // next RAM word to read
    reg         out_valid;
    reg [W-1:0] out_data;
    // Records held, the output register's included: tentative and committed. Kept as
    // counters beside the pointers, so room and the flags are a comparison of a register
    // (no pointer difference in the path to DATA_WE's enables).
    reg [AW:0]  used_tent, used_comm;
    // used_tent != DEPTH as a flip-flop of its own: the decoder's write strobe and the
    // counts' updates both wait on it
    reg         room_r;

    wire        do_write  = DATA_WE & room_r;
    wire        avail     = wr_commit != rd_ptr;
    wire        do_read   = avail & (~out_valid | FIFO_NEXT);
    wire        take      = FIFO_NEXT & out_valid;   // a record leaves
    // The counts' candidate next values and flags, each from registers alone; the
    // strobes (a write, a take, COMMIT, DISCARD) only choose among them, so DATA_WE's
    // and FIFO_NEXT's paths meet no carry chain.
    wire [AW:0] tent_up   = used_tent + 1'b1;
    wire [AW:0] tent_dn   = used_tent - 1'b1;
    wire [AW:0] comm_dn   = used_comm - 1'b1;
    wire        tent_last = used_tent == DEPTH_C - 1'b1;   // one write from full
    wire        comm_full = used_comm == DEPTH_C;

    assign room       = room_r;
    assign occupancy  = used_comm;
    assign free_count = DEPTH_C - used_comm;
    assign FIFO_FREE  = free_count >= PACKET_C;
    assign DATA_VLD   = out_valid;
    assign DATA_OUT   = out_data;

    always @(posedge clk) begin
        if (do_write) mem[wr_ptr[AW-1:0]] <= DATA_IN;
    end

    always @(posedge clk) begin
        if (do_read) out_data <= mem[rd_ptr[AW-1:0]];
    end

    always @(posedge clk) begin
        if (rst) begin
            wr_ptr    <= {(AW+1){1'b0}};
            wr_commit <= {(AW+1){1'b0}};
            rd_ptr    <= {(AW+1){1'b0}};
            out_valid <= 1'b0;
            used_tent <= {(AW+1){1'b0}};
            used_comm <= {(AW+1){1'b0}};
            room_r    <= 1'b1;
        end else begin
            // the counts follow the pointers: a write adds a tentative record, COMMIT
            // makes the tentative ones committed, DISCARD drops them, a take removes one
            if (DISCARD) begin
                used_tent <= take ? comm_dn : used_comm;
                room_r    <= take | ~comm_full;
            end else if (do_write & ~take) begin
                used_tent <= tent_up;
                room_r    <= ~tent_last;
            end else if (~do_write & take) begin
                used_tent <= tent_dn;
                room_r    <= 1'b1;
            end
            if (COMMIT) used_comm <= take ? tent_dn : used_tent;
            else if (take) used_comm <= comm_dn;
            if (DISCARD) wr_ptr <= wr_commit;
            else if (do_write) wr_ptr <= wr_ptr + 1'b1;
            if (COMMIT) wr_commit <= wr_ptr;
            if (do_read) begin
                rd_ptr    <= rd_ptr + 1'b1;
                out_valid <= 1'b1;
            end else if (FIFO_NEXT) begin
                out_valid <= 1'b0;
            end
        end
    end

`ifdef FORMAL
    // The contract: COMMIT and DISCARD never come with DATA_WE, nor with each other (the
    // decoder gives one of them when CS_n rises, after the packet's last record).
    always @(*) assume (!(DATA_WE && (COMMIT || DISCARD)) && !(COMMIT && DISCARD));

    // From the first reset on:
    //  - occupancy: committed records never exceed tentative ones, nor those the depth;
    //    room and FIFO_FREE say what the counts say;
    //  - commit and discard: only COMMIT moves the reader's end (to the tentative one),
    //    DISCARD takes the tentative end back to it, a write without room is dropped;
    //  - data: any record, committed, comes out as written, in order (one record, at
    //    an arbitrary pointer f_ptr, is followed: every record written there is f_data).
    reg reset_seen = 1'b0, past_valid = 1'b0;
    always @(posedge clk) begin
        past_valid <= 1'b1;
        if (rst) reset_seen <= 1'b1;
    end
    wire [AW:0] f_tent = wr_ptr - rd_ptr;
    wire [AW:0] f_comm = wr_commit - rd_ptr;
    // the counters are the pointers' differences (with the output register's record)
    always @(*) if (reset_seen) begin
        assert (used_tent == f_tent + {{AW{1'b0}}, out_valid});
        assert (used_comm == f_comm + {{AW{1'b0}}, out_valid});
    end
    (* anyconst *) reg [AW:0]  f_ptr;
    (* anyconst *) reg [W-1:0] f_data;
    always @(*) if (do_write && wr_ptr == f_ptr) assume (DATA_IN == f_data);
    // f_ptr is written and not yet read: in [rd_ptr, wr_ptr)
    wire        f_held = (f_ptr - rd_ptr) < f_tent;
    always @(*) begin
        if (reset_seen) begin
            assert (f_comm <= f_tent);
            // in one more bit: the tentative records and the output register's
            assert ({1'b0, f_tent} + {{(AW+1){1'b0}}, out_valid} <= {1'b0, DEPTH_C});
            assert (occupancy <= DEPTH_C && free_count == DEPTH_C - occupancy);
            assert (room == (used_tent != DEPTH_C));
            assert (FIFO_FREE == (free_count >= PACKET_C));
            if (f_held) assert (mem[f_ptr[AW-1:0]] == f_data);
            if (out_valid && rd_ptr - 1'b1 == f_ptr) assert (DATA_OUT == f_data);
        end
    end
    always @(posedge clk) begin
        if (reset_seen && past_valid && !$past(rst)) begin
            if ($past(COMMIT)) assert (wr_commit == $past(wr_ptr));
            else assert (wr_commit == $past(wr_commit));
            if ($past(DISCARD)) assert (wr_ptr == $past(wr_commit));
            if ($past(DATA_WE) && !$past(room)) assert (wr_ptr == $past(wr_ptr));
            // a record is read only once committed
            if ($past(do_read)) assert ($past(f_comm) != 0);
        end
        if (past_valid && $past(rst)) assert (occupancy == 0 && !DATA_VLD && room);
    end
`endif
endmodule
`default_nettype wire
