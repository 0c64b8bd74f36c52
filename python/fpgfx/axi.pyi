"""Type stubs for fpgfx.axi: the ray tracer's AXI4-Lite map.

Every name of ``protocol::axi_lite::MAP`` (the source of ``rt_axi_map.vh``: ``AP_CTRL``,
``SCENE_BASE``, ``SYS_RT_CYCLES``, ``AP_DONE`` as a bit number, ...) is an int constant here (listed below; the values come from the native module).
"""

from typing import Dict

#: Every single register by name: its byte address.
REGISTERS: Dict[str, int]
#: Every device counter by name: its low word's byte address (the high word follows).
COUNTERS: Dict[str, int]

ADDR_BITS: int
AOVS: int
AP_CTRL: int
AP_DONE: int
AP_IDLE: int
AP_READY: int
AP_START: int
AUTO_RESTART: int
BPP_DEPTH_F32: int
BPP_KCU116: int
BPP_NORMAL_F32: int
BPP_RGB332: int
BPP_RGB888: int
COUNTER_COUNT: int
COUNTER_CYCLES: int
COUNTER_FRAGMENTS: int
COUNTER_FRAMES: int
COUNTER_SATURATIONS: int
DEVICE_ID: int
FORMAT_CODES: int
FORMAT_DEPTH_F32: int
FORMAT_KCU116: int
FORMAT_NORMAL_F32: int
FORMAT_RGB332: int
FORMAT_RGB888: int
GIE: int
IER: int
IRQ_DONE: int
IRQ_READY: int
ISR: int
MAP_VERSION: int
NUMERIC: int
NUMERIC_CODES: int
NUMERIC_Q16_16: int
PLANE_CODES: int
PLANE_COLOR: int
PLANE_DEPTH: int
PLANE_NORMAL: int
RASTER_BASE: int
READ_BASE: int
READ_FORMAT: int
READ_LEN: int
READ_NONE: int
READ_PAGE: int
READ_PLANE: int
READ_RECT_WH: int
READ_RECT_XY: int
READ_SLAVE: int
READ_WINDOW: int
SCENE_BASE: int
SCENE_WINDOW: int
SCENE_WORDS: int
SLAVE_SPAN: int
SYS_COUNTERS: int
SYS_ID: int
SYS_RESET: int
SYS_RT_CYCLES: int
SYS_RT_WORK: int
SYS_VERSION: int
TEXTURE_BASE: int

def register_name(addr: int) -> str:
    """The name of the register or window at byte address addr."""
