// sim_ram -- simulation model of the external framebuffer memory: 2^18 x 8, synchronous.
//
// Not synthesizable for the board (the board has the SDRAM controller, seed 000 ch. 6.3):
// it is what tests put behind fitkit_raster's memory port. A request is taken in a cycle
// where we or re is high and mem_wait is low; read data is valid the cycle after.
// `mem` is `verilator public` so a Verilator C++ harness can read and write the frame
// directly (rootp->fitkit_sim_top__DOT__u_ram__DOT__mem[addr]); the bd_* port is the same
// backdoor as plain Verilog (combinational read, for harnesses without public access).
`default_nettype none
module sim_ram (
    input  wire        clk,
    input  wire [17:0] addr,
    input  wire [7:0]  wdata,
    input  wire        we,
    input  wire        re,
    output reg  [7:0]  rdata,
    input  wire        mem_wait,
    input  wire [17:0] bd_addr,
    output wire [7:0]  bd_data
);
    reg [7:0] mem [0:262143] /* verilator public */;

    assign bd_data = mem[bd_addr];

    // Power-on contents 0, so that frames compare equal across simulators.
    integer k;
    initial for (k = 0; k < 262144; k = k + 1) mem[k] = 8'd0;

    always @(posedge clk) begin
        if (we && !mem_wait) mem[addr] <= wdata;
        if (re && !mem_wait) rdata <= mem[addr];
    end
endmodule
`default_nettype wire
