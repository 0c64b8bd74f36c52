// fitkit_sim_top_tri -- fitkit_sim_top without the line unit (LINE_UNIT = 0) and with the
// small triangle unit (TRI_SMALL = 1): the triangle-only design for the seed's XC3S50
// (seed 000 built lines and triangles as two designs). A Verilated model of its own in
// the bridge crate, so the differential tests drive that build through the same pins;
// line packets are refused there.
//
// Ports and timing: as fitkit_sim_top.
`default_nettype none
module fitkit_sim_top_tri (
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
    fitkit_sim_top #(.LINE_UNIT(0), .TRI_SMALL(1)) u_top (
        .clk(clk), .rst(rst), .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi),
        .spi_miso(spi_miso), .fifo_free(fifo_free), .busy(busy), .mem_wait(mem_wait),
        .bd_addr(bd_addr), .bd_data(bd_data)
    );
endmodule
`default_nettype wire
