// SPI mode 0 master tasks shared by the block's testbenches and the vectors testbench
// (`fpgfx vectors raster` writes a copy beside tb_fpgfx.v). `include inside a module that
// has reg spi_sck, spi_cs_n, spi_mosi; wire spi_miso; a clock clk; and two parameters:
// HALF, the SCK half period, and CS_GAP, how long CS_n stays high after a transaction
// (both in time units).
//
// spi_begin waits for a falling clk edge, so CS_n and every later SCK edge fall half a
// clock away from the block's rising edge whatever the caller waited on before (a
// `@(posedge clk)` just ahead of it would otherwise race the synchroniser).
task spi_begin;
    begin
        @(negedge clk);
        spi_cs_n = 1'b0;
        #(HALF);
    end
endtask

task spi_xfer(input [7:0] tx, output [7:0] rx);
    integer b;
    begin
        for (b = 7; b >= 0; b = b - 1) begin
            spi_mosi = tx[b];
            #(HALF);
            spi_sck = 1'b1;
            rx[b] = spi_miso;
            #(HALF);
            spi_sck = 1'b0;
        end
    end
endtask

task spi_end;
    begin
        #(HALF);
        spi_cs_n = 1'b1;
        spi_mosi = 1'b0;
        #(CS_GAP);
    end
endtask
