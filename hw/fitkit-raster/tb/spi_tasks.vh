// SPI mode 0 master tasks shared by the testbenches (`include inside a module that has
// reg spi_sck, spi_cs_n, spi_mosi; wire spi_miso; and a parameter HALF, the SCK half
// period in time units).
task spi_begin;
    begin
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
        #(4 * HALF);
    end
endtask
