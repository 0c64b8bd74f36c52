// fitkit_raster -- the FITkit raster block: SPI in, framebuffer memory port out.
//
// Seed 000 ch. 6 (6.1 SPI + address decoder, 6.2 FIFO36, 6.3 the SDRAM side, 6.4 lines,
// 6.5 triangles), wired as docs/rtl.md describes: spi_slave -> spi_decoder -> fifo36 ->
// cmd_exec -> {clear_unit, line_unit, tri_unit} -> frag_fifo -> fb_writer -> memory,
// with readback (channel 0x30) sharing fb_writer's port and status (channel 0x20).
//
// Parameter TRI_LANES: the triangle unit tests 1 (default, the seed's timing) or 2, 4, 8
// pixels of a row per cycle (seed 000's 8-pixel parallel evaluation); the fragments
// still reach memory one per cycle.
// Parameters LINE_UNIT, TRI_UNIT (1 default, 0 leaves the unit out): the seed's XC3S50
// holds the block with one of the two units only (seed 000 built lines and triangles as
// two designs). The absent unit's address is unknown to the decoder (error 5, payload
// ignored) and the status flags say which unit is absent (FLAG_NO_LINE, FLAG_NO_TRIANGLE),
// so the controller refuses those commands before sending them.
// Ports: docs/rtl.md "Top level". rst and the SPI reset (channel 0x7F) reset everything
// but the SPI slave and decoder, which are idle when the reset transaction ends.
// Timing: per unit in its own header; the cycle formulas are collected in docs/rtl.md.
`default_nettype none
`include "fitkit_map.vh"
module fitkit_raster #(
    parameter TRI_LANES = 1,    // tri_unit's pixel tests per cycle: 1 (seed), 2, 4 or 8
    parameter LINE_UNIT = 1,    // 1: the line unit is built; 0: lines are refused
    parameter TRI_UNIT = 1,     // 1: the triangle unit is built; 0: triangles are refused
    parameter TRI_SMALL = 0     // 1: tri_small (TRI_LANES = 1's pixels and cycles, few LUTs)
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        spi_sck,
    input  wire        spi_cs_n,
    input  wire        spi_mosi,
    output wire        spi_miso,
    output wire        fifo_free,
    output wire        busy,
    output wire [17:0] mem_addr,
    output wire [7:0]  mem_wdata,
    output wire        mem_we,
    output wire        mem_re,
    input  wire [7:0]  mem_rdata,
    input  wire        mem_wait
);
    generate
        if ((LINE_UNIT != 0 && LINE_UNIT != 1) || (TRI_UNIT != 0 && TRI_UNIT != 1)
            || (LINE_UNIT == 0 && TRI_UNIT == 0)) begin : bad_parameter
            fitkit_raster_line_unit_and_tri_unit_are_0_or_1_not_both_0 unsupported();
        end
        if ((TRI_SMALL != 0 && TRI_SMALL != 1) || (TRI_SMALL == 1 && TRI_LANES != 1))
        begin : bad_small
            fitkit_raster_tri_small_must_be_0_or_1_with_one_lane unsupported();
        end
    endgenerate

    // SPI.
    wire       cs_start, cs_end, cs_partial, rx_valid, tx_load, bit_start;
    wire [7:0] rx_byte, byte_index;
    reg  [7:0] tx_byte;
    spi_slave u_spi (
        .clk(clk), .rst(rst), .spi_sck(spi_sck), .spi_cs_n(spi_cs_n), .spi_mosi(spi_mosi),
        .spi_miso(spi_miso), .cs_start(cs_start), .cs_end(cs_end), .cs_partial(cs_partial),
        .rx_valid(rx_valid), .rx_byte(rx_byte), .byte_index(byte_index),
        .tx_load(tx_load), .tx_byte(tx_byte), .bit_start(bit_start)
    );

    wire [7:0]  chan, dec_chan;
    wire        chan_valid, fifo_we, fifo_commit, fifo_discard, dec_err, soft_rst, snap;
    wire [37:0] fifo_din;
    wire [`FITKIT_ERR_BITS-1:0] dec_code;
    wire        fifo_room;
    spi_decoder #(.LINE_UNIT(LINE_UNIT), .TRI_UNIT(TRI_UNIT)) u_dec (
        .clk(clk), .rst(rst), .cs_start(cs_start), .cs_end(cs_end), .cs_partial(cs_partial),
        .rx_valid(rx_valid), .rx_byte(rx_byte), .fifo_room(fifo_room),
        .chan(chan), .chan_valid(chan_valid), .fifo_din(fifo_din), .fifo_we(fifo_we),
        .fifo_commit(fifo_commit), .fifo_discard(fifo_discard), .err_valid(dec_err),
        .err_code(dec_code), .err_chan(dec_chan), .soft_rst(soft_rst), .snap(snap)
    );

    // The core's reset: rst or the SPI reset, a cycle late, from one flip-flop (it reaches
    // most of the block's flip-flops; a LUT there put every reset path a level deeper).
    reg core_rst;
    always @(posedge clk) core_rst <= rst | soft_rst;
    wire crst = core_rst;

    // Input FIFO and the executor.
    wire [37:0] data_out;
    wire        data_vld, fifo_next;
    wire [$clog2(`FITKIT_FIFO_RECORDS):0] free_count, occupancy;
    fifo36 u_fifo (
        .clk(clk), .rst(crst), .DATA_IN(fifo_din), .DATA_WE(fifo_we), .COMMIT(fifo_commit),
        .DISCARD(fifo_discard), .FIFO_NEXT(fifo_next), .DATA_OUT(data_out),
        .DATA_VLD(data_vld), .FIFO_FREE(fifo_free), .room(fifo_room),
        .free_count(free_count), .occupancy(occupancy)
    );

    wire [8:0]  wm1, hm1;
    wire [1:0]  cull;
    wire        setup_done, cnt_clr, clr_start, line_start, tri_start;
    wire        clr_done, line_done, tri_done, pkt_done, any_done, exec_busy, pipe_idle;
    wire [7:0]  clr_color;
    wire [70:9] pk;
    cmd_exec u_exec (
        .clk(clk), .rst(crst), .DATA_OUT(data_out), .DATA_VLD(data_vld),
        .FIFO_NEXT(fifo_next), .pipe_idle(pipe_idle), .wm1(wm1), .hm1(hm1), .cull(cull),
        .setup_done(setup_done), .cnt_clr(cnt_clr), .clr_start(clr_start),
        .clr_color(clr_color), .clr_done(clr_done), .line_start(line_start),
        .line_done(line_done), .tri_start(tri_start), .tri_done(tri_done), .packet(pk),
        .pkt_done(pkt_done), .any_done(any_done), .busy(exec_busy)
    );

    // Units.
    wire       frag_full;
    wire       c_busy, c_v, l_busy, l_v, t_busy, t_v;
    wire [8:0] c_x, c_y, l_x, l_y, t_x, t_y;
    wire [7:0] c_col, l_col, t_col;
    clear_unit u_clear (
        .clk(clk), .rst(crst), .start(clr_start), .wm1(wm1), .hm1(hm1), .color(clr_color),
        .busy(c_busy), .frag_valid(c_v), .frag_x(c_x), .frag_y(c_y), .frag_col(c_col),
        .frag_ready(~frag_full), .done(clr_done)
    );
    // A unit left out is idle: no fragment, never busy, never done (the decoder sends it
    // no packet).
    generate
        if (LINE_UNIT != 0) begin : g_line
            line_unit u_line (
                .clk(clk), .rst(crst), .start(line_start), .x0(pk[70:62]), .y0(pk[61:53]),
                .x1(pk[52:44]), .y1(pk[43:35]), .color(pk[34:27]), .busy(l_busy),
                .frag_valid(l_v), .frag_x(l_x), .frag_y(l_y), .frag_col(l_col),
                .frag_ready(~frag_full), .done(line_done)
            );
        end else begin : g_no_line
            // what only the line unit reads (the decoder never starts it)
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused = line_start;
            /* verilator lint_on UNUSEDSIGNAL */
            assign l_busy = 1'b0;
            assign l_v = 1'b0;
            assign l_x = 9'd0;
            assign l_y = 9'd0;
            assign l_col = 8'd0;
            assign line_done = 1'b0;
        end
        if (TRI_UNIT != 0 && TRI_SMALL != 0) begin : g_tri_small
            tri_small u_tri (
                .clk(clk), .rst(crst), .start(tri_start), .x0(pk[70:62]), .y0(pk[61:53]),
                .x1(pk[52:44]), .y1(pk[43:35]), .x2(pk[34:26]), .y2(pk[25:17]),
                .color(pk[16:9]), .wm1(wm1), .hm1(hm1), .cull(cull), .busy(t_busy),
                .frag_valid(t_v), .frag_x(t_x), .frag_y(t_y), .frag_col(t_col),
                .frag_ready(~frag_full), .done(tri_done)
            );
        end else if (TRI_UNIT != 0) begin : g_tri
            tri_unit #(.LANES(TRI_LANES)) u_tri (
                .clk(clk), .rst(crst), .start(tri_start), .x0(pk[70:62]), .y0(pk[61:53]),
                .x1(pk[52:44]), .y1(pk[43:35]), .x2(pk[34:26]), .y2(pk[25:17]), .color(pk[16:9]),
                .wm1(wm1), .hm1(hm1), .cull(cull), .busy(t_busy), .frag_valid(t_v), .frag_x(t_x),
                .frag_y(t_y), .frag_col(t_col), .frag_ready(~frag_full), .done(tri_done)
            );
        end else begin : g_no_tri
            // what only the triangle unit reads (the decoder never starts it)
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused = &{1'b0, tri_start, cull, pk[26:9]};
            /* verilator lint_on UNUSEDSIGNAL */
            assign t_busy = 1'b0;
            assign t_v = 1'b0;
            assign t_x = 9'd0;
            assign t_y = 9'd0;
            assign t_col = 8'd0;
            assign tri_done = 1'b0;
        end
    endgenerate

    // One producer runs at a time: the fragment is an OR of the (zeroed when idle) three.
    wire [26:0] frag_din = c_v ? {1'b0, c_col, c_y, c_x}
                         : l_v ? {1'b1, l_col, l_y, l_x}
                         :       {1'b1, t_col, t_y, t_x};
    wire [26:0] frag_dout;
    wire        frag_empty, frag_re;
    frag_fifo #(.W(27), .AW(4)) u_frag (
        .clk(clk), .rst(crst), .din(frag_din), .we(c_v | l_v | t_v), .full(frag_full),
        .dout(frag_dout), .empty(frag_empty), .re(frag_re)
    );

    // Memory port, read-back.
    wire        rd_req, rd_ack, rd_valid, frag_written, write_pending, underrun;
    wire [17:0] rd_addr;
    wire [7:0]  rd_data, rb_byte, st_byte;
    fb_writer u_wr (
        .clk(clk), .rst(crst), .wm1(wm1), .hm1(hm1), .frag_dout(frag_dout),
        .frag_empty(frag_empty), .frag_re(frag_re), .rd_req(rd_req), .rd_addr(rd_addr),
        .rd_ack(rd_ack), .rd_valid(rd_valid), .rd_data(rd_data),
        .frag_written(frag_written), .write_pending(write_pending), .mem_addr(mem_addr),
        .mem_wdata(mem_wdata), .mem_we(mem_we), .mem_re(mem_re), .mem_rdata(mem_rdata),
        .mem_wait(mem_wait)
    );
    readback u_rb (
        .clk(clk), .rst(crst), .cs_start(cs_start), .rx_valid(rx_valid), .rx_byte(rx_byte),
        .chan(chan), .chan_valid(chan_valid), .tx_load(tx_load),
        .byte_index(byte_index), .bit_start(bit_start), .tx_byte(rb_byte), .rd_req(rd_req),
        .rd_addr(rd_addr), .rd_ack(rd_ack), .rd_valid(rd_valid), .rd_data(rd_data),
        .underrun(underrun)
    );

    assign pipe_idle = frag_empty & ~write_pending;
    assign busy      = exec_busy | (|occupancy) | ~frag_empty | write_pending;

    status #(.LINE_UNIT(LINE_UNIT), .TRI_UNIT(TRI_UNIT)) u_status (
        .clk(clk), .rst(crst), .cnt_clr(cnt_clr), .pkt_done(pkt_done), .any_done(any_done),
        .frag_written(frag_written), .line_busy(l_busy), .tri_busy(t_busy),
        .clr_busy(c_busy), .commit(fifo_commit), .fifo_free(free_count),
        .fifo_occ(occupancy), .busy(busy), .setup_done(setup_done), .dec_err(dec_err),
        .dec_code(dec_code), .dec_chan(dec_chan), .underrun(underrun), .snap(snap),
        .byte_index(byte_index), .tx_byte(st_byte)
    );

    // The channel selects, registered: the channel is known from the address byte on,
    // at least 3 cycles before the first tx_load of a transaction (docs/rtl.md, SPI
    // framing), and the selects' compare stays off the path into the slave's shift register.
    reg sel_status, sel_read;
    always @(posedge clk) begin
        sel_status <= ~rst & chan_valid & (chan == `FITKIT_ADDR_STATUS);
        sel_read   <= ~rst & chan_valid & (chan == `FITKIT_ADDR_READ);
    end
    always @* begin
        if (sel_status) tx_byte = st_byte;
        else if (sel_read) tx_byte = rb_byte;
        else tx_byte = 8'd0;
    end
endmodule
`default_nettype wire
