"""Type stubs for fpgfx.fitkit: the FITkit raster block's SPI map and transactions.

Every name of ``protocol::fitkit_spi::MAP`` (the source of ``fitkit_map.vh``: ``ADDR_*``,
``FLAG_*``, ``STAT_*`` offsets, FIFO geometry) and ``ERR_<code>`` is an int constant here; ``FLAG_*`` are bit numbers, as in the header (listed below; the values come from the native module).
"""

from typing import Any, Dict, List

ADDR_CLEAR: int
ADDR_LINE: int
ADDR_READ: int
ADDR_RESET: int
ADDR_SETUP: int
ADDR_STATUS: int
ADDR_TRIANGLE: int
COLOR_BITS: int
COORD_BITS: int
ERR_BITS: int
ERR_CLEAR_WITHOUT_CB: int
ERR_LENGTH: int
ERR_OVERRUN: int
ERR_PADDING: int
ERR_READ_UNDERRUN: int
ERR_UNKNOWN_ADDRESS: int
FIFO_RECORDS: int
FLAG_BUSY: int
FLAG_ERROR: int
FLAG_FIFO_EMPTY: int
FLAG_NO_LINE: int
FLAG_NO_TRIANGLE: int
FLAG_SETUP_DONE: int
FRAME_SIDE: int
MAX_PACKET_BYTES: int
READ_HEADER_BYTES: int
READ_TURNAROUND: int
RECORD_BITS: int
STATUS_BYTES: int
STATUS_CLEAR_CYCLES: int
STATUS_END_CYCLE: int
STATUS_ERROR_CHANNEL: int
STATUS_ERROR_CODE: int
STATUS_ERROR_PACKET: int
STATUS_FIFO_MAX_PAIRS: int
STATUS_FLAGS: int
STATUS_FRAGMENTS: int
STATUS_FREE: int
STATUS_LINE_CYCLES: int
STATUS_PACKETS: int
STATUS_TRIANGLE_CYCLES: int

def packet(address: int, records: List[int]) -> bytes:
    """The write transaction of one packet: address byte, then the 36-bit records."""

def read_header(x: int, y: int) -> bytes:
    """The bytes that open a read-back from pixel (x, y)."""

def pixel_address(x: int, y: int) -> int:
    """The framebuffer address of pixel (x, y) on the block's memory port."""

def status(data: bytes) -> Dict[str, Any]:
    """Decodes the STATUS_BYTES status block (flags also by name: busy, fifo_empty,
    setup_done, no_line, no_triangle); raises fpgfx.Error on bytes the block never sends."""
