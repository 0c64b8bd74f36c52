// rt_axi_map.vh -- the AXI4-Lite map of the ray-casting core's device.
//
// GENERATED from protocol::axi_lite (protocol/src/axi_lite.rs); do not edit.
// `FPGFX_BLESS=1 cargo test -p protocol --test integration rt_axi_map` rewrites it.
`ifndef RT_AXI_MAP_VH
`define RT_AXI_MAP_VH
// address bits the device decodes
`define RT_AXI_ADDR_BITS 21
// block-level control
`define RT_AXI_AP_CTRL 0
// global interrupt enable
`define RT_AXI_GIE 4
// interrupt enable
`define RT_AXI_IER 8
// interrupt status (toggle on write)
`define RT_AXI_ISR 12
// scalar: number format code
`define RT_AXI_NUMERIC 16
// scalar: bit 0 writes the AOV planes
`define RT_AXI_AOVS 24
// AP_CTRL bit: ap_start
`define RT_AXI_AP_START 0
// AP_CTRL bit: ap_done (clear on read)
`define RT_AXI_AP_DONE 1
// AP_CTRL bit: ap_idle
`define RT_AXI_AP_IDLE 2
// AP_CTRL bit: ap_ready (clear on read)
`define RT_AXI_AP_READY 3
// AP_CTRL bit: auto_restart
`define RT_AXI_AUTO_RESTART 7
// IER / ISR bit: ap_done
`define RT_AXI_IRQ_DONE 0
// IER / ISR bit: ap_ready
`define RT_AXI_IRQ_READY 1
// scene word 0
`define RT_AXI_SCENE_BASE 32'h00000800
// bytes of the scene window
`define RT_AXI_SCENE_WINDOW 32'h00000800
// words of the scene image
`define RT_AXI_SCENE_WORDS 32'h000001ee
// reads DEVICE_ID
`define RT_AXI_SYS_ID 32'h00001000
// reads MAP_VERSION
`define RT_AXI_SYS_VERSION 32'h00001004
// any write: power-on state
`define RT_AXI_SYS_RESET 32'h00001008
// last frame's cycles, low word (high at +4)
`define RT_AXI_SYS_RT_CYCLES 32'h00001010
// last frame's rays, low word (high at +4)
`define RT_AXI_SYS_RT_WORK 32'h00001018
// counter 0's low word; counter i at +8 i
`define RT_AXI_SYS_COUNTERS 32'h00001100
// device counters
`define RT_AXI_COUNTER_COUNT 4
// "FPGX"
`define RT_AXI_DEVICE_ID 32'h46504758
// this map's version
`define RT_AXI_MAP_VERSION 1
// NUMERIC code of Q16.16
`define RT_AXI_NUMERIC_Q16_16 3
// NUMERIC codes that name a format
`define RT_AXI_NUMERIC_CODES 7
// read-back: plane code
`define RT_AXI_READ_PLANE 32'h00003000
// read-back: format code
`define RT_AXI_READ_FORMAT 32'h00003004
// read-back: x | y << 16
`define RT_AXI_READ_RECT_XY 32'h00003008
// read-back: w | h << 16
`define RT_AXI_READ_RECT_WH 32'h0000300c
// read-back: bytes, or READ_NONE
`define RT_AXI_READ_LEN 32'h00003010
// read-back: the window's page
`define RT_AXI_READ_PAGE 32'h00003014
// READ_LEN without a read-back
`define RT_AXI_READ_NONE 32'hffffffff
// the read-back slave
`define RT_AXI_READ_SLAVE 32'h00003000
// READ_PLANE codes that name a plane
`define RT_AXI_PLANE_CODES 3
// READ_FORMAT codes that name a format
`define RT_AXI_FORMAT_CODES 5
// read-back window
`define RT_AXI_READ_BASE 32'h00004000
// bytes of the read-back window
`define RT_AXI_READ_WINDOW 32'h00004000
// the raster slave (not on this device)
`define RT_AXI_RASTER_BASE 32'h00002000
// texture window
`define RT_AXI_TEXTURE_BASE 32'h00100000
// bytes of each register slave
`define RT_AXI_SLAVE_SPAN 32'h00001000
// READ_PLANE code
`define RT_AXI_PLANE_COLOR 0
// READ_PLANE code
`define RT_AXI_PLANE_DEPTH 1
// READ_PLANE code
`define RT_AXI_PLANE_NORMAL 2
// READ_FORMAT code
`define RT_AXI_FORMAT_RGB888 0
// bytes per pixel of the format
`define RT_AXI_BPP_RGB888 3
// READ_FORMAT code
`define RT_AXI_FORMAT_RGB332 1
// bytes per pixel of the format
`define RT_AXI_BPP_RGB332 1
// READ_FORMAT code
`define RT_AXI_FORMAT_KCU116 2
// bytes per pixel of the format
`define RT_AXI_BPP_KCU116 2
// READ_FORMAT code
`define RT_AXI_FORMAT_DEPTH_F32 3
// bytes per pixel of the format
`define RT_AXI_BPP_DEPTH_F32 4
// READ_FORMAT code
`define RT_AXI_FORMAT_NORMAL_F32 4
// bytes per pixel of the format
`define RT_AXI_BPP_NORMAL_F32 12
// device counter index: fragments
`define RT_AXI_COUNTER_FRAGMENTS 0
// device counter index: cycles
`define RT_AXI_COUNTER_CYCLES 1
// device counter index: frames
`define RT_AXI_COUNTER_FRAMES 2
// device counter index: saturations
`define RT_AXI_COUNTER_SATURATIONS 3
`endif
