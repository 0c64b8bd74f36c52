"""fpgfx's bit-exact golden model from Python: a scoreboard for cocotb testbenches.

``raster`` draws a raster job, ``render`` ray-traces a scene and ``compare`` holds one
frame to another, each exactly as the ``fpgfx`` tool does (the same Rust library runs
underneath). ``pack`` and ``axi_writes`` give what a testbench drives into a block
itself; ``fitkit`` and ``axi`` hold the two blocks' maps. Frames are numpy arrays of shape (H, W, 3) and dtype uint8. A refusal
raises ``fpgfx.Error`` (a ``ValueError``) with the library's message. See docs/python.md.
"""

import sys as _sys

from ._fpgfx import (
    Comparison,
    Error,
    FitkitRecords,
    Packet,
    RasterFrame,
    RenderFrame,
    __version__,
    axi,
    axi_writes,
    compare,
    fitkit,
    pack,
    raster,
    render,
)

# The maps are submodules of the native module; registered under the package's name so
# that ``import fpgfx.fitkit`` and ``from fpgfx.axi import SCENE_BASE`` work too.
_sys.modules[__name__ + ".fitkit"] = fitkit
_sys.modules[__name__ + ".axi"] = axi

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
