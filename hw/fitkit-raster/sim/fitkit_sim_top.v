// fitkit_sim_top -- fitkit_raster with the simulation RAM behind it: what the bridge crate
// (fitkit-rtl-sim) Verilates.
//
// Ports: fitkit_raster's clk, rst, SPI pins, fifo_free and busy; mem_wait drives the
// memory port's wait input (tests toggle it to exercise the stall path); bd_addr /
// bd_data read the RAM without a clock (the backdoor; sim_ram's `mem` is also
// `verilator public`).
// Parameters: TRI_LANES, LINE_UNIT, TRI_UNIT and TRI_SMALL as fitkit_raster
// (fitkit_sim_top8 builds it with 8 lanes, fitkit_sim_top_line and fitkit_sim_top_tri
// with one unit each, the latter with tri_small).
`default_nettype none
module fitkit_sim_top #(
    parameter TRI_LANES = 1,
    parameter LINE_UNIT = 1,
    parameter TRI_UNIT = 1,
    parameter TRI_SMALL = 0
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        spi_sck,
    input  wire        spi_cs_n,
    input  wire        spi_mosi,
    output wire        spi_miso,
    output wire        fifo_free,
    output wire        busy,
    input  wire        mem_wait,
    input  wire [17:0] bd_addr,
    output wire [7:0]  bd_data
);
    wire [17:0] mem_addr;
    wire [7:0]  mem_wdata, mem_rdata;
    wire        mem_we, mem_re;

    fitkit_raster #(
        .TRI_LANES(TRI_LANES), .LINE_UNIT(LINE_UNIT), .TRI_UNIT(TRI_UNIT), .TRI_SMALL(TRI_SMALL)
    ) u_dut (
        .clk(clk), .rst(rst), .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi),
        .spi_miso(spi_miso), .fifo_free(fifo_free), .busy(busy), .mem_addr(mem_addr),
        .mem_wdata(mem_wdata), .mem_we(mem_we), .mem_re(mem_re), .mem_rdata(mem_rdata),
        .mem_wait(mem_wait)
    );

    sim_ram u_ram (
        .clk(clk), .addr(mem_addr), .wdata(mem_wdata), .we(mem_we), .re(mem_re),
        .rdata(mem_rdata), .mem_wait(mem_wait), .bd_addr(bd_addr), .bd_data(bd_data)
    );
endmodule
`default_nettype wire
