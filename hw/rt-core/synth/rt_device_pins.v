// rt_device_pins -- rt_device with four pins, for place and route only: the device has
// about 520 ports (the AXI4-Lite slave and the memory's write and read ports), more than
// any ECP5 package bonds out, and nextpnr must place a top's ports on pins. Here every
// input of the device comes from a shift register fed by `sin`, and every output is
// loaded into one (on `load`) that `sout` shifts out (pin_shift). Nothing is constant and
// every output is observed, so the synthesiser keeps the whole device, and its paths stay
// register to register: the figures are the device's, plus the two shift registers
// (252 and 285 flip-flops, no logic between them and the device worth a timing path).
//
// Ports: clk, rst, sin, load; sout.
// Timing: one bit in and out per clock.
// Parameters: OBJ, LIGHTS, SHAPES, SHADOWS as rt_device.
`default_nettype none
`include "rt_axi_map.vh"
`include "rt_map.vh"
module rt_device_pins #(
    parameter integer OBJ = `RT_OBJ_CAPACITY,
    parameter integer LIGHTS = `RT_LIGHT_CAPACITY - 1,
    parameter [6:0] SHAPES = 7'b111_1111,
    parameter integer SHADOWS = 1
) (
    input  wire clk,
    input  wire rst,
    input  wire sin,
    input  wire load,
    output wire sout
);
    localparam integer AW = `RT_AXI_ADDR_BITS;
    localparam integer NI = 1 + AW + 3 + 1 + 32 + 4 + 1 + 1 + AW + 3 + 1 + 1 + 1 + 1 + 24 + 8 +
                            32 + 96;
    localparam integer NO = 1 + 1 + 1 + 2 + 1 + 1 + 32 + 2 + 1 + 1 + 32 + 24 + 16 + 8 + 32 +
                            96 + 1 + 1 + 32;
    wire [NI-1:0] in_sr;
    wire [NO-1:0] outs;
    pin_shift #(.NI(NI), .NO(NO)) u_pins (.clk(clk), .sin(sin), .load(load), .outs(outs),
        .ins(in_sr), .sout(sout));

    wire          awvalid, wvalid, bready, arvalid, rready, mem_ready, rd_ready, rd_resp;
    wire [AW-1:0] awaddr, araddr;
    wire [2:0]    awprot, arprot;
    wire [31:0]   wdata, rd_t;
    wire [3:0]    wstrb;
    wire [23:0]   rd_rgb;
    wire [7:0]    rd_obj;
    wire [95:0]   rd_n;
    assign {awvalid, awaddr, awprot, wvalid, wdata, wstrb, bready, arvalid, araddr, arprot,
            rready, mem_ready, rd_ready, rd_resp, rd_rgb, rd_obj, rd_t, rd_n} = in_sr;

    wire        awready, wready, bvalid, arready, rvalid, irq, mem_valid, mem_aovs, rd_valid;
    wire [1:0]  bresp, rresp;
    wire [31:0] rdata, mem_index, mem_t, rd_index;
    wire [23:0] mem_rgb;
    wire [15:0] mem_kcu116;
    wire [7:0]  mem_obj;
    wire [95:0] mem_n;
    assign outs = {awready, wready, bvalid, bresp, arready, rvalid, rdata, rresp, irq,
                   mem_valid, mem_index, mem_rgb, mem_kcu116, mem_obj, mem_t, mem_n, mem_aovs,
                   rd_valid, rd_index};

    rt_device #(.OBJ(OBJ), .LIGHTS(LIGHTS), .SHAPES(SHAPES), .SHADOWS(SHADOWS)) u_device (
        .clk(clk), .rst(rst),
        .s_axi_awvalid(awvalid), .s_axi_awready(awready), .s_axi_awaddr(awaddr),
        .s_axi_awprot(awprot), .s_axi_wvalid(wvalid), .s_axi_wready(wready),
        .s_axi_wdata(wdata), .s_axi_wstrb(wstrb), .s_axi_bvalid(bvalid),
        .s_axi_bready(bready), .s_axi_bresp(bresp), .s_axi_arvalid(arvalid),
        .s_axi_arready(arready), .s_axi_araddr(araddr), .s_axi_arprot(arprot),
        .s_axi_rvalid(rvalid), .s_axi_rready(rready), .s_axi_rdata(rdata),
        .s_axi_rresp(rresp), .irq(irq), .mem_valid(mem_valid), .mem_ready(mem_ready),
        .mem_index(mem_index), .mem_rgb(mem_rgb), .mem_kcu116(mem_kcu116),
        .mem_obj(mem_obj), .mem_t(mem_t), .mem_n(mem_n), .mem_aovs(mem_aovs),
        .rd_valid(rd_valid), .rd_ready(rd_ready), .rd_index(rd_index), .rd_resp(rd_resp),
        .rd_rgb(rd_rgb), .rd_obj(rd_obj), .rd_t(rd_t), .rd_n(rd_n));
endmodule
`default_nettype wire
