// fitkit_raster_pins -- the FITkit raster block with five pins, for place and route on a
// part whose tool places no unconstrained I/O (nextpnr-himbaechel for Gowin): every input
// of the block comes from a shift register fed by `sin`, every output is loaded into one
// (on `load`) that `sout` shifts out, so the constraints file names five pins whatever
// the board, and every path of the block is register to register.
//
// Ports: clk, rst, sin, load; sout.
// Timing: one bit in and out per clock; the block sees its inputs one clock after they
// are shifted into place.
// Parameters: TRI_LANES as fitkit_raster.
`default_nettype none
module fitkit_raster_pins #(
    parameter TRI_LANES = 1
) (
    input  wire clk,
    input  wire rst,
    input  wire sin,
    input  wire load,
    output wire sout
);
    localparam integer NI = 3 + 8 + 1;
    localparam integer NO = 3 + 18 + 8 + 2;
    wire [NI-1:0] ins;
    wire [NO-1:0] outs;
    pin_shift #(.NI(NI), .NO(NO)) u_pins (.clk(clk), .sin(sin), .load(load), .outs(outs),
        .ins(ins), .sout(sout));

    wire        spi_sck, spi_cs_n, spi_mosi, mem_wait;
    wire [7:0]  mem_rdata;
    assign {spi_sck, spi_cs_n, spi_mosi, mem_rdata, mem_wait} = ins;

    wire        spi_miso, fifo_free, busy, mem_we, mem_re;
    wire [17:0] mem_addr;
    wire [7:0]  mem_wdata;
    assign outs = {spi_miso, fifo_free, busy, mem_addr, mem_wdata, mem_we, mem_re};

    fitkit_raster #(.TRI_LANES(TRI_LANES)) u_block (
        .clk(clk), .rst(rst), .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi),
        .spi_miso(spi_miso), .fifo_free(fifo_free), .busy(busy), .mem_addr(mem_addr),
        .mem_wdata(mem_wdata), .mem_we(mem_we), .mem_re(mem_re), .mem_rdata(mem_rdata),
        .mem_wait(mem_wait));
endmodule
`default_nettype wire
