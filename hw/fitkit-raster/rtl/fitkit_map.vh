// fitkit_map.vh -- the FITkit raster block's SPI map, status layout and FIFO geometry.
//
// GENERATED from protocol::fitkit_spi::MAP (protocol/src/fitkit_spi.rs); do not edit.
// `FPGFX_BLESS=1 cargo test -p protocol --test integration fitkit_map` rewrites it.
`ifndef FITKIT_MAP_VH
`define FITKIT_MAP_VH
// set-up packet (frame size, background, culling, then a clear)
`define FITKIT_ADDR_SETUP 8'h00
// line packets (2 records)
`define FITKIT_ADDR_LINE 8'h01
// triangle packets (2 records)
`define FITKIT_ADDR_TRIANGLE 8'h02
// stand-alone clear packets (1 record)
`define FITKIT_ADDR_CLEAR 8'h03
// status block read
`define FITKIT_ADDR_STATUS 8'h20
// framebuffer read-back
`define FITKIT_ADDR_READ 8'h30
// block reset, no payload
`define FITKIT_ADDR_RESET 8'h7F
// bits of one input FIFO record
`define FITKIT_RECORD_BITS 36
// records the input FIFO holds
`define FITKIT_FIFO_RECORDS 512
// payload bytes of the widest packet
`define FITKIT_MAX_PACKET_BYTES 9
// side of the framebuffer the coordinates address
`define FITKIT_FRAME_SIDE 512
// bits of a coordinate
`define FITKIT_COORD_BITS 9
// bits of a colour (RGB332)
`define FITKIT_COLOR_BITS 8
// bytes of the status block
`define FITKIT_STATUS_BYTES 32
// bytes between the read-back's address and its first pixel
`define FITKIT_READ_TURNAROUND 1
// bytes before the first pixel of a read-back
`define FITKIT_READ_HEADER_BYTES 5
// bits of an error code
`define FITKIT_ERR_BITS 3
// flags bit: a packet is queued or executing
`define FITKIT_FLAG_BUSY 0
// flags bit: a sticky error is latched
`define FITKIT_FLAG_ERROR 1
// flags bit: the input FIFO is empty
`define FITKIT_FLAG_FIFO_EMPTY 2
// flags bit: a set-up has run since reset
`define FITKIT_FLAG_SETUP_DONE 3
// flags bit: this build has no line unit
`define FITKIT_FLAG_NO_LINE 4
// flags bit: this build has no triangle unit
`define FITKIT_FLAG_NO_TRIANGLE 5
// status offset: free records, 2 bytes
`define FITKIT_STATUS_FREE 0
// status offset: flags
`define FITKIT_STATUS_FLAGS 2
// status offset: error code
`define FITKIT_STATUS_ERROR_CODE 3
// status offset: the failing packet's address
`define FITKIT_STATUS_ERROR_CHANNEL 4
// status offset: the failing packet's index, 2 bytes
`define FITKIT_STATUS_ERROR_PACKET 5
// status offset: packets executed, 4 bytes
`define FITKIT_STATUS_PACKETS 7
// status offset: fragments written, 4 bytes
`define FITKIT_STATUS_FRAGMENTS 11
// status offset: line unit busy cycles, 4 bytes
`define FITKIT_STATUS_LINE_CYCLES 15
// status offset: triangle unit busy cycles, 4 bytes
`define FITKIT_STATUS_TRIANGLE_CYCLES 19
// status offset: clearing cycles, 4 bytes
`define FITKIT_STATUS_CLEAR_CYCLES 23
// status offset: the last packet's end cycle, 4 bytes
`define FITKIT_STATUS_END_CYCLE 27
// status offset: highest FIFO occupancy / 2
`define FITKIT_STATUS_FIFO_MAX_PAIRS 31
// error code: wrong payload length
`define FITKIT_ERR_LENGTH 3'd1
// error code: non-zero padding
`define FITKIT_ERR_PADDING 3'd2
// error code: input FIFO overrun
`define FITKIT_ERR_OVERRUN 3'd3
// error code: clear without CB
`define FITKIT_ERR_CLEAR_WITHOUT_CB 3'd4
// error code: unknown address
`define FITKIT_ERR_UNKNOWN_ADDRESS 3'd5
// error code: read-back underrun
`define FITKIT_ERR_READ_UNDERRUN 3'd6
`endif
