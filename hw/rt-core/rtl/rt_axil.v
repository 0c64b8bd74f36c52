// rt_axil -- an AXI4-Lite slave port turned into one register access at a time: the bus
// side of the ray-casting core's device (seed 002's ViRAY is an HLS block whose
// `s_axilite` bundle a MicroBlaze drives; protocol::axi_lite is its map).
//
// Why a separate module: the AXI handshakes (address and data of a write arriving in
// either order, a response held until taken, reads and writes competing) are the same
// for every register behind them, and their rules are properties a solver can prove
// once (below); the map's decode and the HLS control semantics live in rt_regs.
//
// Behaviour: AW and W are taken independently, each held until the write's response
// has been taken; AR likewise until its read's response. With a write (both halves) and
// a read waiting, they alternate. An access is a pulse on `req` (req_wr, req_addr,
// req_data), answered by `ack` (ack_err, ack_data) one or more clocks later; no second
// request is issued before the ack. A write whose strobes are not all set, or an access
// to an address that is not word-aligned, is answered SLVERR here without a request:
// every register of the map is one whole word. The response is OKAY or SLVERR (2'b10),
// as `ack_err` says. AWPROT and ARPROT are not used.
//
// Ports: s_axi_* (AXI4-Lite slave, AW address bits); req, req_wr, req_addr, req_data;
// ack, ack_err, ack_data.
// Timing: a write's response 2 clocks after its later half at the earliest, a read's 2
// after its address (1 to the request, 1 to the ack at least); one access in flight.
// Parameters: AW 3..32 address bits.
`default_nettype none
module rt_axil #(
    parameter integer AW = 21
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          s_axi_awvalid,
    output wire          s_axi_awready,
    input  wire [AW-1:0] s_axi_awaddr,
    input  wire [2:0]    s_axi_awprot,
    input  wire          s_axi_wvalid,
    output wire          s_axi_wready,
    input  wire [31:0]   s_axi_wdata,
    input  wire [3:0]    s_axi_wstrb,
    output reg           s_axi_bvalid,
    input  wire          s_axi_bready,
    output reg  [1:0]    s_axi_bresp,
    input  wire          s_axi_arvalid,
    output wire          s_axi_arready,
    input  wire [AW-1:0] s_axi_araddr,
    input  wire [2:0]    s_axi_arprot,
    output reg           s_axi_rvalid,
    input  wire          s_axi_rready,
    output reg  [31:0]   s_axi_rdata,
    output reg  [1:0]    s_axi_rresp,
    output reg           req,
    output reg           req_wr,
    output reg  [AW-1:0] req_addr,
    output reg  [31:0]   req_data,
    input  wire          ack,
    input  wire          ack_err,
    input  wire [31:0]   ack_data
);
    generate
        if (AW < 3 || AW > 32) begin : bad_parameter
            rt_axil_parameter_out_of_range unsupported();
        end
    endgenerate

    localparam [1:0] OKAY = 2'b00, SLVERR = 2'b10;

    // the halves taken, waiting for their access and then for the response to be taken
    reg          aw_full, w_full, ar_full;
    reg [AW-1:0] aw_addr, ar_addr;
    reg [31:0]   w_data;
    reg [3:0]    w_strb;
    reg          inflight;   // a request is out, its ack not yet back
    reg          wr_done;    // the write has been answered (response out)
    reg          rd_done;
    reg          last_wr;    // the last access was a write: a read goes first now

    assign s_axi_awready = !aw_full;
    assign s_axi_wready = !w_full;
    assign s_axi_arready = !ar_full;

    wire wr_ready = aw_full && w_full && !wr_done;
    wire rd_ready = ar_full && !rd_done;
    wire pick_wr = wr_ready && (!rd_ready || !last_wr);
    wire pick_rd = rd_ready && !pick_wr;
    wire wr_bad = aw_addr[1:0] != 2'b00 || w_strb != 4'hf;
    wire rd_bad = ar_addr[1:0] != 2'b00;

    always @(posedge clk) begin
        if (rst) begin
            aw_full <= 1'b0;
            w_full <= 1'b0;
            ar_full <= 1'b0;
            inflight <= 1'b0;
            wr_done <= 1'b0;
            rd_done <= 1'b0;
            last_wr <= 1'b0;
            req <= 1'b0;
            req_wr <= 1'b0;
            s_axi_bvalid <= 1'b0;
            s_axi_rvalid <= 1'b0;
            s_axi_bresp <= OKAY;
            s_axi_rresp <= OKAY;
        end else begin
            req <= 1'b0;
            if (s_axi_awvalid && !aw_full) begin
                aw_full <= 1'b1;
                aw_addr <= s_axi_awaddr;
            end
            if (s_axi_wvalid && !w_full) begin
                w_full <= 1'b1;
                w_data <= s_axi_wdata;
                w_strb <= s_axi_wstrb;
            end
            if (s_axi_arvalid && !ar_full) begin
                ar_full <= 1'b1;
                ar_addr <= s_axi_araddr;
            end
            // issue one access, or answer a malformed one at once
            if (!inflight && !req) begin
                if (pick_wr) begin
                    last_wr <= 1'b1;
                    if (wr_bad) begin
                        wr_done <= 1'b1;
                        s_axi_bvalid <= 1'b1;
                        s_axi_bresp <= SLVERR;
                    end else begin
                        req <= 1'b1;
                        req_wr <= 1'b1;
                        req_addr <= aw_addr;
                        req_data <= w_data;
                        inflight <= 1'b1;
                    end
                end else if (pick_rd) begin
                    last_wr <= 1'b0;
                    if (rd_bad) begin
                        rd_done <= 1'b1;
                        s_axi_rvalid <= 1'b1;
                        s_axi_rresp <= SLVERR;
                        s_axi_rdata <= 32'd0;
                    end else begin
                        req <= 1'b1;
                        req_wr <= 1'b0;
                        req_addr <= ar_addr;
                        inflight <= 1'b1;
                    end
                end
            end
            if (inflight && ack) begin
                inflight <= 1'b0;
                if (req_wr) begin
                    wr_done <= 1'b1;
                    s_axi_bvalid <= 1'b1;
                    s_axi_bresp <= ack_err ? SLVERR : OKAY;
                end else begin
                    rd_done <= 1'b1;
                    s_axi_rvalid <= 1'b1;
                    s_axi_rresp <= ack_err ? SLVERR : OKAY;
                    s_axi_rdata <= ack_err ? 32'd0 : ack_data;
                end
            end
            // a response taken frees its halves for the next access
            if (s_axi_bvalid && s_axi_bready) begin
                s_axi_bvalid <= 1'b0;
                wr_done <= 1'b0;
                aw_full <= 1'b0;
                w_full <= 1'b0;
            end
            if (s_axi_rvalid && s_axi_rready) begin
                s_axi_rvalid <= 1'b0;
                rd_done <= 1'b0;
                ar_full <= 1'b0;
            end
        end
    end

    // AWPROT and ARPROT carry nothing this slave distinguishes
    /* verilator lint_off UNUSEDSIGNAL */
    wire unused = &{1'b0, s_axi_awprot, s_axi_arprot};
    /* verilator lint_on UNUSEDSIGNAL */

`ifdef FORMAL
    // The register side answers every request one clock later (rt_regs does).
    reg past_valid = 1'b0, reset_seen = 1'b0;
    always @(posedge clk) begin
        past_valid <= 1'b1;
        if (rst) reset_seen <= 1'b1;
    end
    reg req_seen = 1'b0;
    always @(posedge clk) req_seen <= req && !rst;
    always @(*) assume (ack == req_seen);
    // The master keeps what it offers until it is taken (AXI's rule for VALID).
    always @(posedge clk) begin
        if (past_valid && !$past(rst)) begin
            if ($past(s_axi_awvalid && !s_axi_awready))
                assume (s_axi_awvalid && $stable(s_axi_awaddr));
            if ($past(s_axi_wvalid && !s_axi_wready))
                assume (s_axi_wvalid && $stable(s_axi_wdata) && $stable(s_axi_wstrb));
            if ($past(s_axi_arvalid && !s_axi_arready))
                assume (s_axi_arvalid && $stable(s_axi_araddr));
        end
    end
    // The slave's side of the same rule: a response stays, unchanged, until it is taken.
    always @(posedge clk) begin
        if (reset_seen && past_valid && !$past(rst)) begin
            if ($past(s_axi_bvalid && !s_axi_bready))
                assert (s_axi_bvalid && $stable(s_axi_bresp));
            if ($past(s_axi_rvalid && !s_axi_rready))
                assert (s_axi_rvalid && $stable(s_axi_rresp) && $stable(s_axi_rdata));
        end
    end
    // A response only for an access taken whole; one request at a time, and only for an
    // access waiting; the responses are OKAY or SLVERR; a malformed access never reaches
    // the registers.
    always @(*) begin
        if (reset_seen && !rst) begin
            if (s_axi_bvalid) assert (aw_full && w_full && wr_done && !(inflight && req_wr));
            if (s_axi_rvalid) assert (ar_full && rd_done);
            if (req) assert (inflight && (req_wr ? aw_full && w_full : ar_full));
            if (req && req_wr) assert (req_addr[1:0] == 2'b00 && w_strb == 4'hf);
            if (req && !req_wr) assert (req_addr[1:0] == 2'b00);
            assert (s_axi_bresp == OKAY || s_axi_bresp == SLVERR);
            assert (s_axi_rresp == OKAY || s_axi_rresp == SLVERR);
            if (inflight) assert (!(req_wr ? wr_done : rd_done));
            if (wr_done) assert (s_axi_bvalid);
            if (rd_done) assert (s_axi_rvalid);
        end
    end
`endif
endmodule
`default_nettype wire
