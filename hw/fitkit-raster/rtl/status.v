// status -- the status block (SPI channel 0x20): counters, flags, the sticky error.
//
// Not in seed 000 (its MCU only polled FIFO_FREE); the layout is docs/rtl.md "Status
// block". All 32 bytes are captured in one cycle (snap, when the address byte 0x20
// completes), so a read is a consistent snapshot however slowly the master clocks it.
//
// Counters (32 bits, wrapping), zeroed by rst and by cnt_clr (a set-up starting):
//   packets    pkt_done strobes: line, triangle and clear packets completed
//   fragments  frag_written strobes: counted fragments the memory accepted
//   line/tri   cycles line_busy / tri_busy is high
//   clear      cycles clr_busy is high (set-up clears, clear packets, CB clears)
//   last       the value of `cycle` at the last done strobe (any packet, set-up included);
//              `cycle` counts clk cycles from the cnt_clr cycle (0 there)
//   max occ    the highest committed input FIFO occupancy, / 2, saturating at 255
// The first error after rst is kept (code, channel, packet index = commits so far);
// later errors are ignored until rst. A decoder error wins over a simultaneous underrun.
//
// Ports: byte_index selects tx_byte = snapshot byte byte_index - 1 (bytes after the
// address), 0 past byte 31.
module status (
    input  wire       clk,
    input  wire       rst,
    input  wire       cnt_clr,
    input  wire       pkt_done,
    input  wire       any_done,
    input  wire       frag_written,
    input  wire       line_busy,
    input  wire       tri_busy,
    input  wire       clr_busy,
    input  wire       commit,
    input  wire [9:0] fifo_free,
    input  wire [9:0] fifo_occ,
    input  wire       busy,
    input  wire       setup_done,
    input  wire       dec_err,
    input  wire [2:0] dec_code,
    input  wire [7:0] dec_chan,
    input  wire       underrun,
    input  wire       snap,
    input  wire [7:0] byte_index,
    output wire [7:0] tx_byte
);
    reg [31:0] packets, fragments, line_cyc, tri_cyc, clr_cyc, cycle, last;
    reg [9:0]  max_occ;
    reg [15:0] commits;
    reg        err;
    reg [2:0]  err_code;
    reg [7:0]  err_chan;
    reg [15:0] err_pkt;
    reg [255:0] snapshot;

    wire [7:0] occ_half = (max_occ[9:1] > 9'd255) ? 8'd255 : max_occ[8:1];
    wire [7:0] flags    = {4'd0, setup_done, fifo_occ == 10'd0, err, busy};
    wire [255:0] block  = {6'd0, fifo_free, flags, 5'd0, err_code, err_chan, err_pkt,
                           packets, fragments, line_cyc, tri_cyc, clr_cyc, last, occ_half};

    wire [4:0] k = byte_index[4:0] - 5'd1;
    assign tx_byte = (byte_index >= 8'd1 && byte_index <= 8'd32)
                   ? snapshot[8'd255 - {k, 3'd0} -: 8] : 8'd0;

    always @(posedge clk) begin
        if (rst) begin
            packets <= 32'd0; fragments <= 32'd0; line_cyc <= 32'd0; tri_cyc <= 32'd0;
            clr_cyc <= 32'd0; cycle <= 32'd0; last <= 32'd0; max_occ <= 10'd0;
            commits <= 16'd0; err <= 1'b0; err_code <= 3'd0; err_chan <= 8'd0;
            err_pkt <= 16'd0; snapshot <= 256'd0;
        end else begin
            if (cnt_clr) begin
                packets <= 32'd0; fragments <= 32'd0; line_cyc <= 32'd0; tri_cyc <= 32'd0;
                clr_cyc <= 32'd0; cycle <= 32'd0; last <= 32'd0; max_occ <= fifo_occ;
            end else begin
                cycle <= cycle + 32'd1;
                if (pkt_done) packets <= packets + 32'd1;
                if (frag_written) fragments <= fragments + 32'd1;
                if (line_busy) line_cyc <= line_cyc + 32'd1;
                if (tri_busy) tri_cyc <= tri_cyc + 32'd1;
                if (clr_busy) clr_cyc <= clr_cyc + 32'd1;
                if (any_done) last <= cycle;
                if (fifo_occ > max_occ) max_occ <= fifo_occ;
            end
            if (commit) commits <= commits + 16'd1;
            if (!err && (dec_err || underrun)) begin
                err      <= 1'b1;
                err_code <= dec_err ? dec_code : 3'd6;
                err_chan <= dec_err ? dec_chan : 8'h30;
                err_pkt  <= commits;
            end
            if (snap) snapshot <= block;
        end
    end
endmodule
