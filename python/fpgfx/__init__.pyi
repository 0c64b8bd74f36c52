"""Type stubs for fpgfx (the native module fpgfx._fpgfx, re-exported)."""

import os
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union, final

import numpy as np
import numpy.typing as npt

from . import axi as axi
from . import fitkit as fitkit

__version__: str
__all__ = [
    "Comparison",
    "Error",
    "FitkitRecords",
    "Packet",
    "RasterFrame",
    "RenderFrame",
    "__version__",
    "axi",
    "axi_writes",
    "compare",
    "fitkit",
    "pack",
    "raster",
    "render",
]

#: A raster job or a scene: its TOML text, a path to the file, or a dict of the same shape.
_Job = Union[str, "os.PathLike[str]", Mapping[str, Any]]
#: A scene, or a register image: 1-D uint32, axi.SCENE_WORDS words (RenderFrame.regs).
_Scene = Union[_Job, npt.NDArray[np.uint32]]

class Error(ValueError):
    """A refusal: a job or scene that does not parse or that the model cannot run, or an
    argument of the right type with an unusable value. The message names file, line and key."""

@final
class FitkitRecords:
    """The job as the FITkit block takes it (what ``fpgfx vectors raster`` writes)."""

    #: SPI write transactions, one per CS_n-low period, address byte first.
    spi: List[bytes]
    #: Input FIFO records per packet: (tag = SPI channel, records).
    packets: List[Tuple[int, List[int]]]
    #: Every framebuffer write in order: (N, 4) uint32 rows kind, x, y, RGB332 word.
    writes: npt.NDArray[np.uint32]
    #: The final framebuffer, (H, W) uint8 RGB332 words.
    framebuffer: npt.NDArray[np.uint8]
    #: The status counters of this run (bounding-box traversal, as the RTL walks).
    counters: Dict[str, Union[int, float]]

@final
class RasterFrame:
    """A raster job's frame and counters."""

    #: (H, W, 3) uint8 RGB, the PNG ``fpgfx raster`` writes.
    image: npt.NDArray[np.uint8]
    #: commands, fragments, pixel_tests, block_tests, cycles_<unit>, cycles, end_cycle,
    #: board_time_s, fifo_records, fifo_stalls, fifo_max, fragment_stalls.
    counters: Dict[str, Union[int, float]]
    #: With ``records=True``, the job on the FITkit layout.
    records: Optional[FitkitRecords]

@final
class RenderFrame:
    """A ray-traced frame, its planes and its register image."""

    #: (H, W, 3) uint8 RGB, the PNG ``fpgfx render`` writes.
    image: npt.NDArray[np.uint8]
    #: (H, W) float32 distance to the first hit, +inf where the ray missed.
    depth: npt.NDArray[np.float32]
    #: (H, W, 3) float32 world-space normal, 0 where the ray missed.
    normal: npt.NDArray[np.float32]
    #: The register image (uint32, scene memory order).
    regs: npt.NDArray[np.uint32]
    #: The AXI4-Lite writes of the frame: (N, 2) uint32 rows address, data in bus order.
    writes: npt.NDArray[np.uint32]
    #: rays_traced, rays_nominal, cycles, board_time_s, core_cycles, saturations.
    counters: Dict[str, Union[int, float]]
    #: The number format, spelled as ``--numeric`` takes it.
    numeric: str

@final
class Packet:
    """One packet of a raster job as the controller pushes it (``pack``)."""

    #: Index of the job's command; None for the FITkit's set-up packet.
    command: Optional[int]
    #: The command's op as the job file spells it, "setup" for the set-up.
    op: str
    #: The SPI address on the FITkit (``fitkit.ADDR_*``), the channel on other layouts.
    address: int
    #: The input FIFO's records in push order.
    records: List[int]
    #: On the FITkit, the whole CS_n-low write transaction, address byte first.
    spi: Optional[bytes]

@final
class Comparison:
    """The figures ``fpgfx compare`` reports for two colour frames."""

    width: int
    height: int
    pixels: int
    equal: int
    within_tolerance: int
    near_edge: int
    missing: int
    unexpected: int
    differing: int
    failures: int
    passed: bool
    max_error: int
    mean_error: float
    psnr_db: float
    background: Optional[str]
    mismatches: List[Dict[str, Any]]
    mask: npt.NDArray[np.uint8]
    def __bool__(self) -> bool: ...

def raster(job: _Job, *, records: bool = False, name: Optional[str] = None) -> RasterFrame:
    """Draws a raster job as ``fpgfx raster`` does on the built-in target."""

def render(
    scene: _Scene,
    numeric: str = "q16.16",
    *,
    size: Optional[Tuple[int, int]] = None,
    spp: Optional[int] = None,
    name: Optional[str] = None,
) -> RenderFrame:
    """Renders a scene as ``fpgfx render --numeric NUMERIC`` does on the built-in target."""

def compare(
    expected: npt.NDArray[np.uint8],
    actual: npt.NDArray[np.uint8],
    tolerance: float = 0.0,
    *,
    raster: Optional[_Job] = None,
    coverage_precision: Optional[int] = None,
    max_listed: int = 10,
) -> Comparison:
    """Compares two (H, W, 3) uint8 frames as ``fpgfx compare`` does."""

def pack(job: _Job, *, layout: str = "fitkit", name: Optional[str] = None) -> List[Packet]:
    """Packs a raster job as the controller does (FITkit: set-up first, SPI bytes each)."""

def axi_writes(
    scene: _Scene,
    numeric: str = "q16.16",
    *,
    size: Optional[Tuple[int, int]] = None,
    spp: Optional[int] = None,
    name: Optional[str] = None,
) -> npt.NDArray[np.uint32]:
    """The AXI4-Lite writes that render the scene: (N, 2) uint32 rows address, data."""
