#!/usr/bin/env python3
"""Writes the seed inputs of the fuzz targets into corpus/TARGET/seed-*.

Sources: the golden message bytes of protocol/tests/integration/frame.rs (raw, and framed with
COBS + CRC-32 as protocol::link::encode_frame does), the example scene files and the
example raster files (as TOML and as JSON). Run from fuzz/: python3 make_seeds.py
"""
import json
import pathlib
import re
import tomllib
import zlib

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = pathlib.Path(__file__).resolve().parent / "corpus"


def golden_messages():
    src = (ROOT / "protocol/tests/integration/frame.rs").read_text()
    src = re.sub(r"//[^\n]*", "", src)
    seen = []
    for m in re.finditer(r"&\[\s*((?:0x[0-9a-fA-F]{2}\s*,?\s*)+)\]", src):
        b = bytes(int(h, 16) for h in re.findall(r"0x([0-9a-fA-F]{2})", m.group(1)))
        if b not in seen:
            seen.append(b)
    return seen


def cobs(data):
    out, block = bytearray(), bytearray()
    for x in data:
        if x == 0:
            out += bytes([len(block) + 1]) + block
            block = bytearray()
        else:
            block.append(x)
            if len(block) == 254:
                out += b"\xff" + block
                block = bytearray()
    out += bytes([len(block) + 1]) + block
    return bytes(out)


def frame(kind, seq, ack, credit, payload=b"", epoch=0):
    raw = bytes([kind | (epoch << 4), seq & 255, seq >> 8, ack & 255, ack >> 8, credit])
    raw += payload
    raw += zlib.crc32(raw).to_bytes(4, "little")
    return cobs(raw) + b"\x00"


def write(target, name, data):
    d = OUT / target
    d.mkdir(parents=True, exist_ok=True)
    (d / f"seed-{name}").write_bytes(data)


msgs = golden_messages()
for i, m in enumerate(msgs):
    write("frame_decode", f"msg{i:02}", m)
    write("frame_decode", f"frame{i:02}", frame(1, i, 0, 8, m))
write("frame_decode", "ack", frame(2, 0, 3, 8))
stream = b"".join(frame(1, i, 0, 8, m) for i, m in enumerate(msgs[:6]))
write("link_rx", "whole", b"\xff" + stream)
write("link_rx", "bytewise", b"\x01" + stream)
write("link_rx", "reset", b"\x10" + frame(5, 0x1234, 0, 8) + frame(1, 0, 0, 8, msgs[0], epoch=1))
write("link_rx", "reorder", b"\x07" + frame(1, 1, 0, 8, msgs[1]) + frame(1, 0, 0, 8, msgs[0]))

for p in [ROOT / "examples/reference.toml", *sorted((ROOT / "examples/rt").glob("*.toml"))]:
    write("scene_file", p.name, p.read_bytes())
    write("scene_render", p.name, p.read_bytes())
for p in sorted((ROOT / "examples/raster").glob("*.toml")):
    write("raster_file", p.name, p.read_bytes())
    j = json.dumps(tomllib.loads(p.read_text()), indent=1)
    write("raster_file", p.stem + ".json", j.encode())

# device_regs: byte 0 = number format (bits 0-2), base image (bits 3-6), mode (bit 7).
# Mode 1 with no patches is each example scene's image as it is; a few patches set a
# width, a count and a code word to values the decoder must refuse or clamp.
for base in range(10):
    write("device_regs", f"base{base}", bytes([0x80 | base << 3 | base % 7]))
patch = lambda at, word: at.to_bytes(2, "little") + word.to_bytes(4, "little")
write("device_regs", "width0", bytes([0x80]) + patch(4, 0))
write("device_regs", "objects9", bytes([0x88]) + patch(2, 9))
write("device_regs", "lights0", bytes([0x90]) + patch(3, 0))
write("device_regs", "format7", bytes([0x98]) + patch(15, 7))
write("device_regs", "zeros", bytes([0x01]) + bytes(4 * 494))

# capi: a sequence of calls, one opcode byte each (0 new, 1 push, 2 read, 3 free,
# 4 compare, 5 render) followed by its arguments (fuzz_targets/capi.rs).
new = lambda layout, w, h: bytes([0, layout, w, h, 0, 10, 20, 30, 0, 0, 0, 3, 2])
push = lambda n: bytes([1, 0, 4, n]) + bytes(range(8 * n)) + b"\x05"
read = lambda fmt: bytes([2, 0, fmt, 3])
write("capi", "raster-wide", new(2, 5, 3) + push(2) + read(0) + read(1) + bytes([3, 0]))
write("capi", "raster-fitkit", new(0, 8, 8) + bytes([1, 0, 2, 3]) + bytes(24) + b"\x05" + read(1))
write("capi", "raster-nulls", new(2, 4, 4)[:-1] + b"\x00" + new(2, 4, 4)[:-1] + b"\x01")
write("capi", "compare", bytes([4, 1, 3, 4, 4, 1, 3, 3, 1]) + bytes(range(96)))
write("capi", "compare-huge", bytes([4, 0, 1, 1, 0]) + bytes([255] * 8) + bytes(6))
write("capi", "compare-exact", bytes([4, 0, 8, 8, 1, 3, 3, 1]) + bytes(range(192)))
for base in range(10):
    write("capi", f"render{base}", bytes([5, base << 3, 3, 1, 3, 3, 1, 1, 1, 0]))

# python: byte 0 picks the call (0 raster, 1 render, 2 compare, 3 dict → TOML).
for p in sorted((ROOT / "examples/raster").glob("*.toml")):
    write("python", "raster-" + p.name, b"\x00" + p.read_bytes())
for i, p in enumerate([ROOT / "examples/reference.toml", *sorted((ROOT / "examples/rt").glob("*.toml"))]):
    write("python", "render-" + p.name, bytes([1, i, 3, 2]) + p.read_bytes())
    write("python", "dict-" + p.name, b"\x03" + p.read_bytes())
write("python", "compare", bytes([2, 2, 4, 3, 3, 1]) + bytes(range(200)))
write("python", "compare-sizes", bytes([2, 0, 1, 2, 2, 0, 3, 3]) + bytes(range(60)))
