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
module fifo36 (
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
    output wire [$clog2(`FITKIT_FIFO_RECORDS):0] free_count,
    output wire [$clog2(`FITKIT_FIFO_RECORDS):0] occupancy
);
    localparam W     = `FITKIT_RECORD_BITS + 2;         // record + tag
    localparam DEPTH = `FITKIT_FIFO_RECORDS;
    localparam AW    = $clog2(DEPTH);                    // pointers carry one more bit
    localparam [AW:0] DEPTH_C  = DEPTH;
    // Records of the widest packet: what FIFO_FREE promises room for.
    localparam [AW:0] PACKET_C = (`FITKIT_MAX_PACKET_BYTES * 8) / `FITKIT_RECORD_BITS;

    reg [W-1:0] mem [0:DEPTH-1];
    reg [AW:0]  wr_ptr;     // tentative
    reg [AW:0]  wr_commit;  // visible to the reader
    reg [AW:0]  rd_ptr;     // next RAM word to read
    reg         out_valid;
    reg [W-1:0] out_data;

    wire [AW:0] used_tent = (wr_ptr - rd_ptr) + {{AW{1'b0}}, out_valid};
    wire [AW:0] used_comm = (wr_commit - rd_ptr) + {{AW{1'b0}}, out_valid};
    wire        do_write  = DATA_WE & room;
    wire        avail     = wr_commit != rd_ptr;
    wire        do_read   = avail & (~out_valid | FIFO_NEXT);

    assign room       = used_tent != DEPTH_C;
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
        end else begin
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
endmodule
`default_nettype wire
