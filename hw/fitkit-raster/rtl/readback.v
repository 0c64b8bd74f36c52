// readback -- SPI channel 0x30: framebuffer bytes from consecutive addresses.
//
// Not in seed 000 (its frame was only seen on VGA); fpgfx needs it to compare frames.
// Transaction: address 0x30, 3 bytes start address (24 bits, the low 18 used), 1
// turnaround byte, then one pixel per byte. After the third address byte the unit
// prefetches up to two bytes through fb_writer's read port (one read in flight at a
// time), so each pixel has a whole SPI byte time (>= 64 clk cycles at f_SCK = f_clk/8)
// to arrive. A byte the master clocks (its first bit sampled) without the data having
// arrived is sent as 0 and reported as a read underrun (underrun strobe); its byte, when
// it comes, is dropped, so every later byte is still the one of its own address. A read
// still in flight when a new transaction starts is dropped on arrival.
//
// Ports: the spi_slave's events and chan / chan_valid from spi_decoder in; tx_byte is
// the byte for the slave while channel 0x30 is selected; rd_* to / from fb_writer.
// The channel and the header's length (address, start address, turnaround) are the
// generated map's (fitkit_map.vh), which the host reads by.
`default_nettype none
`include "fitkit_map.vh"
module readback (
    input  wire        clk,
    input  wire        rst,
    input  wire        cs_start,
    input  wire        rx_valid,
    input  wire [7:0]  rx_byte,
    input  wire [7:0]  chan,
    input  wire        chan_valid,
    input  wire        tx_load,
    input  wire [7:0]  byte_index,
    input  wire        bit_start,
    output wire [7:0]  tx_byte,
    output wire        rd_req,
    output wire [17:0] rd_addr,
    input  wire        rd_ack,
    input  wire        rd_valid,
    input  wire [7:0]  rd_data,
    output reg         underrun
);
    reg [17:0] addr;
    reg        en;
    reg [7:0]  b0, b1;       // b0 is the head
    reg [1:0]  cnt;
    reg        pend;         // a read is in flight
    reg        drop;         // ... and belongs to an earlier transaction
    reg        missing;      // the byte loaded last had no data
    reg [17:0] skip;         // bytes still to come whose slots went out as 0
    reg        owed;         // skip != 0, as a flip-flop for the queue's enables

    // Byte indices in the transaction: the last start-address byte, the first pixel.
    localparam [7:0] LAST_ADDR   = `FITKIT_READ_HEADER_BYTES - `FITKIT_READ_TURNAROUND - 1;
    localparam [7:0] FIRST_PIXEL = `FITKIT_READ_HEADER_BYTES;

    // registered: the channel is known bytes before a pixel slot, and byte_index changes
    // on a byte's last rising SCK edge, at least 4 clock cycles before the tx_load of the
    // next byte (docs/rtl.md, SPI framing), so one cycle late is early enough. A byte the
    // slave completes (rx_valid) is the one byte_index counted the cycle before (the
    // slave loads its rx_index from it with rx_valid), so the start address's byte
    // selects are flags of byte_index, registered with rx_valid: no compare lies between
    // the slave's strobe and the address's enables.
    reg active, pix, addr_slot, last_slot;
    always @(posedge clk) begin
        active    <= ~rst & chan_valid & (chan == `FITKIT_ADDR_READ);
        pix       <= ~rst & (byte_index >= FIRST_PIXEL);
        addr_slot <= ~rst & (byte_index >= 8'd1) & (byte_index <= LAST_ADDR);
        last_slot <= ~rst & (byte_index == LAST_ADDR);
    end
    wire addr_byte = rx_valid & active & addr_slot;   // a start-address byte came
    wire pop    = active & tx_load & pix;
    wire arrive = rd_valid & ~drop;
    // a slot sent as 0 now; with it, the bytes to drop (the next arriving is the oldest).
    // An arriving byte is kept only when nothing is owed: no earlier slot went out as 0
    // and this one does not. Tested on `skip` itself, not on skip + miss, so the add
    // stays off the path from the slave's byte strobe to the queue's enables.
    wire miss   = pop & (cnt == 2'd0);
    wire none_owed = ~owed & ~miss;
    wire push   = arrive & none_owed;
    wire [17:0] skip_up = skip + 18'd1;
    wire [17:0] skip_dn = skip - 18'd1;

    assign rd_req  = en & ~pend & (cnt != 2'd2);
    assign rd_addr = addr;
    assign tx_byte = (pix && cnt != 2'd0) ? b0 : 8'd0;

    always @(posedge clk) begin
        underrun <= 1'b0;
        if (rst) begin
            addr    <= 18'd0;
            en      <= 1'b0;
            b0      <= 8'd0;
            b1      <= 8'd0;
            cnt     <= 2'd0;
            pend    <= 1'b0;
            drop    <= 1'b0;
            missing <= 1'b0;
            skip    <= 18'd0;
            owed    <= 1'b0;
        end else begin
            if (rd_ack) begin
                pend <= 1'b1;
                addr <= addr + 18'd1;
            end else if (rd_valid) begin
                pend <= 1'b0;
                drop <= 1'b0;
            end
            if (cs_start) begin
                en      <= 1'b0;
                cnt     <= 2'd0;
                missing <= 1'b0;
                skip    <= 18'd0;
                owed    <= 1'b0;
                drop    <= (pend & ~rd_valid) | rd_ack;
            end else begin
                if (addr_byte) begin
                    addr <= {addr[9:0], rx_byte};
                    en   <= last_slot;
                end
                // Queue: pop the head and / or push at the tail.
                case ({push, pop & (cnt != 2'd0)})
                    2'b10: begin
                        if (cnt == 2'd0) b0 <= rd_data; else b1 <= rd_data;
                        cnt <= cnt + 2'd1;
                    end
                    2'b01: begin
                        b0  <= b1;
                        cnt <= cnt - 2'd1;
                    end
                    2'b11: begin
                        if (cnt == 2'd1) b0 <= rd_data;
                        else begin
                            b0 <= b1;
                            b1 <= rd_data;
                        end
                    end
                    default: ;
                endcase
                if (pop) missing <= cnt == 2'd0;
                // skip + miss, less the byte dropped now (none when nothing was owed); the
                // sums are taken from registers and chosen by miss and arrive, so the
                // slave's strobe reaches skip through no carry chain
                if (!none_owed) begin
                    skip <= (miss == arrive) ? skip : miss ? skip_up : skip_dn;
                    // whether the new count is not 0, from the old one's value (compares
                    // of the register, no sum in the way)
                    owed <= (miss == arrive) ? owed : miss ? (skip != 18'h3FFFF)
                                                           : (skip != 18'd1);
                end
                if (active && bit_start && missing) begin
                    underrun <= 1'b1;
                    missing  <= 1'b0;
                end
            end
        end
    end

`ifdef FORMAL
    // The stream keeps to its addresses: with any memory (one arbitrary address f_a is
    // followed, whose reads return f_d), every pixel slot the master clocks sends the byte
    // of its own address (start + k for slot k) or, when that byte is late, 0 -- never a
    // neighbour's. The environment: the decoder gives one start address per transaction
    // and pixel slots only after it; the port acks only what is requested and answers
    // only the read in flight.
    reg         reset_seen = 1'b0, f_flight = 1'b0;
    reg  [17:0] f_flight_addr = 18'd0, f_slot = 18'd0;
    (* anyconst *) reg [17:0] f_a;
    (* anyconst *) reg [7:0]  f_d;
    always @(*) begin
        if (rd_ack) assume (rd_req);
        if (rd_valid) assume (f_flight && !rd_ack);
        if (rd_valid && f_flight_addr == f_a) assume (rd_data == f_d);
        if (pop) assume (en && !cs_start);
        if (en) assume (!addr_byte);
    end
    always @(posedge clk) begin
        if (rst) begin
            reset_seen <= 1'b1;
            f_flight <= 1'b0;
        end else begin
            if (rd_ack) begin
                f_flight <= 1'b1;
                f_flight_addr <= rd_addr;
            end else if (rd_valid) begin
                f_flight <= 1'b0;
            end
            if (!cs_start && addr_byte && last_slot) f_slot <= {addr[9:0], rx_byte};
            else if (pop) f_slot <= f_slot + 18'd1;
        end
    end
    wire [17:0] f_mine = {17'd0, pend && !drop};   // the read in flight is this stream's
    always @(*) begin
        if (reset_seen) begin
            assert (pend == f_flight && cnt <= 2'd2 && (pend || !drop));
            if (pend && !drop) assert (f_flight_addr == addr - 18'd1);
            if (!en) assert (!(pend && !drop) && cnt == 2'd0 && skip == 18'd0);
            if (skip != 18'd0) assert (cnt == 2'd0);
            assert (owed == (skip != 18'd0));
            // the queue and the read in flight: two bytes at most
            assert ({1'b0, cnt} + {2'd0, pend && !drop} <= 3'd2);
            if (en) begin
                // requested = served + queued + in flight + dropped, in addresses
                assert (addr + skip == f_slot + {16'd0, cnt} + f_mine);
                if (cnt != 2'd0 && f_slot == f_a) assert (b0 == f_d);
                if (cnt == 2'd2 && f_slot + 18'd1 == f_a) assert (b1 == f_d);
                // the property: a slot sent with data sends its address's byte
                if (pop && cnt != 2'd0 && f_slot == f_a) assert (tx_byte == f_d);
            end
        end
    end
`endif
endmodule
`default_nettype wire
