// rt_isect -- the core's intersection unit: one (ray, object) pair per clock in object
// space, every shape the golden model has, its hit distance bit for bit
// (`shapes::intersect` with the model's default math: the stable root formula and the
// format's own square root; sim-target/src/rt/shapes.rs).
//
// Why three datapaths side by side: a pair is one shape, but consecutive pairs are any
// shapes, so each family has its own pipeline (the curved shapes' quadratic, the flat
// shapes' single quotient, the cube's slabs) and the pair's code picks the result once
// all three are aligned to the longest. Which shapes are built is a parameter, so a
// design carries only what its scenes need; a pair asking for a shape this instance does
// not build comes out with `unsupported` high and no hit (the host refuses such a scene
// before it is sent). Seed 002 §3.4 intersects each object in its own space.
//
// The nearest hit is the caller's: the model passes the best distance so far as tmax,
// but which root a shape picks never depends on tmax except through the final range
// test, so the caller can give tmax = max_distance here and keep, in object order, each
// hit t <= best.
//
// Ports: shape (rt_map.vh codes), o, d (object-space ray, Q16.16), tmin (the scene's
// bias), tmax, tag (TB bits the caller carries along: pixel, object index);
// in_valid / out_valid; hit, t, unsupported.
// Timing: latency LAT_QUADRIC + 1 = 80 (isect.vh: the longest datapath, then the
// choice), one pair per clock; ce low holds everything.
// Parameters: SHAPES, bit i builds shape code i (rt_map.vh); TB >= 1.
`default_nettype none
`include "rt_map.vh"
module rt_isect #(
    parameter [6:0] SHAPES = 7'b111_1111,
    parameter integer TB = 16
) (
    input  wire                      clk,
    input  wire                      rst,
    input  wire                      ce,
    input  wire                      in_valid,
    input  wire [`RT_SHAPE_BITS-1:0] shape,
    input  wire [31:0]               ox,
    input  wire [31:0]               oy,
    input  wire [31:0]               oz,
    input  wire [31:0]               dx,
    input  wire [31:0]               dy,
    input  wire [31:0]               dz,
    input  wire [31:0]               tmin,
    input  wire [31:0]               tmax,
    input  wire [TB-1:0]             tag,
    output reg                       out_valid,
    output reg                       hit,
    output reg  [31:0]               t,
    output reg                       unsupported,
    output reg  [TB-1:0]             tag_out
);
    generate
        if (TB < 1) begin : bad_parameter
            rt_isect_parameter_out_of_range unsupported_parameter();
        end
    endgenerate

    `include "q16_ops.vh"
    `include "isect.vh"
    localparam integer SB = `RT_SHAPE_BITS;
    // each shape's bit as the submodules' integer parameters
    localparam integer SPHERE = SHAPES[0] ? 1 : 0;
    localparam integer PLANE = SHAPES[1] ? 1 : 0;
    localparam integer DISK = SHAPES[2] ? 1 : 0;
    localparam integer SQUARE = SHAPES[3] ? 1 : 0;
    localparam integer CYLINDER = SHAPES[4] ? 1 : 0;
    localparam integer CONE = SHAPES[5] ? 1 : 0;
    localparam integer QUADRIC = SPHERE + CYLINDER + CONE != 0 ? 1 : 0;
    localparam integer FLAT = PLANE + DISK + SQUARE != 0 ? 1 : 0;

    wire        hit_q, hit_f, hit_c;
    wire [31:0] t_q, t_f, t_c;

    generate
        if (QUADRIC != 0) begin : quadric
            isect_quadric #(.SPHERE(SPHERE), .CYLINDER(CYLINDER), .CONE(CONE)) u (
                .clk(clk), .rst(rst), .ce(ce), .shape(shape),
                .ox(ox), .oy(oy), .oz(oz), .dx(dx), .dy(dy), .dz(dz),
                .tmin(tmin), .tmax(tmax), .hit(hit_q), .t(t_q)
            );
        end else begin : no_quadric
            assign hit_q = 1'b0;
            assign t_q = 32'd0;
        end
        if (FLAT != 0) begin : flat
            wire        h;
            wire [31:0] tt;
            isect_flat #(.PLANE(PLANE), .DISK(DISK), .SQUARE(SQUARE)) u (
                .clk(clk), .rst(rst), .ce(ce), .shape(shape),
                .ox(ox), .oy(oy), .oz(oz), .dx(dx), .dy(dy), .dz(dz),
                .tmin(tmin), .tmax(tmax), .hit(h), .t(tt)
            );
            dly #(.W(33), .N(LAT_QUADRIC - LAT_FLAT)) align (.clk(clk), .rst(rst), .ce(ce),
                .d({h, tt}), .q({hit_f, t_f}));
        end else begin : no_flat
            assign hit_f = 1'b0;
            assign t_f = 32'd0;
        end
        if (SHAPES[6]) begin : cube
            wire        h;
            wire [31:0] tt;
            isect_cube u (
                .clk(clk), .rst(rst), .ce(ce),
                .ox(ox), .oy(oy), .oz(oz), .dx(dx), .dy(dy), .dz(dz),
                .tmin(tmin), .tmax(tmax), .hit(h), .t(tt)
            );
            dly #(.W(33), .N(LAT_QUADRIC - LAT_CUBE)) align (.clk(clk), .rst(rst), .ce(ce),
                .d({h, tt}), .q({hit_c, t_c}));
        end else begin : no_cube
            assign hit_c = 1'b0;
            assign t_c = 32'd0;
        end
    endgenerate

    wire [SB-1:0] shape_l;
    wire [TB-1:0] tag_l;
    wire          valid_l;
    dly #(.W(SB + TB), .N(LAT_QUADRIC)) d_pair (.clk(clk), .rst(rst), .ce(ce),
        .d({shape, tag}), .q({shape_l, tag_l}));
    dly #(.W(1), .N(LAT_QUADRIC), .RESET(1)) d_valid (.clk(clk), .rst(rst), .ce(ce),
        .d(in_valid), .q(valid_l));

    wire built = shape_l <= 3'd6 && SHAPES[shape_l];
    always @(posedge clk) begin
        if (rst) out_valid <= 1'b0;
        else if (ce) out_valid <= valid_l;
        if (ce) begin
            unsupported <= !built;
            tag_out <= tag_l;
            case (shape_l)
                `RT_SHAPE_SPHERE, `RT_SHAPE_CYLINDER, `RT_SHAPE_CONE: begin
                    hit <= built && hit_q;
                    t <= t_q;
                end
                `RT_SHAPE_PLANE, `RT_SHAPE_DISK, `RT_SHAPE_SQUARE: begin
                    hit <= built && hit_f;
                    t <= t_f;
                end
                default: begin
                    hit <= built && hit_c;
                    t <= t_c;
                end
            endcase
        end
    end
endmodule
`default_nettype wire
