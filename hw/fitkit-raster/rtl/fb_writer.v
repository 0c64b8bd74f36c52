// fb_writer -- fragments to the external memory port, frame clipping, read arbitration.
//
// Seed 000 ch. 6.3 (SDRAM controller interface: the framebuffer at y * 512 + x, one
// RGB332 byte per pixel). The request register (mem_addr, mem_wdata, mem_we, mem_re) is
// loaded only when it is empty or its request is being accepted (asserted with mem_wait
// low), so a request waiting on mem_wait is held unchanged, as the memory expects.
// A read-back request (rd_req) has priority over fragments: it comes at most once per
// SPI byte and must not underrun. Fragments outside the frame (x > wm1 or y > hm1) are
// popped and dropped without a memory cycle.
//
// Fragment format (frag_dout): {counted, col[7:0], y[8:0], x[8:0]}; "counted" is 0 for
// the clear unit's fragments, which frag_written does not count.
//
// Ports: frag_dout / frag_empty / frag_re to frag_fifo; rd_req / rd_addr / rd_ack from
// readback (rd_ack: the request was loaded); rd_valid / rd_data the read's byte, the
// cycle after acceptance; frag_written a counted fragment accepted by the memory;
// write_pending a write is in the request register.
// Timing: one request per cycle while mem_wait is low; a fragment popped in cycle t is
// on the port in cycle t + 1.
`default_nettype none
module fb_writer (
    input  wire        clk,
    input  wire        rst,
    input  wire [8:0]  wm1,
    input  wire [8:0]  hm1,
    input  wire [26:0] frag_dout,
    input  wire        frag_empty,
    output wire        frag_re,
    input  wire        rd_req,
    input  wire [17:0] rd_addr,
    output wire        rd_ack,
    output reg         rd_valid,
    output wire [7:0]  rd_data,
    output wire        frag_written,
    output wire        write_pending,
    output wire [17:0] mem_addr,
    output wire [7:0]  mem_wdata,
    output wire        mem_we,
    output wire        mem_re,
    input  wire [7:0]  mem_rdata,
    input  wire        mem_wait
);
    reg        req_v, req_w, req_cnt;
    reg [17:0] req_addr;
    reg [7:0]  req_data;

    wire       accept = req_v & ~mem_wait;
    wire       load   = ~req_v | accept;
    wire [8:0] fx     = frag_dout[8:0];
    wire [8:0] fy     = frag_dout[17:9];
    wire       in_fr  = (fx <= wm1) & (fy <= hm1);

    assign rd_ack        = load & rd_req;
    assign frag_re       = load & ~rd_req & ~frag_empty;
    assign rd_data       = mem_rdata;
    assign frag_written  = accept & req_w & req_cnt;
    assign write_pending = req_v & req_w;
    assign mem_addr      = req_addr;
    assign mem_wdata     = req_data;
    assign mem_we        = req_v & req_w;
    assign mem_re        = req_v & ~req_w;

    always @(posedge clk) begin
        if (rst) begin
            req_v    <= 1'b0;
            req_w    <= 1'b0;
            req_cnt  <= 1'b0;
            req_addr <= 18'd0;
            req_data <= 8'd0;
            rd_valid <= 1'b0;
        end else begin
            rd_valid <= accept & ~req_w;
            if (load) begin
                if (rd_req) begin
                    req_v    <= 1'b1;
                    req_w    <= 1'b0;
                    req_cnt  <= 1'b0;
                    req_addr <= rd_addr;
                end else begin
                    // the fragment is taken whatever its place and only req_v waits on
                    // the frame test, so no comparison lies between the FIFO's block
                    // RAM and the request register's enables
                    req_v    <= ~frag_empty & in_fr;
                    req_w    <= 1'b1;
                    req_cnt  <= frag_dout[26];
                    req_addr <= {fy, fx};
                    req_data <= frag_dout[25:18];
                end
            end
        end
    end
endmodule
`default_nettype wire
