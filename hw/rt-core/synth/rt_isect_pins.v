// rt_isect_pins -- the intersection unit alone with four pins, for place and route only:
// the unit's ~250 ports would not fit a package, so every input comes from a shift
// register fed by `sin` and every output is loaded into one (on `load`) that `sout`
// shifts out, as rt_device_pins does for the whole device. Placed alone because it is
// the part of the core that must take one pair per clock, and it fits a part the whole
// core does not: its Fmax is the core's pair rate.
//
// Ports: clk, rst, sin, load; sout.
// Timing: one bit in and out per clock.
// Parameters: SHAPES, TB as rt_isect.
`default_nettype none
`include "rt_map.vh"
module rt_isect_pins #(
    parameter [6:0] SHAPES = 7'b111_1111,
    parameter integer TB = 16
) (
    input  wire clk,
    input  wire rst,
    input  wire sin,
    input  wire load,
    output wire sout
);
    localparam integer SB = `RT_SHAPE_BITS;
    localparam integer NI = 1 + SB + 8 * 32 + TB;
    localparam integer NO = 1 + 1 + 32 + 1 + TB;
    wire [NI-1:0] in_sr;
    wire [NO-1:0] outs;
    pin_shift #(.NI(NI), .NO(NO)) u_pins (.clk(clk), .sin(sin), .load(load), .outs(outs),
        .ins(in_sr), .sout(sout));

    wire          in_valid;
    wire [SB-1:0] shape;
    wire [31:0]   ox, oy, oz, dx, dy, dz, tmin, tmax;
    wire [TB-1:0] tag;
    assign {in_valid, shape, ox, oy, oz, dx, dy, dz, tmin, tmax, tag} = in_sr;

    wire          out_valid, hit, unsupported;
    wire [31:0]   t;
    wire [TB-1:0] tag_out;
    assign outs = {out_valid, hit, t, unsupported, tag_out};

    rt_isect #(.SHAPES(SHAPES), .TB(TB)) u_isect (
        .clk(clk), .rst(rst), .ce(1'b1), .in_valid(in_valid), .shape(shape),
        .ox(ox), .oy(oy), .oz(oz), .dx(dx), .dy(dy), .dz(dz), .tmin(tmin), .tmax(tmax),
        .tag(tag), .out_valid(out_valid), .hit(hit), .t(t), .unsupported(unsupported),
        .tag_out(tag_out));
endmodule
`default_nettype wire
