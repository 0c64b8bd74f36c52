// rt_regs -- the register map of the ray-casting core's device (protocol::axi_lite,
// generated into rt_axi_map.vh) with the control semantics Vivado HLS generates for an
// `s_axilite` block such as seed 002's ViRAY (its §3.7 driver polls ap_done), and the
// model's register file (sim-target/src/mmio.rs) has:
//
//   AP_CTRL  ap_start (set by a write, held until the frame ends, then auto_restart's
//            value), ap_done and ap_ready (rise at the frame's end, clear on read),
//            ap_idle (no frame running or about to), auto_restart (written with each
//            write); a start while a frame runs is refused (SLVERR), as the model's Busy;
//   GIE, IER, ISR: ISR bits rise with enabled events at the frame's end and toggle on a
//            written 1; irq = GIE and a pending ISR bit;
//   NUMERIC, AOVS: the scalars; a NUMERIC code no format has is refused;
//   the scene window: word i at SCENE_BASE + 4 i, kept in a RAM (reads return what was
//            written, as the HLS array does) and forwarded to the core's cfg port;
//   ID, VERSION, RESET (any write: the power-on state, the core included);
//   RT_CYCLES, RT_WORK and the device counters: 64 bits as two words, the low word's
//            read latching the high word (a high word read without it is refused).
//
// What the core cannot do is refused at the start, not discovered later: a start is
// answered SLVERR when NUMERIC is not Q16.16 (the only format the core computes) or the
// core's `refuse` bits are set (the scene's format, samples, objects, shapes, size,
// lights, materials: rt_cast), and nothing runs. A scene write while a frame runs is
// refused too (the core reads its words during the frame). Addresses the device does not
// have (the raster slave, the texture window, reserved words) and accesses against a
// register's direction answer SLVERR. The read-back slave and window are rt_readback's:
// the device does not hand their accesses here.
//
// Differences from the model's register file: the model's ap_done rises after a number
// of polls, this one when the frame ends; RESET leaves the scene RAM's words as they
// were (a block RAM has no reset; a driver writes the whole image before a frame); the
// counters of fragments (the raster block's) and of saturations (not counted by the core
// yet) read 0; RT_WORK counts the rays the core tested (every pixel's primary ray and,
// with shadows, one shadow ray per light), where the model counts those it traced.
//
// Ports: req, req_wr, req_addr, req_data (one access, rt_axil), answered by ack, ack_err,
// ack_data one clock later. Core side: soft_rst (RESET's pulse, for the core), cfg_we,
// cfg_addr, cfg_data, core_start (a pulse); core_busy, core_done, core_refuse, core_rays.
// aovs (AOVS as the running frame took it), idle (AP_CTRL's ap_idle), irq.
// Timing: every access answered the clock after its request; a frame starts the clock
// after the accepted AP_CTRL write (auto-restart: the clock after its end).
// Parameters: AW address bits, at least `RT_AXI_ADDR_BITS`.
`default_nettype none
`include "rt_axi_map.vh"
module rt_regs #(
    parameter integer AW = `RT_AXI_ADDR_BITS
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          req,
    input  wire          req_wr,
    input  wire [AW-1:0] req_addr,
    input  wire [31:0]   req_data,
    output reg           ack,
    output reg           ack_err,
    output wire [31:0]   ack_data,
    output reg           soft_rst,
    output reg           cfg_we,
    output reg  [8:0]    cfg_addr,
    output reg  [31:0]   cfg_data,
    output reg           core_start,
    input  wire          core_busy,
    input  wire          core_done,
    input  wire [7:0]    core_refuse,
    input  wire [31:0]   core_rays,
    output reg           aovs,
    output wire          idle,
    output wire          irq
);
    generate
        if (AW < `RT_AXI_ADDR_BITS || AW > 32 || `RT_AXI_SCENE_WORDS > 512)
        begin : bad_parameter
            rt_regs_parameter_out_of_range unsupported();
        end
    endgenerate

    localparam integer NC = `RT_AXI_COUNTER_COUNT;
    wire [31:0] a = {{(32 - AW){1'b0}}, req_addr};

    // ---- state ----------------------------------------------------------------------------
    reg        start_r, auto_r, done_r, ready_r, running;
    reg        gie;
    reg [1:0]  ier, isr;
    reg [31:0] numeric;
    reg        aovs_r;
    reg [63:0] cyc, last_cycles, last_work, total_cycles, frames;
    reg        latched;
    reg [31:0] latch_addr, latch_hi;
    reg [31:0] scene [0:`RT_AXI_SCENE_WORDS - 1];
    reg [31:0] reg_data, scene_q;  // a register's word; the scene RAM's read
    reg        from_scene;        // the answer is the scene RAM's
    assign idle = !running && !start_r;
    assign irq = gie && isr != 2'b00;

    // the decode: which register, counter or scene word the address selects
    wire        in_scene = a >= `RT_AXI_SCENE_BASE &&
                           a < `RT_AXI_SCENE_BASE + 4 * `RT_AXI_SCENE_WORDS;
    // word offsets within the scene window and the counters (the byte bits are 0: rt_axil
    // refuses an unaligned address; the scene index is below 512)
    /* verilator lint_off UNUSEDSIGNAL */
    wire [31:0] scene_off = a - `RT_AXI_SCENE_BASE;
    wire [8:0]  scene_i = scene_off[10:2];
    wire        in_counters = a >= `RT_AXI_SYS_COUNTERS && a < `RT_AXI_SYS_COUNTERS + 8 * NC;
    wire [31:0] counter_off = a - `RT_AXI_SYS_COUNTERS;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] counter_i = {3'd0, counter_off[31:3]};
    wire        counter_hi = counter_off[2];
    reg  [63:0] counter;
    always @(*) begin
        case (counter_i)
            `RT_AXI_COUNTER_CYCLES: counter = total_cycles;
            `RT_AXI_COUNTER_FRAMES: counter = frames;
            default: counter = 64'd0;  // fragments: no raster block; saturations: not yet
        endcase
    end

    // a 64-bit value's low word (latching the high word) or its high word (if latched)
    wire is_wide_lo = a == `RT_AXI_SYS_RT_CYCLES || a == `RT_AXI_SYS_RT_WORK ||
                      (in_counters && !counter_hi);
    wire is_wide_hi = a == `RT_AXI_SYS_RT_CYCLES + 4 || a == `RT_AXI_SYS_RT_WORK + 4 ||
                      (in_counters && counter_hi);
    wire [63:0] wide = a == `RT_AXI_SYS_RT_CYCLES ? last_cycles :
                       a == `RT_AXI_SYS_RT_WORK ? last_work : counter;

    // a start is refused when the core cannot render the image or another format is asked
    wire start_bad = numeric != `RT_AXI_NUMERIC_Q16_16 || core_refuse != 8'd0;
    wire ctrl_rd = req && !req_wr && a == `RT_AXI_AP_CTRL;

    // ---- the frame's control ----------------------------------------------------------------
    always @(posedge clk) begin
        if (rst || soft_rst) begin
            start_r <= 1'b0;
            auto_r <= 1'b0;
            done_r <= 1'b0;
            ready_r <= 1'b0;
            running <= 1'b0;
            core_start <= 1'b0;
            isr <= 2'b00;
            cyc <= 64'd0;
            last_cycles <= 64'd0;
            last_work <= 64'd0;
            total_cycles <= 64'd0;
            frames <= 64'd0;
            aovs <= 1'b0;
        end else begin
            core_start <= 1'b0;
            // ap_done and ap_ready clear when read; a frame ending now sets them again
            if (ctrl_rd) begin
                done_r <= 1'b0;
                ready_r <= 1'b0;
            end
            if (req && req_wr && a == `RT_AXI_AP_CTRL && !(req_data[0] && (!idle || start_bad)))
            begin
                if (req_data[0]) start_r <= 1'b1;
                auto_r <= req_data[`RT_AXI_AUTO_RESTART];
            end
            if (req && req_wr && a == `RT_AXI_ISR) isr <= isr ^ req_data[1:0];
            // take the start
            if (start_r && !running && !core_start && !core_busy) begin
                core_start <= 1'b1;
                running <= 1'b1;
                aovs <= aovs_r;
            end
            if (core_start) cyc <= 64'd1;
            else if (running) cyc <= cyc + 64'd1;
            if (running && core_done) begin
                running <= 1'b0;
                done_r <= 1'b1;
                ready_r <= 1'b1;
                start_r <= auto_r;
                isr <= (req && req_wr && a == `RT_AXI_ISR ? isr ^ req_data[1:0] : isr) | ier;
                last_cycles <= cyc;
                last_work <= {32'd0, core_rays};
                total_cycles <= total_cycles + cyc;
                frames <= frames + 64'd1;
            end
        end
    end

    // ---- accesses -----------------------------------------------------------------------------
    always @(posedge clk) begin
        if (rst || soft_rst) begin
            ack <= 1'b0;
            ack_err <= 1'b0;
            soft_rst <= 1'b0;
            cfg_we <= 1'b0;
            gie <= 1'b0;
            ier <= 2'b00;
            numeric <= 32'd0;
            aovs_r <= 1'b0;
            latched <= 1'b0;
        end else begin
            ack <= req;
            ack_err <= 1'b0;
            reg_data <= 32'd0;
            from_scene <= 1'b0;
            cfg_we <= 1'b0;
            if (req && req_wr) begin
                if (in_scene) begin
                    if (!idle) ack_err <= 1'b1;
                    else begin
                        cfg_we <= 1'b1;
                        cfg_addr <= scene_i;
                        cfg_data <= req_data;
                    end
                end else begin
                    case (a)
                        `RT_AXI_AP_CTRL: ack_err <= req_data[0] && (!idle || start_bad);
                        `RT_AXI_GIE: gie <= req_data[0];
                        `RT_AXI_IER: ier <= req_data[1:0];
                        `RT_AXI_ISR: ;  // toggled above
                        `RT_AXI_NUMERIC: begin
                            if (req_data < `RT_AXI_NUMERIC_CODES) numeric <= req_data;
                            else ack_err <= 1'b1;
                        end
                        `RT_AXI_AOVS: aovs_r <= req_data[0];
                        `RT_AXI_SYS_RESET: soft_rst <= 1'b1;
                        default: ack_err <= 1'b1;  // read-only or not on this device
                    endcase
                end
            end else if (req) begin
                if (in_scene) begin
                    from_scene <= 1'b1;
                end else if (is_wide_lo) begin
                    reg_data <= wide[31:0];
                    latched <= 1'b1;
                    latch_addr <= a + 32'd4;
                    latch_hi <= wide[63:32];
                end else if (is_wide_hi) begin
                    if (latched && latch_addr == a) reg_data <= latch_hi;
                    else ack_err <= 1'b1;
                end else begin
                    case (a)
                        `RT_AXI_AP_CTRL:
                            reg_data <= {31'd0, auto_r} << `RT_AXI_AUTO_RESTART |
                                        {31'd0, ready_r} << `RT_AXI_AP_READY |
                                        {31'd0, idle} << `RT_AXI_AP_IDLE |
                                        {31'd0, done_r} << `RT_AXI_AP_DONE |
                                        {31'd0, start_r} << `RT_AXI_AP_START;
                        `RT_AXI_GIE: reg_data <= {31'd0, gie};
                        `RT_AXI_IER: reg_data <= {30'd0, ier};
                        `RT_AXI_ISR: reg_data <= {30'd0, isr};
                        `RT_AXI_NUMERIC: reg_data <= numeric;
                        `RT_AXI_AOVS: reg_data <= {31'd0, aovs_r};
                        `RT_AXI_SYS_ID: reg_data <= `RT_AXI_DEVICE_ID;
                        `RT_AXI_SYS_VERSION: reg_data <= `RT_AXI_MAP_VERSION;
                        default: ack_err <= 1'b1;  // write-only or not on this device
                    endcase
                end
            end
        end
    end
    // the scene RAM's write and read ports on their own, so that it maps to a block RAM
    // (inside the decode above a synthesiser keeps it in distributed RAM)
    always @(posedge clk) begin
        if (req && req_wr && in_scene && idle) scene[scene_i] <= req_data;
        scene_q <= scene[scene_i];
    end
    assign ack_data = from_scene ? scene_q : reg_data;
endmodule
`default_nettype wire
