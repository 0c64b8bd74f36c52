"""The Python bindings held to the `fpgfx` tool: the same frames, counters, records and
comparison figures, and a Python exception (never a crash) for every bad input."""

import json
import re
import threading
import warnings

import numpy as np
import pytest

import fpgfx
from PIL import Image

FITKIT = "examples/raster/fitkit.toml"
REFERENCE = "examples/reference.toml"


def read_png(path):
    """The PNG at ``path`` as an (H, W, 3) uint8 array: 8-bit RGB or RGBA (alpha dropped),
    what the ``image`` crate writes for fpgfx; anything else is a failure, not a
    conversion."""
    with Image.open(path) as im:
        assert im.mode in ("RGB", "RGBA"), f"{path}: mode {im.mode}"
        return np.asarray(im)[:, :, :3].copy()


def write_png(path, rgb):
    """Writes an (H, W, 3) uint8 array as an 8-bit RGB PNG."""
    Image.fromarray(rgb, "RGB").save(path)


def hexwords(path):
    """The words of a $readmemh file, comments dropped."""
    words = []
    for line in open(path):
        line = line.split("//")[0].strip()
        if line and not line.startswith("@"):
            words.append(int(line, 16))
    return words


# ---- raster -----------------------------------------------------------------------


def test_raster_equals_the_golden_png(repo):
    frame = fpgfx.raster(repo / FITKIT)
    golden = read_png(repo / "examples/raster/golden/fitkit.png")
    assert frame.image.dtype == np.uint8 and frame.image.shape == (240, 320, 3)
    assert np.array_equal(frame.image, golden)
    assert frame.records is None


@pytest.mark.parametrize("job", ["gallery.toml", "aa.toml"])
def test_every_raster_example_equals_its_golden_png(repo, job):
    frame = fpgfx.raster((repo / "examples/raster" / job).read_text(), name=job)
    golden = read_png(repo / "examples/raster/golden" / job.replace(".toml", ".png"))
    assert np.array_equal(frame.image, golden)


def test_raster_counters_are_the_clis(repo, fpgfx_cli, tmp_path):
    out = fpgfx_cli("raster", FITKIT, "-o", tmp_path / "f.png", "--stats").stdout
    stats = {}
    for line in out.splitlines():
        for label, key in [("commands", "commands"), ("fragments", "fragments"), ("FPGA cycles", "cycles")]:
            m = re.match(re.escape(label) + r"\s+(\d+)", line)
            if m:
                stats[key] = int(m.group(1))
    assert len(stats) == 3, out
    counters = fpgfx.raster(repo / FITKIT).counters
    assert {k: counters[k] for k in stats} == stats
    units = sum(counters[f"cycles_{u}"] for u in ("triangle", "line", "circle", "fill", "clear"))
    assert units == counters["cycles"] > 0
    assert np.array_equal(read_png(tmp_path / "f.png"), fpgfx.raster(repo / FITKIT).image)


def test_records_are_fpgfx_vectors(repo, fpgfx_cli, tmp_path):
    fpgfx_cli("vectors", "raster", FITKIT, "-o", tmp_path)
    rec = fpgfx.raster(repo / FITKIT, records=True).records
    assert isinstance(rec, fpgfx.FitkitRecords)
    spi = b"".join(rec.spi)
    assert list(spi) == hexwords(tmp_path / "spi_bytes.hex")
    frames = hexwords(tmp_path / "spi_frames.hex")
    assert [len(t) for t in rec.spi] == [f & 0xFF for f in frames]
    fifo = []
    for tag, records in rec.packets:
        for k, r in enumerate(records):
            last = 4 if k + 1 == len(records) else 0
            fifo.append(((last | tag) << 36) | r)
    assert fifo == hexwords(tmp_path / "fifo_records.hex")
    frags = [(k << 32) | (y << 20) | (x << 8) | c for k, x, y, c in rec.writes.tolist()]
    assert frags == hexwords(tmp_path / "expected_fragments.hex")
    fb = hexwords(tmp_path / "expected_framebuffer.hex")
    assert rec.framebuffer.shape == (240, 320)
    assert rec.framebuffer.ravel().tolist() == fb[-320 * 240 :]
    manifest = (tmp_path / "manifest.toml").read_text()
    for key in ("packets", "fragments", "line_cycles", "triangle_cycles", "clear_cycles"):
        counter = {"packets": "commands", "fragments": "fragments"}.get(key, "cycles_" + key.split("_")[0])
        assert f"{key} = {rec.counters[counter]}\n" in manifest, key


def test_a_dict_job_is_the_same_job(repo):
    job = {
        "size": [64, 48],
        "background": "#000055",
        "subpixel_bits": 0,
        "cmd": [
            {"op": "line", "from": [1.0, 2.0], "to": [60.0, 40.0], "color": "#ffffff"},
            {"op": "triangle", "v": [[5.0, 5.0], [50.0, 10.0], [20.0, 45.0]], "color": "#ffff00"},
        ],
    }
    text = """
size = [64, 48]
background = "#000055"
subpixel_bits = 0
[[cmd]]
op = "line"
from = [1.0, 2.0]
to = [60.0, 40.0]
color = "#ffffff"
[[cmd]]
op = "triangle"
v = [[5.0, 5.0], [50.0, 10.0], [20.0, 45.0]]
color = "#ffff00"
"""
    a, b = fpgfx.raster(job), fpgfx.raster(text)
    assert np.array_equal(a.image, b.image) and a.counters == b.counters
    assert (a.image[0, 0] == [0, 0, 0x55]).all() and (a.image == [255, 255, 0]).all(axis=2).any()


# ---- render -----------------------------------------------------------------------


@pytest.mark.parametrize("numeric", ["q16.16", "f32"])
def test_render_equals_the_cli(repo, fpgfx_cli, tmp_path, numeric):
    out = tmp_path / "frame.png"
    fpgfx_cli("render", REFERENCE, "--numeric", numeric, "--size", "160x90", "-o", out)
    frame = fpgfx.render(repo / REFERENCE, numeric, size=(160, 90))
    assert frame.image.shape == (90, 160, 3) and frame.numeric == numeric
    assert np.array_equal(frame.image, read_png(out))
    assert frame.depth.shape == (90, 160) and frame.depth.dtype == np.float32
    assert frame.normal.shape == (90, 160, 3)
    hit = np.isfinite(frame.depth)
    assert hit.any(), "the reference scene has surfaces"
    assert np.allclose(np.linalg.norm(frame.normal[hit], axis=1), 1.0, atol=1e-2)
    assert frame.regs.dtype == np.uint32 and frame.regs.size > 0


def test_render_default_is_q16_16_and_the_aovs_are_the_clis(repo, fpgfx_cli, tmp_path):
    fpgfx_cli("render", REFERENCE, "--numeric", "q16.16", "--size", "64x36", "-o", tmp_path / "f.png", "--aov", f"depth={tmp_path / 'd.pfm'}")
    frame = fpgfx.render((repo / REFERENCE).read_text(), size=(64, 36))
    assert frame.numeric == "q16.16"
    data = (tmp_path / "d.pfm").read_bytes()
    header, rest = data.split(b"\n", 3)[:3], data.split(b"\n", 3)[3]
    assert header[0] == b"Pf" and header[1] == b"64 36"
    scale = float(header[2])
    depth = np.frombuffer(rest, dtype="<f4" if scale < 0 else ">f4").reshape(36, 64)[::-1]
    assert np.array_equal(depth, frame.depth)


def test_render_releases_the_interpreter_lock(repo):
    done = []
    t = threading.Thread(target=lambda: done.append(fpgfx.render(repo / REFERENCE, "f32", size=(320, 180))))
    spins = 0
    t.start()
    while t.is_alive():
        spins += 1
    t.join()
    assert done and done[0].image.shape == (180, 320, 3)
    # With the lock held for the whole render, this thread could not have run meanwhile.
    assert spins > 10_000, spins


# ---- compare ----------------------------------------------------------------------


def test_compare_reports_the_clis_figures(repo, fpgfx_cli, tmp_path):
    expected = fpgfx.raster(repo / FITKIT).image
    actual = expected.copy()
    actual[10, 20] = [1, 2, 3]  # on the black background: unexpected
    actual[100, 100] = np.clip(actual[100, 100].astype(int) + 5, 0, 255)
    actual[239, 319, 1] ^= 0x80
    write_png(tmp_path / "e.png", expected)
    write_png(tmp_path / "a.png", actual)
    cli = json.loads(fpgfx_cli("compare", tmp_path / "e.png", tmp_path / "a.png", "--json", check=False).stdout)
    c = fpgfx.compare(expected, actual)
    assert not c and not c.passed and c.failures == 3
    for key in ("width", "height", "pixels", "equal", "within_tolerance", "near_edge", "missing", "unexpected", "differing", "failures", "passed", "background"):
        assert getattr(c, key) == cli[key], key
    assert c.max_error == cli["max_error"] == 0x80
    assert c.mean_error == pytest.approx(cli["mean_error"], rel=1e-12)
    assert c.psnr_db == pytest.approx(cli["psnr_db"], rel=1e-12)
    assert [(m["x"], m["y"], list(m["expected"]), list(m["actual"]), m["class"]) for m in c.mismatches] == [
        (m["x"], m["y"], m["expected"], m["actual"], m["class"]) for m in cli["mismatches"]
    ]
    assert (c.mismatches[0]["x"], c.mismatches[0]["y"], c.mismatches[0]["class"]) == (20, 10, "unexpected")
    assert c.mask.shape == expected.shape and tuple(c.mask[10, 20]) == (255, 0, 0)
    # Within a tolerance of 5 only the flipped bit fails.
    t = fpgfx.compare(expected, actual, tolerance=5)
    assert (t.failures, t.within_tolerance) == (1, 2)
    same = fpgfx.compare(expected, expected)
    assert same and same.failures == 0 and same.psnr_db == float("inf")


def test_compare_takes_any_strides():
    a = np.zeros((3, 4, 3), dtype=np.uint8)
    a[1, 2] = 9
    b = np.ascontiguousarray(a.transpose(1, 0, 2)).transpose(1, 0, 2)  # Fortran-like strides
    assert not b.flags["C_CONTIGUOUS"] and fpgfx.compare(a, b).failures == 0


def test_compare_edge_allowance_from_a_raster_job(repo):
    expected = fpgfx.raster(repo / FITKIT).image
    actual = expected.copy()
    # A pixel on the white anti-diagonal line: allowed as near an edge.
    y, x = next((y, x) for y in range(240) for x in range(320) if (expected[y, x] == 255).all())
    actual[y, x] = 0
    assert fpgfx.compare(expected, actual).failures == 1
    c = fpgfx.compare(expected, actual, raster=repo / FITKIT, coverage_precision=0)
    assert c.passed and c.near_edge == 1


# ---- errors -----------------------------------------------------------------------


def test_error_is_a_value_error():
    assert issubclass(fpgfx.Error, ValueError)


def test_a_bad_raster_file_names_file_and_line():
    with pytest.raises(fpgfx.Error, match=r"job\.toml.*line 3"):
        fpgfx.raster('size = [8, 8]\nbackground = "#000000"\ncmd = 3 3\n', name="job.toml")


def test_a_bad_raster_command_names_its_index():
    job = {"size": [8, 8], "cmd": [{"op": "line", "from": [0, 0], "to": [7, 7], "color": "#fff"}]}
    with pytest.raises(fpgfx.Error, match=r"<raster job dict>.*cmd\[0\].*color"):
        fpgfx.raster(job)


def test_a_job_the_fitkit_cannot_carry_is_refused_only_with_records():
    job = {"size": [32, 32], "cmd": [{"op": "circle", "center": [16.0, 16.0], "radius": 5.0, "color": "#ffffff"}]}
    assert fpgfx.raster(job).image.shape == (32, 32, 3)
    with pytest.raises(fpgfx.Error, match=r"cmd\[0\] \(circle\).*FITkit|cmd\[0\] \(circle\).*fitkit"):
        fpgfx.raster(job, records=True)


def test_a_bad_scene_names_file_line_and_key(repo):
    text = (repo / REFERENCE).read_text().replace("spp = 1", "spp = \"one\"", 1)
    with pytest.raises(fpgfx.Error, match=r"scene\.toml:11.*spp"):
        fpgfx.render(text, name="scene.toml")


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"numeric": "q3.3"}, r"numeric: \"q3\.3\""),
        ({"size": (0, 10)}, r"size: 0x10"),
        ({"spp": 0}, r"spp: 0"),
    ],
)
def test_bad_render_arguments_are_named(repo, kwargs, message):
    with pytest.raises(fpgfx.Error, match=message):
        fpgfx.render(repo / REFERENCE, **kwargs)


def test_a_missing_file_is_an_error(tmp_path):
    with pytest.raises(fpgfx.Error, match="cannot read"):
        fpgfx.raster(tmp_path / "nope.toml")


@pytest.mark.parametrize(
    "job, exc, message",
    [
        (42, TypeError, r"job: expected the raster job as TOML text"),
        ({"size": [8, 8], "cmd": None}, TypeError, r"job\[\"cmd\"\]: NoneType has no TOML form"),
        ({1: 2}, TypeError, r"keys must be str"),
    ],
)
def test_jobs_of_the_wrong_type_are_type_errors(job, exc, message):
    with pytest.raises(exc, match=message):
        fpgfx.raster(job)


@pytest.mark.parametrize(
    "expected, actual, exc, message",
    [
        (np.zeros((4, 4, 3), np.float32), np.zeros((4, 4, 3), np.uint8), TypeError, r"expected: dtype is float32, expected uint8"),
        (np.zeros((4, 4, 3), np.uint8), [[0]], TypeError, r"actual: expected a numpy array"),
        (np.zeros((4, 4, 3), np.uint8), np.zeros((4, 4), np.uint8), fpgfx.Error, r"actual: shape is \[4, 4\]"),
        (np.zeros((4, 4, 3), np.uint8), np.zeros((4, 4, 4), np.uint8), fpgfx.Error, r"actual: shape is \[4, 4, 4\]"),
        (np.zeros((0, 4, 3), np.uint8), np.zeros((0, 4, 3), np.uint8), fpgfx.Error, r"expected: shape is \[0, 4, 3\]"),
        (np.zeros((4, 4, 3), np.uint8), np.zeros((4, 5, 3), np.uint8), fpgfx.Error, r"sizes differ"),
    ],
)
def test_bad_frames_are_refused_naming_the_argument(expected, actual, exc, message):
    with pytest.raises(exc, match=message):
        fpgfx.compare(expected, actual)


@pytest.mark.parametrize("tolerance", [-1, 0.5, 256, float("nan")])
def test_bad_tolerances_are_refused(tolerance):
    a = np.zeros((2, 2, 3), np.uint8)
    with pytest.raises(fpgfx.Error, match="tolerance"):
        fpgfx.compare(a, a, tolerance)


def test_coverage_without_a_job_is_refused():
    a = np.zeros((2, 2, 3), np.uint8)
    with pytest.raises(fpgfx.Error, match="coverage_precision.*raster="):
        fpgfx.compare(a, a, coverage_precision=4)


# ---- packers and maps -------------------------------------------------------------


def verilog_defines(path, prefix):
    """`define PREFIX_NAME VALUE` of a generated header as {NAME: int} (sized literals
    such as 8'h20 and 3'd1 read as Verilog reads them)."""
    out = {}
    for line in open(path):
        m = re.match(rf"`define {prefix}(\w+) (\S+)$", line.strip())
        if not m:
            continue
        value = m.group(2)
        if "'" in value:
            base, digits = value.split("'")[1][0], value.split("'")[1][1:]
            out[m.group(1)] = int(digits, {"h": 16, "d": 10, "b": 2}[base.lower()])
        else:
            out[m.group(1)] = int(value)
    return out


def test_pack_is_what_the_controller_sends_and_the_fifo_takes(repo):
    packets = fpgfx.pack(repo / FITKIT)
    rec = fpgfx.raster(repo / FITKIT, records=True).records
    assert [p.spi for p in packets] == rec.spi
    assert [(p.address, p.records) for p in packets] == rec.packets
    assert packets[0].command is None and packets[0].op == "setup"
    assert packets[0].address == fpgfx.fitkit.ADDR_SETUP
    ops = {"line": fpgfx.fitkit.ADDR_LINE, "triangle": fpgfx.fitkit.ADDR_TRIANGLE, "clear": fpgfx.fitkit.ADDR_CLEAR}
    assert [p.command for p in packets[1:]] == list(range(len(packets) - 1))
    for p in packets[1:]:
        assert p.address == ops[p.op], p
        # the transaction is the packet builder's for the same records
        assert p.spi == fpgfx.fitkit.packet(p.address, p.records)
        assert all(r < 1 << fpgfx.fitkit.RECORD_BITS for r in p.records)


def test_pack_on_other_layouts_has_no_spi_and_refuses_what_the_fitkit_cannot_carry(repo):
    wide = fpgfx.pack(repo / "examples/raster/gallery.toml", layout="wide")
    assert wide and all(p.spi is None and p.command == i for i, p in enumerate(wide))
    assert wide[0].op == "clear"
    with pytest.raises(fpgfx.Error, match=r"gallery.toml: cmd\[0\] \(clear\).*RGB332"):
        fpgfx.pack(repo / "examples/raster/gallery.toml")
    with pytest.raises(fpgfx.Error, match="layout: \"vga\" is not one of fitkit, extended, wide"):
        fpgfx.pack(repo / FITKIT, layout="vga")


def test_the_fitkit_map_is_the_rtls_header(repo):
    header = verilog_defines(repo / "hw/fitkit-raster/rtl/fitkit_map.vh", "FITKIT_")
    assert len(header) > 30
    for name, value in header.items():
        assert getattr(fpgfx.fitkit, name) == value, name
    import fpgfx.fitkit as fk  # the submodule imports by name too

    assert fk is fpgfx.fitkit


def test_the_axi_map_is_the_cores_header(repo):
    header = verilog_defines(repo / "hw/rt-core/rtl/rt_axi_map.vh", "RT_AXI_")
    assert len(header) > 50
    for name, value in header.items():
        assert getattr(fpgfx.axi, name) == value, name
    from fpgfx.axi import REGISTERS, register_name

    assert REGISTERS["AP_CTRL"] == fpgfx.axi.AP_CTRL and REGISTERS["RT_CYCLES_LO"] == fpgfx.axi.SYS_RT_CYCLES
    assert all(register_name(a) == n for n, a in REGISTERS.items())
    assert list(fpgfx.axi.COUNTERS) == ["fragments", "cycles", "frames", "saturations"]


def test_fitkit_transactions_and_the_status_block():
    fk = fpgfx.fitkit
    assert fk.packet(fk.ADDR_CLEAR, [0x123456789]) == bytes([fk.ADDR_CLEAR, 0x12, 0x34, 0x56, 0x78, 0x90])
    assert fk.read_header(3, 4) == bytes([fk.ADDR_READ, 0x00, 0x08, 0x03, 0x00])
    assert fk.pixel_address(3, 4) == 4 * 512 + 3
    block = bytearray(fk.STATUS_BYTES)
    block[fk.STATUS_FREE : fk.STATUS_FREE + 2] = (300).to_bytes(2, "big")
    block[fk.STATUS_FLAGS] = 1 << fk.FLAG_BUSY | 1 << fk.FLAG_ERROR | 1 << fk.FLAG_SETUP_DONE
    block[fk.STATUS_ERROR_CODE] = fk.ERR_OVERRUN
    block[fk.STATUS_ERROR_CHANNEL] = fk.ADDR_LINE
    block[fk.STATUS_ERROR_PACKET + 1] = 7
    block[fk.STATUS_FRAGMENTS : fk.STATUS_FRAGMENTS + 4] = (123456).to_bytes(4, "big")
    s = fk.status(bytes(block))
    assert s["free"] == 300 and s["fragments"] == 123456 and s["flags"] >> fk.FLAG_SETUP_DONE & 1
    # FLAG_* are bit numbers, as in the Verilog header; the flags by name are booleans
    assert (s["busy"], s["setup_done"], s["fifo_empty"], s["no_line"], s["no_triangle"]) == (True, True, False, False, False)
    assert s["error"]["code"] == fk.ERR_OVERRUN and s["error"]["name"] == "OVERRUN"
    assert (s["error"]["channel"], s["error"]["packet"]) == (fk.ADDR_LINE, 7)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda fk: fk.packet(1, [1 << 36, 0]), "record 0 = 0x1000000000 is wider than 36 bits"),
        (lambda fk: fk.packet(1, [1, 2, 3]), "a packet of 3 records"),
        (lambda fk: fk.read_header(512, 0), r"pixel \(512, 0\) is outside"),
        (lambda fk: fk.status(bytes(31)), "data: 31 bytes, a status block is 32"),
        (lambda fk: fk.status(bytes([0xFF] * 32)), "status byte 0 = 0xff is not a valid"),
    ],
)
def test_bad_fitkit_arguments_are_refused_naming_them(call, message):
    with pytest.raises(fpgfx.Error, match=message):
        call(fpgfx.fitkit)


def test_axi_writes_are_fpgfx_vectors_and_the_frames(repo, fpgfx_cli, tmp_path):
    scene = repo / "hw/rt-core/scenes/core.toml"
    fpgfx_cli("vectors", "render", scene, "--numeric", "q16.16", "--size", "16x9", "-o", tmp_path)
    writes = fpgfx.axi_writes(scene, "q16.16", size=(16, 9))
    assert writes.dtype == np.uint32 and writes.shape[1] == 2
    assert [(a << 32) | d for a, d in writes.tolist()] == hexwords(tmp_path / "axi_writes.hex")
    frame = fpgfx.render(scene, size=(16, 9))
    assert np.array_equal(frame.writes, writes)
    ax = fpgfx.axi
    n = frame.regs.size
    assert n == ax.SCENE_WORDS and np.array_equal(writes[:n, 1], frame.regs)
    assert writes[:n, 0].tolist() == [ax.SCENE_BASE + 4 * i for i in range(n)]
    assert writes[n:].tolist() == [[ax.NUMERIC, ax.NUMERIC_Q16_16], [ax.AOVS, 1], [ax.AP_CTRL, 1 << ax.AP_START]]


def stats_numbers(text, label):
    line = next(l for l in text.splitlines() if l.startswith(label))
    return [int(x) for x in re.findall(r"\b\d+\b", line)]


def test_render_counters_are_the_clis_and_the_cores(repo, fpgfx_cli, tmp_path):
    scene = repo / "hw/rt-core/scenes/core.toml"
    frame = fpgfx.render(scene, size=(16, 9))
    c = frame.counters
    cli = fpgfx_cli("render", scene, "--numeric", "q16.16", "--size", "16x9", "--stats", "-o", tmp_path / "m.png").stdout
    nominal, traced = stats_numbers(cli, "rays")
    assert (c["rays_nominal"], c["rays_traced"]) == (nominal, traced)
    assert c["cycles"] == stats_numbers(cli, "board time")[2]
    assert c["saturations"] == stats_numbers(cli, "saturations")[0] > 0
    # the ray-casting core's RTL, Verilated, counts the clocks the model says it will
    rtl = fpgfx_cli("render", scene, "--numeric", "q16.16", "--size", "16x9", "--stats", "-o", tmp_path / "r.png", port="rtl:rt").stdout
    assert c["core_cycles"] == stats_numbers(rtl, "board time")[2]
    assert "identical to the RTL's" in rtl
    assert np.array_equal(frame.image, read_png(tmp_path / "r.png"))



def test_a_register_image_renders_as_the_scene_it_came_from(repo):
    scene = repo / "hw/rt-core/scenes/core.toml"
    frame = fpgfx.render(scene, size=(16, 9))
    again = fpgfx.render(frame.regs)
    assert np.array_equal(again.image, frame.image) and np.array_equal(again.depth, frame.depth)
    assert np.array_equal(again.normal, frame.normal) and again.counters == frame.counters
    assert np.array_equal(fpgfx.axi_writes(frame.regs), frame.writes)
    # read-only and strided arrays are images too
    view = np.repeat(frame.regs, 2)[::2]
    view.flags.writeable = False
    assert np.array_equal(fpgfx.render(view).image, frame.image)


@pytest.mark.parametrize(
    "change, kwargs, exc, message",
    [
        (lambda r: r.astype(np.int64), {}, TypeError, "scene: dtype is int64, expected uint32"),
        (lambda r: r[:-1], {}, fpgfx.Error, r"scene: shape is \[\d+\], a register image is \(\d+,\)"),
        (lambda r: r, {"size": (4, 4)}, fpgfx.Error, "size: 4x4 given with a register image"),
        (lambda r: r, {"spp": 2}, fpgfx.Error, "spp: 2 given with a register image"),
        (lambda r: np.where(np.arange(r.size) == 0, 0xFFFFFFFF, r).astype(np.uint32), {}, fpgfx.Error, "magic word is 0xffffffff"),
    ],
)
def test_a_bad_register_image_is_refused_naming_what(repo, change, kwargs, exc, message):
    regs = fpgfx.render(repo / "hw/rt-core/scenes/core.toml", size=(8, 4)).regs
    with pytest.raises(exc, match=message):
        fpgfx.render(change(regs), **kwargs)


def test_a_corrupt_word_anywhere_in_the_image_is_an_error_or_a_frame(repo):
    """Every word of the image set to all ones: the device's decoder names the field it
    refuses, or the frame renders; the interpreter never sees a panic."""
    regs = fpgfx.render(repo / "hw/rt-core/scenes/core.toml", size=(4, 4)).regs
    refused = 0
    for i in range(regs.size):
        bad = regs.copy()
        bad[i] = 0xFFFFFFFF
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fpgfx.render(bad)
        except fpgfx.Error as e:
            assert str(e), i
            refused += 1
    assert refused > 20, refused
