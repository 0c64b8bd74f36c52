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
module fifo36 (
    input  wire        clk,
    input  wire        rst,
    input  wire [37:0] DATA_IN,
    input  wire        DATA_WE,
    input  wire        COMMIT,
    input  wire        DISCARD,
    input  wire        FIFO_NEXT,
    output wire [37:0] DATA_OUT,
    output wire        DATA_VLD,
    output wire        FIFO_FREE,
    output wire        room,
    output wire [9:0]  free_count,
    output wire [9:0]  occupancy
);
    reg [37:0] mem [0:511];
    reg [9:0]  wr_ptr;     // tentative
    reg [9:0]  wr_commit;  // visible to the reader
    reg [9:0]  rd_ptr;     // next RAM word to read
    reg        out_valid;
    reg [37:0] out_data;

    wire [9:0] used_tent = (wr_ptr - rd_ptr) + {9'd0, out_valid};
    wire [9:0] used_comm = (wr_commit - rd_ptr) + {9'd0, out_valid};
    wire       do_write  = DATA_WE & room;
    wire       avail     = wr_commit != rd_ptr;
    wire       do_read   = avail & (~out_valid | FIFO_NEXT);

    assign room       = used_tent != 10'd512;
    assign occupancy  = used_comm;
    assign free_count = 10'd512 - used_comm;
    assign FIFO_FREE  = free_count >= 10'd2;
    assign DATA_VLD   = out_valid;
    assign DATA_OUT   = out_data;

    always @(posedge clk) begin
        if (do_write) mem[wr_ptr[8:0]] <= DATA_IN;
    end

    always @(posedge clk) begin
        if (do_read) out_data <= mem[rd_ptr[8:0]];
    end

    always @(posedge clk) begin
        if (rst) begin
            wr_ptr    <= 10'd0;
            wr_commit <= 10'd0;
            rd_ptr    <= 10'd0;
            out_valid <= 1'b0;
        end else begin
            if (DISCARD) wr_ptr <= wr_commit;
            else if (do_write) wr_ptr <= wr_ptr + 10'd1;
            if (COMMIT) wr_commit <= wr_ptr;
            if (do_read) begin
                rd_ptr    <= rd_ptr + 10'd1;
                out_valid <= 1'b1;
            end else if (FIFO_NEXT) begin
                out_valid <= 1'b0;
            end
        end
    end
endmodule
