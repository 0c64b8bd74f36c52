"""Type stubs for fpgfx.axi: the ray tracer's AXI4-Lite map.

Every name of ``protocol::axi_lite::MAP`` (the source of ``rt_axi_map.vh``: ``AP_CTRL``,
``SCENE_BASE``, ``SYS_RT_CYCLES``, ``AP_DONE`` as a bit number, ...) is an int constant here.
"""

from typing import Dict

#: Every single register by name: its byte address.
REGISTERS: Dict[str, int]
#: Every device counter by name: its low word's byte address (the high word follows).
COUNTERS: Dict[str, int]

def __getattr__(name: str) -> int: ...
def register_name(addr: int) -> str:
    """The name of the register or window at byte address addr."""
