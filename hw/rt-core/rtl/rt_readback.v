// rt_readback -- the read-back slave and window of the ray-casting core's device: the
// frame and AOV planes the core wrote to memory, given back over AXI4-Lite in the byte
// layout protocol::axi_lite's READ_* registers define (seed 002 §3.8 reads the frame
// back to the host; the register-file model's window, sim-target's mmio.rs and
// device.rs `read_len`/`read`, is the specification this follows byte for byte).
//
// Registers: READ_PLANE and READ_FORMAT (codes; an unknown code is refused), READ_RECT_XY
// and READ_RECT_WH (x | y << 16, w | h << 16), READ_PAGE, and READ_LEN (read only): the
// bytes of the read-back, w h times the format's bytes per pixel, or READ_NONE when there
// is none: no frame since reset, the rectangle not inside the frame, a plane and format
// that do not go together (colour: RGB888, RGB332, KCU116; depth: DEPTH_F32; normal:
// NORMAL_F32), or an AOV plane of a frame that did not write them (AOVS at its start).
// The window word at byte `off` holds read-back bytes PAGE * READ_WINDOW + off .. + 3,
// little-endian; bytes past READ_LEN in the last word read 0. Refused (SLVERR): READ_LEN
// or a window word while a frame runs or is about to (`busy`), a window word with no
// read-back or at or past READ_LEN, writes to READ_LEN or the window, and every other
// address of the slave.
//
// Byte layout per pixel, the model's: RGB888 R, G, B; RGB332 the nearest of the levels
// bit replication gives back, ties to the darker (protocol's quantize_rgb332); KCU116 G,
// then B on even and R on odd columns of the rectangle (the model packs the rectangle,
// not the frame); DEPTH_F32 the distance as binary32 (q16_to_f32: the model's `to_f64()
// as f32`), +inf for a miss; NORMAL_F32 x, y, z as binary32, zeros for a miss.
//
// How a word is found: a cursor keeps the byte offset after the last word read with the
// pixel's memory index, its column in the rectangle and the byte within the pixel, so the
// next word in sequence (what a driver reads) costs only steps; any other offset seeks by
// two serial divisions (offset / bytes per pixel, then pixel / w: 33 clocks each) and one
// multiplication. Each pixel is read once from memory and, for the AOV formats, its four
// words converted through one q16_to_f32 in turn.
//
// Memory read port: rd_valid with rd_index (y W + x of the frame, as the write port
// numbers pixels) until rd_ready; the record comes back on any later clock with rd_resp
// (rd_rgb R in bits 23:16, rd_obj 8'hff for a miss, rd_t, rd_n x in bits 31:0). One read
// is outstanding at a time.
//
// Ports: req, req_wr, req_addr, req_data (one access, rt_axil; only addresses of this
// slave and the window), answered by ack, ack_err, ack_data. busy; shown, shown_w,
// shown_h, shown_aovs (the last frame started since reset: its size and whether it wrote
// the AOV planes); stale (a frame starts: the memory changes under the cursor). rd_*.
// Timing: a register access is answered the clock after its request; a window word
// after 5 clocks at the least (the next word of a colour plane, its pixel read before),
// about 80 plus 3 per pixel read and 6 per conversion at the most.
// Parameters: AW address bits, at least `RT_AXI_ADDR_BITS`.
`default_nettype none
`include "rt_axi_map.vh"
module rt_readback #(
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
    output reg  [31:0]   ack_data,
    input  wire          busy,
    input  wire          shown,
    input  wire [15:0]   shown_w,
    input  wire [15:0]   shown_h,
    input  wire          shown_aovs,
    input  wire          stale,
    output reg           rd_valid,
    input  wire          rd_ready,
    output reg  [31:0]   rd_index,
    input  wire          rd_resp,
    input  wire [23:0]   rd_rgb,
    input  wire [7:0]    rd_obj,
    input  wire [31:0]   rd_t,
    input  wire [95:0]   rd_n
);
    generate
        if (AW < `RT_AXI_ADDR_BITS || AW > 32 || `RT_AXI_READ_WINDOW != 32'h4000)
        begin : bad_parameter
            rt_readback_parameter_out_of_range unsupported();
        end
    endgenerate

    wire [31:0] a = {{(32 - AW){1'b0}}, req_addr};

    // ---- the registers ----------------------------------------------------------------------
    reg  [1:0]  plane;
    reg  [2:0]  format;
    reg  [31:0] rect_xy, rect_wh, page;
    wire [15:0] rx = rect_xy[15:0], ry = rect_xy[31:16];
    wire [15:0] rw = rect_wh[15:0], rh = rect_wh[31:16];
    reg  [3:0]  bpp;
    always @(*) begin
        case (format)
            `RT_AXI_FORMAT_RGB888: bpp = `RT_AXI_BPP_RGB888;
            `RT_AXI_FORMAT_RGB332: bpp = `RT_AXI_BPP_RGB332;
            `RT_AXI_FORMAT_KCU116: bpp = `RT_AXI_BPP_KCU116;
            `RT_AXI_FORMAT_DEPTH_F32: bpp = `RT_AXI_BPP_DEPTH_F32;
            default: bpp = `RT_AXI_BPP_NORMAL_F32;
        endcase
    end
    wire in_frame = {1'b0, rx} + {1'b0, rw} <= {1'b0, shown_w} &&
                  {1'b0, ry} + {1'b0, rh} <= {1'b0, shown_h};
    wire colour = format == `RT_AXI_FORMAT_RGB888 || format == `RT_AXI_FORMAT_RGB332 ||
                  format == `RT_AXI_FORMAT_KCU116;
    wire pairs = plane == `RT_AXI_PLANE_COLOR ? colour :
                 plane == `RT_AXI_PLANE_DEPTH ? format == `RT_AXI_FORMAT_DEPTH_F32 && shown_aovs :
                 format == `RT_AXI_FORMAT_NORMAL_F32 && shown_aovs;
    wire        have = shown && in_frame && pairs;
    wire [31:0] area = {16'd0, rw} * {16'd0, rh};
    /* verilator lint_off UNUSEDSIGNAL */
    wire [35:0] len_wide = {4'd0, area} * {32'd0, bpp};  // the model's u32 product
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] len = len_wide[31:0];

    // the window word's offset in the read-back (a page past 2^18 is past any length)
    /* verilator lint_off UNUSEDSIGNAL */
    wire [31:0] win_off = a - `RT_AXI_READ_BASE;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] off = {page[17:0], win_off[13:0]};
    wire        in_window = a >= `RT_AXI_READ_BASE && a < `RT_AXI_READ_BASE + `RT_AXI_READ_WINDOW;
    wire        past = page[31:18] != 14'd0 || off >= len;

    // ---- the cursor and the pixel read last -----------------------------------------------------
    reg        cur_ok;        // cur_* describe byte cur_off
    reg [31:0] cur_off, cur_index;
    reg [15:0] cur_col;
    reg [3:0]  cur_b;
    reg        pix_ok;        // pix_* hold the record at pix_index, converted if an AOV format
    reg [31:0] pix_index;
    reg [23:0] pix_rgb;
    reg [7:0]  pix_obj;
    reg [31:0] pix_f [0:3];   // t, n.x, n.y, n.z as binary32

    // ---- the read of one window word ------------------------------------------------------------
    localparam [2:0] S_IDLE = 3'd0, S_DIV = 3'd1, S_BYTE = 3'd2, S_READ = 3'd3, S_WAIT = 3'd4,
                     S_CONV = 3'd5;
    reg [2:0]  st;
    reg [31:0] w_off;         // the word's first byte
    reg [2:0]  k;             // its byte now
    reg [31:0] word;
    reg        dv_second;     // the division is pixel / w (else offset / bpp)
    reg [5:0]  dv_i;
    reg [31:0] dv_n;          // dividend, the quotient shifting in from the right
    reg [15:0] dv_r;          // remainder (< the divisor)
    reg [15:0] dv_d;
    wire [16:0] dv_t = {dv_r, dv_n[31]};
    wire        dv_ge = dv_t >= {1'b0, dv_d};
    // both below the divisor when kept, so 16 bits
    /* verilator lint_off UNUSEDSIGNAL */
    wire [16:0] dv_sub = dv_t - {1'b0, dv_d};
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] row_index = ({15'd0, {1'b0, ry} + {1'b0, dv_n[15:0]}}) * {16'd0, shown_w};
    reg [2:0]  cv_in, cv_out;  // conversions started, finished
    reg [31:0] rd_t_q;         // the record's words, converted in turn
    reg [95:0] rd_n_q;

    wire [31:0] byte_at = w_off + {29'd0, k};
    wire        row_end = cur_col == rw - 16'd1;
    wire        pix_end = cur_b == bpp - 4'd1;

    // the pixel's byte cur_b in the format
    function [2:0] level3(input [7:0] v);  // nearest of k << 5 | k << 2 | k >> 1, ties down
        integer i;
        reg [7:0] e;
        reg [8:0] best, d;
        begin
            level3 = 3'd0;
            best = 9'h1ff;
            for (i = 0; i < 8; i = i + 1) begin
                e = {i[2:0], i[2:0], i[2:1]};
                d = v >= e ? {1'b0, v - e} : {1'b0, e - v};
                if (d < best) begin
                    best = d;
                    level3 = i[2:0];
                end
            end
        end
    endfunction
    function [1:0] level2(input [7:0] v);  // nearest of k * 0x55, ties down
        integer i;
        reg [7:0] e;
        reg [8:0] best, d;
        begin
            level2 = 2'd0;
            best = 9'h1ff;
            for (i = 0; i < 4; i = i + 1) begin
                e = {i[1:0], i[1:0], i[1:0], i[1:0]};
                d = v >= e ? {1'b0, v - e} : {1'b0, e - v};
                if (d < best) begin
                    best = d;
                    level2 = i[1:0];
                end
            end
        end
    endfunction
    wire        miss = pix_obj == 8'hff;
    wire [31:0] fword = format == `RT_AXI_FORMAT_DEPTH_F32 ?
                            (miss ? 32'h7f80_0000 : pix_f[0]) :
                            (miss ? 32'd0 : pix_f[cur_b[3:2] + 2'd1]);
    reg  [7:0]  pix_byte;
    always @(*) begin
        case (format)
            `RT_AXI_FORMAT_RGB888:
                pix_byte = cur_b == 4'd0 ? pix_rgb[23:16] :
                           cur_b == 4'd1 ? pix_rgb[15:8] : pix_rgb[7:0];
            `RT_AXI_FORMAT_RGB332:
                pix_byte = {level3(pix_rgb[23:16]), level3(pix_rgb[15:8]), level2(pix_rgb[7:0])};
            `RT_AXI_FORMAT_KCU116:
                pix_byte = cur_b == 4'd0 ? pix_rgb[15:8] :
                           cur_col[0] ? pix_rgb[23:16] : pix_rgb[7:0];
            default: pix_byte = fword[{cur_b[1:0], 3'd0} +: 8];
        endcase
    end

    wire        cv_valid;
    wire [31:0] cv_y;
    reg  [31:0] cv_q;
    always @(*) begin
        case (cv_in[1:0])
            2'd0: cv_q = rd_t_q;
            2'd1: cv_q = rd_n_q[31:0];
            2'd2: cv_q = rd_n_q[63:32];
            default: cv_q = rd_n_q[95:64];
        endcase
    end
    q16_to_f32 u_f32 (.clk(clk), .rst(rst), .ce(1'b1), .in_valid(st == S_CONV && !cv_in[2]),
        .q(cv_q), .out_valid(cv_valid), .y(cv_y));

    // what a register read gives
    reg [31:0] reg_word;
    always @(*) begin
        case (a)
            `RT_AXI_READ_PLANE: reg_word = {30'd0, plane};
            `RT_AXI_READ_FORMAT: reg_word = {29'd0, format};
            `RT_AXI_READ_RECT_XY: reg_word = rect_xy;
            `RT_AXI_READ_RECT_WH: reg_word = rect_wh;
            `RT_AXI_READ_LEN: reg_word = have ? len : `RT_AXI_READ_NONE;
            default: reg_word = page;
        endcase
    end
    wire reg_known = a == `RT_AXI_READ_PLANE || a == `RT_AXI_READ_FORMAT ||
                     a == `RT_AXI_READ_RECT_XY || a == `RT_AXI_READ_RECT_WH ||
                     a == `RT_AXI_READ_LEN || a == `RT_AXI_READ_PAGE;

    always @(posedge clk) begin
        if (rst) begin
            ack <= 1'b0;
            ack_err <= 1'b0;
            ack_data <= 32'd0;
            plane <= `RT_AXI_PLANE_COLOR;
            format <= `RT_AXI_FORMAT_RGB888;
            rect_xy <= 32'd0;
            rect_wh <= 32'd0;
            page <= 32'd0;
            cur_ok <= 1'b0;
            pix_ok <= 1'b0;
            rd_valid <= 1'b0;
            st <= S_IDLE;
        end else begin
            ack <= 1'b0;
            ack_err <= 1'b0;
            if (stale) begin
                cur_ok <= 1'b0;
                pix_ok <= 1'b0;
            end
            case (st)
                S_IDLE: if (req) begin
                    ack_data <= 32'd0;
                    if (req_wr) begin
                        ack <= 1'b1;
                        // a new mapping of bytes to pixels: the cursor and the pixel go
                        if (a != `RT_AXI_READ_PAGE) begin
                            cur_ok <= 1'b0;
                            pix_ok <= 1'b0;
                        end
                        case (a)
                            `RT_AXI_READ_PLANE:
                                if (req_data < `RT_AXI_PLANE_CODES) plane <= req_data[1:0];
                                else ack_err <= 1'b1;
                            `RT_AXI_READ_FORMAT:
                                if (req_data < `RT_AXI_FORMAT_CODES) format <= req_data[2:0];
                                else ack_err <= 1'b1;
                            `RT_AXI_READ_RECT_XY: rect_xy <= req_data;
                            `RT_AXI_READ_RECT_WH: rect_wh <= req_data;
                            `RT_AXI_READ_PAGE: page <= req_data;
                            default: ack_err <= 1'b1;  // READ_LEN, the window, the rest
                        endcase
                    end else if (in_window) begin
                        if (busy || !have || past) begin
                            ack <= 1'b1;
                            ack_err <= 1'b1;
                        end else begin
                            w_off <= off;
                            k <= 3'd0;
                            word <= 32'd0;
                            if (cur_ok && cur_off == off) st <= S_BYTE;
                            else begin
                                // seek: offset / bytes per pixel first
                                st <= S_DIV;
                                dv_second <= 1'b0;
                                dv_i <= 6'd0;
                                dv_n <= off;
                                dv_r <= 16'd0;
                                dv_d <= {12'd0, bpp};
                            end
                        end
                    end else begin
                        ack <= 1'b1;
                        if (!reg_known || (a == `RT_AXI_READ_LEN && busy)) ack_err <= 1'b1;
                        else ack_data <= reg_word;
                    end
                end
                S_DIV: begin
                    if (dv_i != 6'd32) begin
                        dv_r <= dv_ge ? dv_sub[15:0] : dv_t[15:0];
                        dv_n <= {dv_n[30:0], dv_ge};
                        dv_i <= dv_i + 6'd1;
                    end else if (!dv_second) begin
                        // the pixel and its byte; then pixel / w for its row and column
                        cur_b <= dv_r[3:0];
                        dv_second <= 1'b1;
                        dv_i <= 6'd0;
                        dv_r <= 16'd0;
                        dv_d <= rw;
                    end else begin
                        // dv_n: the row in the rectangle (< h), dv_r: the column
                        cur_col <= dv_r;
                        cur_index <= row_index + {16'd0, rx} + {16'd0, dv_r};
                        cur_off <= w_off;
                        cur_ok <= 1'b1;
                        st <= S_BYTE;
                    end
                end
                S_BYTE: begin
                    if (k == 3'd4) begin
                        ack <= 1'b1;
                        ack_data <= word;
                        st <= S_IDLE;
                    end else if (byte_at >= len) begin
                        // past the read-back's end: 0, and the cursor has nowhere to go
                        k <= k + 3'd1;
                        cur_ok <= 1'b0;
                    end else if (!pix_ok || pix_index != cur_index) begin
                        st <= S_READ;
                        rd_valid <= 1'b1;
                        rd_index <= cur_index;
                    end else begin
                        word[{k[1:0], 3'd0} +: 8] <= pix_byte;
                        k <= k + 3'd1;
                        cur_off <= cur_off + 32'd1;
                        if (!pix_end) cur_b <= cur_b + 4'd1;
                        else begin
                            cur_b <= 4'd0;
                            if (!row_end) begin
                                cur_col <= cur_col + 16'd1;
                                cur_index <= cur_index + 32'd1;
                            end else begin
                                cur_col <= 16'd0;
                                cur_index <= cur_index + 32'd1 + {16'd0, shown_w - rw};
                            end
                        end
                    end
                end
                S_READ: if (rd_ready) begin
                    rd_valid <= 1'b0;
                    st <= S_WAIT;
                end
                S_WAIT: if (rd_resp) begin
                    pix_index <= rd_index;
                    pix_rgb <= rd_rgb;
                    pix_obj <= rd_obj;
                    rd_t_q <= rd_t;
                    rd_n_q <= rd_n;
                    if (colour) begin
                        pix_ok <= 1'b1;
                        st <= S_BYTE;
                    end else begin
                        cv_in <= 3'd0;
                        cv_out <= 3'd0;
                        st <= S_CONV;
                    end
                end
                S_CONV: begin
                    if (!cv_in[2]) cv_in <= cv_in + 3'd1;
                    if (cv_valid) begin
                        pix_f[cv_out[1:0]] <= cv_y;
                        cv_out <= cv_out + 3'd1;
                        if (cv_out == 3'd3) begin
                            pix_ok <= 1'b1;
                            st <= S_BYTE;
                        end
                    end
                end
                default: st <= S_IDLE;
            endcase
        end
    end

`ifdef FORMAL
    // The bus side (rt_axil promises one request at a time): every request is answered
    // exactly once, and nothing is answered without one; the memory read is held until
    // taken, and only a word's read makes one.
    reg pending;
    initial assume (rst);
    always @(posedge clk) begin
        if (rst) pending <= 1'b0;
        else if (req) pending <= 1'b1;
        else if (ack) pending <= 1'b0;
    end
    always @(*) if (pending) assume (!req);
    always @(*) begin
        if (!rst) begin
            if (!pending) assert (st == S_IDLE && !ack && !rd_valid);
            if (pending && st == S_IDLE) assert (ack);
            if (st != S_IDLE) assert (!ack && pending);
            assert (rd_valid == (st == S_READ));
            assert (st <= S_CONV);
            if (st == S_BYTE) assert (k <= 3'd4);
            if (st != S_IDLE && st != S_BYTE) assert (k <= 3'd3);
            if (st == S_DIV) assert (dv_i <= 6'd32);
        end
    end
`endif
endmodule
`default_nettype wire
