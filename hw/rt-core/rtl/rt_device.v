// rt_device -- the ray-casting core as a device on the seed's bus: the AXI4-Lite slave
// (rt_axil) with protocol::axi_lite's map and HLS control (rt_regs) in front of the frame
// core (rt_cast), and a memory port through which every pixel's results leave in raster
// order (seed 002: ViRAY is an HLS block a MicroBlaze drives over AXI4-Lite and that
// writes its frame to memory).
//
// The memory port: one record per pixel, mem_valid with mem_index (y W + x, counted
// from the frame's start), mem_rgb (R in bits 23:16), mem_kcu116, and the AOV words
// (mem_obj: the nearest object's index, 8'hff for a miss; mem_t: its distance, Q16.16;
// mem_n: the unit normal, x in bits 31:0), with mem_aovs saying whether the frame asked
// for the AOV planes (AOVS at its start). A record is taken on a clock with mem_valid and
// mem_ready both high; while mem_ready is low with a record waiting, the whole core
// holds (its `hold`), so the frame takes one clock more per such clock and nothing is
// lost.
//
// The memory's read port gives the records back to the read-back slave and window
// (rt_readback): rd_valid with rd_index until rd_ready, then the record (as the write
// port wrote it at that index) on a later clock with rd_resp. The read-back reads the
// frame last started (its size and AOVS kept at the start), and only while no frame runs.
//
// Ports: s_axi_* (AXI4-Lite slave, `RT_AXI_ADDR_BITS address bits), irq; mem_*; rd_*.
// Timing: as rt_axil, rt_regs, rt_readback and rt_cast.
// Parameters: OBJ, LIGHTS, SHAPES, SHADOWS as rt_cast.
`default_nettype none
`include "rt_axi_map.vh"
`include "rt_map.vh"
module rt_device #(
    parameter integer OBJ = `RT_OBJ_CAPACITY,
    parameter integer LIGHTS = `RT_LIGHT_CAPACITY - 1,
    parameter [6:0] SHAPES = 7'b111_1111,
    parameter integer SHADOWS = 1
) (
    input  wire                         clk,
    input  wire                         rst,
    input  wire                         s_axi_awvalid,
    output wire                         s_axi_awready,
    input  wire [`RT_AXI_ADDR_BITS-1:0] s_axi_awaddr,
    input  wire [2:0]                   s_axi_awprot,
    input  wire                         s_axi_wvalid,
    output wire                         s_axi_wready,
    input  wire [31:0]                  s_axi_wdata,
    input  wire [3:0]                   s_axi_wstrb,
    output wire                         s_axi_bvalid,
    input  wire                         s_axi_bready,
    output wire [1:0]                   s_axi_bresp,
    input  wire                         s_axi_arvalid,
    output wire                         s_axi_arready,
    input  wire [`RT_AXI_ADDR_BITS-1:0] s_axi_araddr,
    input  wire [2:0]                   s_axi_arprot,
    output wire                         s_axi_rvalid,
    input  wire                         s_axi_rready,
    output wire [31:0]                  s_axi_rdata,
    output wire [1:0]                   s_axi_rresp,
    output wire                         irq,
    output wire                         mem_valid,
    input  wire                         mem_ready,
    output reg  [31:0]                  mem_index,
    output wire [23:0]                  mem_rgb,
    output wire [15:0]                  mem_kcu116,
    output wire [7:0]                   mem_obj,
    output wire [31:0]                  mem_t,
    output wire [95:0]                  mem_n,
    output wire                         mem_aovs,
    output wire                         rd_valid,
    input  wire                         rd_ready,
    output wire [31:0]                  rd_index,
    input  wire                         rd_resp,
    input  wire [23:0]                  rd_rgb,
    input  wire [7:0]                   rd_obj,
    input  wire [31:0]                  rd_t,
    input  wire [95:0]                  rd_n
);
    localparam integer AW = `RT_AXI_ADDR_BITS;

    wire          req, req_wr, ack, ack_err;
    wire [AW-1:0] req_addr;
    wire [31:0]   req_data, ack_data;
    rt_axil #(.AW(AW)) u_axil (.clk(clk), .rst(rst),
        .s_axi_awvalid(s_axi_awvalid), .s_axi_awready(s_axi_awready),
        .s_axi_awaddr(s_axi_awaddr), .s_axi_awprot(s_axi_awprot),
        .s_axi_wvalid(s_axi_wvalid), .s_axi_wready(s_axi_wready), .s_axi_wdata(s_axi_wdata),
        .s_axi_wstrb(s_axi_wstrb), .s_axi_bvalid(s_axi_bvalid), .s_axi_bready(s_axi_bready),
        .s_axi_bresp(s_axi_bresp), .s_axi_arvalid(s_axi_arvalid),
        .s_axi_arready(s_axi_arready), .s_axi_araddr(s_axi_araddr),
        .s_axi_arprot(s_axi_arprot), .s_axi_rvalid(s_axi_rvalid), .s_axi_rready(s_axi_rready),
        .s_axi_rdata(s_axi_rdata), .s_axi_rresp(s_axi_rresp),
        .req(req), .req_wr(req_wr), .req_addr(req_addr), .req_data(req_data), .ack(ack),
        .ack_err(ack_err), .ack_data(ack_data));

    // the read-back slave and window go to rt_readback, everything else to rt_regs
    wire [31:0] a = {{(32 - AW){1'b0}}, req_addr};
    wire rb_sel = (a >= `RT_AXI_READ_SLAVE && a < `RT_AXI_READ_SLAVE + `RT_AXI_SLAVE_SPAN) ||
                  (a >= `RT_AXI_READ_BASE && a < `RT_AXI_READ_BASE + `RT_AXI_READ_WINDOW);
    wire        regs_ack, regs_err, rb_ack, rb_err;
    wire [31:0] regs_data, rb_data;
    assign ack = regs_ack || rb_ack;
    assign ack_err = rb_ack ? rb_err : regs_err;
    assign ack_data = rb_ack ? rb_data : regs_data;

    wire        soft_rst, cfg_we, core_start, core_busy, core_done, idle;
    wire [8:0]  cfg_addr;
    wire [31:0] cfg_data, core_rays;
    wire [7:0]  core_refuse;
    rt_regs #(.AW(AW)) u_regs (.clk(clk), .rst(rst), .req(req && !rb_sel), .req_wr(req_wr),
        .req_addr(req_addr), .req_data(req_data), .ack(regs_ack), .ack_err(regs_err),
        .ack_data(regs_data), .soft_rst(soft_rst), .cfg_we(cfg_we), .cfg_addr(cfg_addr),
        .cfg_data(cfg_data), .core_start(core_start), .core_busy(core_busy),
        .core_done(core_done), .core_refuse(core_refuse), .core_rays(core_rays),
        .aovs(mem_aovs), .idle(idle), .irq(irq));

    // the frame the read-back reads: the last one started since reset
    wire [15:0] core_w, core_h;
    reg         shown;
    reg  [15:0] shown_w, shown_h;
    always @(posedge clk) begin
        if (rst || soft_rst) shown <= 1'b0;
        else if (core_start) begin
            shown <= 1'b1;
            shown_w <= core_w;
            shown_h <= core_h;
        end
    end
    rt_readback #(.AW(AW)) u_readback (.clk(clk), .rst(rst || soft_rst),
        .req(req && rb_sel), .req_wr(req_wr), .req_addr(req_addr), .req_data(req_data),
        .ack(rb_ack), .ack_err(rb_err), .ack_data(rb_data), .busy(!idle), .shown(shown),
        .shown_w(shown_w), .shown_h(shown_h), .shown_aovs(mem_aovs), .stale(core_start),
        .rd_valid(rd_valid), .rd_ready(rd_ready), .rd_index(rd_index), .rd_resp(rd_resp),
        .rd_rgb(rd_rgb), .rd_obj(rd_obj), .rd_t(rd_t), .rd_n(rd_n));

    wire        pix_valid, pix_hit;
    wire [15:0] pix_x, pix_y;
    wire [7:0]  pix_obj;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [7:0]  core_err;  // the start refused what it would raise (rt_regs)
    /* verilator lint_on UNUSEDSIGNAL */
    rt_cast #(.OBJ(OBJ), .LIGHTS(LIGHTS), .SHAPES(SHAPES), .SHADOWS(SHADOWS)) u_cast (
        .clk(clk), .rst(rst || soft_rst), .cfg_we(cfg_we), .cfg_addr(cfg_addr),
        .cfg_data(cfg_data), .start(core_start), .hold(mem_valid && !mem_ready),
        .busy(core_busy), .done(core_done), .err(core_err), .pix_valid(pix_valid),
        .pix_x(pix_x), .pix_y(pix_y), .pix_hit(pix_hit), .pix_obj(pix_obj), .pix_t(mem_t),
        .pix_n(mem_n), .pix_rgb(mem_rgb), .pix_kcu116(mem_kcu116), .refuse(core_refuse),
        .rays(core_rays), .width(core_w), .height(core_h));
    // x and y are the index's, counted instead of multiplied
    /* verilator lint_off UNUSEDSIGNAL */
    wire [31:0] unused_xy = {pix_x, pix_y};
    /* verilator lint_on UNUSEDSIGNAL */
    assign mem_valid = pix_valid;
    assign mem_obj = pix_hit ? pix_obj : 8'hff;
    always @(posedge clk) begin
        if (rst || soft_rst || core_start) mem_index <= 32'd0;
        else if (mem_valid && mem_ready) mem_index <= mem_index + 32'd1;
    end
endmodule
`default_nettype wire
