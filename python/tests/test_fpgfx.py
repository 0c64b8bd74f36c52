"""The Python bindings held to the `fpgfx` tool: the same frames, counters, records and
comparison figures, and a Python exception (never a crash) for every bad input."""

import json
import re
import threading

import numpy as np
import pytest

import fpgfx
import png

FITKIT = "examples/raster/fitkit.toml"
REFERENCE = "examples/reference.toml"


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
    golden = png.read(repo / "examples/raster/golden/fitkit.png")
    assert frame.image.dtype == np.uint8 and frame.image.shape == (240, 320, 3)
    assert np.array_equal(frame.image, golden)
    assert frame.records is None


@pytest.mark.parametrize("job", ["gallery.toml", "aa.toml"])
def test_every_raster_example_equals_its_golden_png(repo, job):
    frame = fpgfx.raster((repo / "examples/raster" / job).read_text(), name=job)
    golden = png.read(repo / "examples/raster/golden" / job.replace(".toml", ".png"))
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
    assert np.array_equal(png.read(tmp_path / "f.png"), fpgfx.raster(repo / FITKIT).image)


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
    assert np.array_equal(frame.image, png.read(out))
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
    png.write(tmp_path / "e.png", expected)
    png.write(tmp_path / "a.png", actual)
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
