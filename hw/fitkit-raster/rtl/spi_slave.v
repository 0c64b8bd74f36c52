// spi_slave -- SPI mode 0 slave, oversampled in the block's clock domain.
//
// Seed 000 ch. 6.1 (MCU control: the SPI link from the MSP430 to the FPGA). The seed's
// slave ran on SCK itself; here SCK, CS_n and MOSI are two-flop synchronised into clk so
// the whole block has one clock domain. That needs f_SCK <= f_clk / 8: a half period of
// SCK must span at least 4 clk cycles, because MISO changes 3 cycles after the falling
// edge it answers (2 synchroniser flops + the output register) and must be stable at
// the next rising edge.
//
// Ports
//   spi_sck, spi_cs_n, spi_mosi  asynchronous pins; spi_miso is 0 while spi_cs_n is high.
//   cs_start / cs_end            one-cycle pulses when CS_n falls / rises; cs_partial is
//                                valid with cs_end: bits of an unfinished byte were clocked.
//   rx_valid, rx_byte            a byte completed (8th rising SCK edge); its position in
//                                the transaction (0 = address) is byte_index of the cycle
//                                before rx_valid (byte_index counts it with rx_valid), so a
//                                unit registers its byte-position flags from byte_index and
//                                has them with rx_valid.
//   byte_index                   bytes completed so far in this transaction (the index of
//                                the byte now being shifted), saturating at 255.
//   tx_load                      combinational strobe: tx_byte is sampled now as byte
//                                byte_index (falling edge after the previous byte). Byte 0
//                                (during the address) is always 0.
//   bit_start                    combinational strobe: the master samples the first bit
//                                (MSB) of byte byte_index now.
//
// Timing: rx_valid comes 3 clk cycles after the 8th rising SCK edge; tx_byte must be
// valid from then on until tx_load (at least 4 cycles later at f_SCK = f_clk / 8).
`default_nettype none
module spi_slave (
    input  wire       clk,
    input  wire       rst,
    input  wire       spi_sck,
    input  wire       spi_cs_n,
    input  wire       spi_mosi,
    output wire       spi_miso,
    output reg        cs_start,
    output reg        cs_end,
    output reg        cs_partial,
    output reg        rx_valid,
    output reg  [7:0] rx_byte,
    output wire [7:0] byte_index,
    output wire       tx_load,
    input  wire [7:0] tx_byte,
    output wire       bit_start
);
    reg [2:0] sck_s;
    reg [2:0] cs_s;
    reg [1:0] mosi_s;
    reg       active;
    reg [2:0] bitcnt;
    reg [6:0] rx_sh;
    reg [7:0] nbytes;
    reg       nnz;         // nbytes != 0, kept as a flip-flop for tx_load
    reg [6:0] tx_sh;
    reg       miso_r;

    wire sck_rise = sck_s[1] & ~sck_s[2];
    wire sck_fall = ~sck_s[1] & sck_s[2];
    wire cs_fall  = ~cs_s[1] & cs_s[2];
    wire cs_rise  = cs_s[1] & ~cs_s[2];
    wire run      = active & ~cs_fall & ~cs_rise;

    assign byte_index = nbytes;
    assign tx_load    = run & sck_fall & (bitcnt == 3'd0) & nnz;
    assign bit_start  = run & sck_rise & (bitcnt == 3'd0);
    assign spi_miso   = miso_r & ~spi_cs_n;

    always @(posedge clk) begin
        // CS_n's synchroniser resets to low: a reset while the master holds CS_n low then
        // sees no falling edge, and the rest of that transaction is no packet (no cs_start,
        // no byte, no cs_end: the slave is inactive until CS_n has been high). A reset
        // while CS_n is high shows a rising edge to an inactive slave, which does nothing.
        if (rst) begin
            sck_s  <= 3'b000;
            cs_s   <= 3'b000;
            mosi_s <= 2'b00;
        end else begin
            sck_s  <= {sck_s[1:0], spi_sck};
            cs_s   <= {cs_s[1:0], spi_cs_n};
            mosi_s <= {mosi_s[0], spi_mosi};
        end
    end

    always @(posedge clk) begin
        cs_start <= 1'b0;
        cs_end   <= 1'b0;
        rx_valid <= 1'b0;
        if (rst) begin
            active     <= 1'b0;
            bitcnt     <= 3'd0;
            rx_sh      <= 7'd0;
            nbytes     <= 8'd0;
            nnz        <= 1'b0;
            tx_sh      <= 7'd0;
            miso_r     <= 1'b0;
            cs_partial <= 1'b0;
            rx_byte    <= 8'd0;
        end else if (cs_fall) begin
            active   <= 1'b1;
            bitcnt   <= 3'd0;
            nbytes   <= 8'd0;
            nnz      <= 1'b0;
            tx_sh    <= 7'd0;
            miso_r   <= 1'b0;
            cs_start <= 1'b1;
        end else if (cs_rise) begin
            active     <= 1'b0;
            miso_r     <= 1'b0;
            cs_end     <= active;
            cs_partial <= bitcnt != 3'd0;
        end else if (active) begin
            if (sck_rise) begin
                rx_sh  <= {rx_sh[5:0], mosi_s[1]};
                bitcnt <= bitcnt + 3'd1;
                if (bitcnt == 3'd7) begin
                    rx_valid <= 1'b1;
                    rx_byte  <= {rx_sh, mosi_s[1]};
                    if (nbytes != 8'hFF) nbytes <= nbytes + 8'd1;
                    nnz <= 1'b1;
                end
            end
            if (sck_fall) begin
                if (tx_load) begin
                    tx_sh  <= tx_byte[6:0];
                    miso_r <= tx_byte[7];
                end else begin
                    tx_sh  <= {tx_sh[5:0], 1'b0};
                    miso_r <= tx_sh[6];
                end
            end
        end
    end

`ifdef FORMAL
    // A reset at any cycle leaves no partial transaction behind: after a reset no
    // transaction starts before CS_n has been high (a reset while the master holds CS_n
    // low is not a new CS_n fall), and until one starts the slave gives no byte, no end
    // and no transmit strobe. The strobes keep to the slave's state: a transaction starts
    // as it goes active and ends as it goes inactive, and bytes come while it is active.
    reg reset_seen = 1'b0, cs_high_seen = 1'b0, idle_since_rst = 1'b0;
    always @(posedge clk) begin
        if (rst) begin
            reset_seen <= 1'b1;
            cs_high_seen <= 1'b0;
            idle_since_rst <= 1'b1;
        end else begin
            if (spi_cs_n) cs_high_seen <= 1'b1;
            if (cs_fall) idle_since_rst <= 1'b0;
        end
    end
    always @(*) begin
        if (reset_seen) begin
            if (cs_start) assert (cs_high_seen);
            if (idle_since_rst) assert (!active && !rx_valid && !cs_end && !tx_load && !bit_start);
            if (cs_end) assert (!active);
            if (cs_start || rx_valid) assert (active);
            // the synchroniser holds no high CS_n the pin has not shown since the reset
            if (!cs_high_seen) assert (cs_s == 3'b000);
            assert (nnz == (nbytes != 8'd0));
        end
    end
`endif
endmodule
`default_nettype wire
