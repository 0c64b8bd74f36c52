"""Seeded random raster jobs that the FITkit layout can carry, for the cocotb testbench.

A job is the dict form of a raster command file (docs/raster.md), which ``fpgfx.raster``
takes as it takes the TOML: ``size``, ``background``, ``cull``, ``subpixel_bits`` and a
``cmd`` list of ``clear``, ``line`` and flat ``triangle`` commands. The FITkit layout
refuses everything else (circles, fills, Gouraud colours, sub-pixel coordinates,
colours outside RGB332, coordinates outside 0..511), so the generator stays inside it;
``fpgfx.raster`` is the judge of that, and the testbench also holds it to a job that
breaks the rule on purpose.

The same seed gives the same job on every machine (``random.Random``, no global state),
so a failing case is named by its seed alone.
"""

from __future__ import annotations

import random
from typing import Any

import numpy as np

Job = dict[str, Any]

#: Largest coordinate a 9-bit FITkit record holds.
COORD_MAX = 511
#: Cull modes by the names the command file takes (protocol/src/names.rs).
CULL_NAMES = ("none", "cw", "ccw")


def rgb332_to_rgb(word: int) -> tuple[int, int, int]:
    """The RGB888 colour an RGB332 memory word stands for: each field widened by bit
    replication (3-bit 7 and 2-bit 3 become 255).

    The generator names colours through it, so that every colour it writes is one the
    FITkit can hold; ``fpgfx.raster`` refuses any other, so a wrong widening here fails
    every job rather than passing silently. The testbench widens the block's read-back
    with it too, to compare RGB images with ``fpgfx.compare``.
    """
    r3, g3, b2 = word >> 5 & 7, word >> 2 & 7, word & 3

    def e3(v: int) -> int:
        return (v << 5 | v << 2 | v >> 1) & 0xFF

    return e3(r3), e3(g3), b2 * 0x55


def rgb332_image(words: np.ndarray) -> np.ndarray:
    """An (H, W) array of RGB332 words as the (H, W, 3) uint8 image ``fpgfx.compare``
    takes."""
    table = np.array([rgb332_to_rgb(w) for w in range(256)], dtype=np.uint8)
    return table[np.asarray(words, dtype=np.uint8)]


def color(word: int) -> str:
    """``#rrggbb`` of an RGB332 word, as the command file spells colours."""
    return "#{:02x}{:02x}{:02x}".format(*rgb332_to_rgb(word))


def _point(rng: random.Random, width: int, height: int, spill: float) -> list[float]:
    """A vertex: inside the frame mostly; with probability ``spill`` anywhere the 9-bit
    coordinates reach up to twice the frame (clipped fragments, longer walks)."""
    if rng.random() < spill:
        return [
            float(rng.randint(0, min(COORD_MAX, 2 * width))),
            float(rng.randint(0, min(COORD_MAX, 2 * height))),
        ]
    return [float(rng.randrange(width)), float(rng.randrange(height))]


def random_job(seed: int, width: int = 40, height: int = 30, commands: int = 8) -> Job:
    """A job of ``commands`` commands (lines and triangles, now and then a clear) on a
    ``width`` × ``height`` frame with a random background and culling mode.

    Small frames on purpose: the testbench reads every pixel back over SPI, and under
    Icarus each SPI byte is a few thousand Python wake-ups.
    """
    rng = random.Random(seed)
    cmds: list[dict[str, Any]] = []
    for _ in range(commands):
        op = rng.choices(["line", "triangle", "clear"], weights=[6, 6, 1])[0]
        c = color(rng.randrange(256))
        if op == "clear":
            cmds.append({"op": "clear", "color": c})
        elif op == "line":
            cmds.append(
                {
                    "op": "line",
                    "from": _point(rng, width, height, 0.15),
                    "to": _point(rng, width, height, 0.15),
                    "color": c,
                }
            )
        else:
            cmds.append(
                {
                    "op": "triangle",
                    "v": [_point(rng, width, height, 0.1) for _ in range(3)],
                    "color": c,
                }
            )
    return {
        "size": [width, height],
        "background": color(rng.randrange(256)),
        "cull": rng.choice(CULL_NAMES),
        "subpixel_bits": 0,
        "cmd": cmds,
    }


def invalid_jobs() -> list[tuple[Job, str]]:
    """Jobs the FITkit layout cannot carry, each with a word the refusal must name."""
    base = random_job(0, commands=1)
    circle = dict(
        base, cmd=[{"op": "circle", "center": [8.0, 8.0], "radius": 4.0, "color": "#ffffff"}]
    )
    far = dict(
        base, cmd=[{"op": "line", "from": [0.0, 0.0], "to": [600.0, 3.0], "color": "#ffffff"}]
    )
    off_palette = dict(
        base, cmd=[{"op": "line", "from": [0.0, 0.0], "to": [9.0, 3.0], "color": "#123456"}]
    )
    return [(circle, "circle"), (far, "600"), (off_palette, "RGB332")]
