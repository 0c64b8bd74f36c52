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
for p in sorted((ROOT / "examples/raster").glob("*.toml")):
    write("raster_file", p.name, p.read_bytes())
    j = json.dumps(tomllib.loads(p.read_text()), indent=1)
    write("raster_file", p.stem + ".json", j.encode())
