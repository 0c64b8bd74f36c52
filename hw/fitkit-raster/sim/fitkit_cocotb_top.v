// fitkit_cocotb_top -- fitkit_sim_top (the block and its simulation RAM) with its clock
// made here, for the cocotb testbench (docs/cocotb.md).
//
// Why a wrapper: cocotb 1.9's Clock is a Python coroutine, two wake-ups of the
// interpreter per cycle, which made the clock most of the run time under Icarus; made in
// Verilog it costs nothing, and Python wakes only for the SPI master's edges and the
// memory-port writes it checks. Everything else is fitkit_sim_top's ports, passed
// through; the RAM's backdoor is not used (the testbench reads the frame over SPI).
// Parameter: CLK_NS, the clock period in ns (the testbench passes its own, so the two
// agree; the runner's timescale is 1 ns).
`default_nettype none
module fitkit_cocotb_top #(
    parameter CLK_NS = 20
) (
    input  wire rst,
    input  wire spi_sck,
    input  wire spi_cs_n,
    input  wire spi_mosi,
    output wire spi_miso,
    output wire fifo_free,
    output wire busy,
    input  wire mem_wait
);
    reg clk = 1'b0;
`ifdef VERILATOR
    // linted here only (the bench runs on Icarus); a delay is no lint model
    /* verilator lint_off UNUSEDPARAM */
    localparam UNUSED_CLK_NS = CLK_NS;
    /* verilator lint_on UNUSEDPARAM */
`else
    always #(CLK_NS / 2) clk = ~clk;
`endif
    // the RAM's backdoor, unused here
    /* verilator lint_off UNUSEDSIGNAL */
    wire [7:0] bd_data;
    /* verilator lint_on UNUSEDSIGNAL */

    fitkit_sim_top u_sim (
        .clk(clk), .rst(rst), .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi),
        .spi_miso(spi_miso), .fifo_free(fifo_free), .busy(busy), .mem_wait(mem_wait),
        .bd_addr(18'd0), .bd_data(bd_data)
    );
endmodule
`default_nettype wire
