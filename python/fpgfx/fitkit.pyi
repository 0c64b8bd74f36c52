"""Type stubs for fpgfx.fitkit: the FITkit raster block's SPI map and transactions.

Every name of ``protocol::fitkit_spi::MAP`` (the source of ``fitkit_map.vh``: ``ADDR_*``,
``FLAG_*``, ``STAT_*`` offsets, FIFO geometry) and ``ERR_<code>`` is an int constant here.
"""

from typing import Any, Dict, List

def __getattr__(name: str) -> int: ...
def packet(address: int, records: List[int]) -> bytes:
    """The write transaction of one packet: address byte, then the 36-bit records."""

def read_header(x: int, y: int) -> bytes:
    """The bytes that open a read-back from pixel (x, y)."""

def pixel_address(x: int, y: int) -> int:
    """The framebuffer address of pixel (x, y) on the block's memory port."""

def status(data: bytes) -> Dict[str, Any]:
    """Decodes the STATUS_BYTES status block; raises fpgfx.Error on bytes the block never sends."""
