"""fpgfx's bit-exact golden model from Python: a scoreboard for cocotb testbenches.

``raster`` draws a raster job, ``render`` ray-traces a scene and ``compare`` holds one
frame to another, each exactly as the ``fpgfx`` tool does (the same Rust library runs
underneath). Frames are numpy arrays of shape (H, W, 3) and dtype uint8. A refusal
raises ``fpgfx.Error`` (a ``ValueError``) with the library's message. See docs/python.md.
"""

from ._fpgfx import (
    Comparison,
    Error,
    FitkitRecords,
    RasterFrame,
    RenderFrame,
    __version__,
    compare,
    raster,
    render,
)

__all__ = [
    "Comparison",
    "Error",
    "FitkitRecords",
    "RasterFrame",
    "RenderFrame",
    "__version__",
    "compare",
    "raster",
    "render",
]
