"""pytest entry of the FITkit raster block's cocotb testbench: builds ``fitkit_sim_top``
(in ``fitkit_cocotb_top``, which makes its clock) with Icarus through cocotb's Python runner and runs ``fitkit_tb``'s tests in it, so one
``pytest hw/fitkit-raster/cocotb`` (or ``cargo xtask cocotb``) runs everything.

The RTL is every ``.v`` of the block's ``rtl/`` and ``sim/`` folders (``sim/`` holds
``fitkit_cocotb_top`` too), the same globs ``run-tests.sh`` compiles ``tb_top`` from; ``FPGFX_RTL_DIR=DIR`` builds another copy of
``rtl/`` instead (a scratch copy with a deliberate bug, to see the testbench catch it),
as it does for the Verilator bridge. Build products go to ``target/cocotb``.
"""

from __future__ import annotations

import json
import os
import sys
import time
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import fpgfx
import pytest

from fitkit_driver import CLK_NS
from jobgen import invalid_jobs, random_job

HERE = Path(__file__).resolve().parent
BLOCK = HERE.parent
ROOT = BLOCK.parents[1]
TOP = "fitkit_cocotb_top"


def rtl_dir() -> Path:
    """The block's ``rtl/``, or ``$FPGFX_RTL_DIR``."""
    return Path(os.environ.get("FPGFX_RTL_DIR", BLOCK / "rtl")).resolve()


def build_dir() -> Path:
    """``target/cocotb`` under the workspace's target directory."""
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return (target if target.is_absolute() else ROOT / target) / "cocotb"


def test_generated_jobs_are_fitkit_jobs() -> None:
    """Every seed's job is one the FITkit layout carries (the model refuses others)."""
    for seed in range(1, 40):
        records = fpgfx.raster(random_job(seed), records=True).records
        assert len(records.spi) == len(records.packets) >= 2


@pytest.mark.parametrize("job,word", invalid_jobs(), ids=["circle", "coordinate", "colour"])
def test_an_invalid_job_is_refused_by_name(job: dict, word: str) -> None:
    """What the FITkit cannot draw is refused before any stimulus exists, naming why."""
    with pytest.raises(fpgfx.Error, match=word):
        fpgfx.raster(job, records=True)


def failed_tests(results: Path) -> list[str]:
    """The names of the failing cocotb tests in a results file."""
    return [
        case.get("name", "?")
        for case in ET.parse(results).iter("testcase")
        if any(True for _ in case.iter("failure"))
    ]


def test_rtl_draws_like_the_model(capsys: pytest.CaptureFixture[str]) -> None:
    """The cocotb regression (``fitkit_tb``) on Icarus."""
    with warnings.catch_warnings():  # 1.9 calls its runner experimental; it is pinned
        warnings.simplefilter("ignore", UserWarning)
        from cocotb.runner import get_runner

    rtl = rtl_dir()
    sources = sorted(rtl.glob("*.v")) + sorted((BLOCK / "sim").glob("*.v"))
    assert sources, f"no Verilog in {rtl}"
    assert any(s.name == f"{TOP}.v" for s in sources), f"no {TOP}.v in {BLOCK / 'sim'}"
    build = build_dir()
    tests = build / "tests"
    tests.mkdir(parents=True, exist_ok=True)
    # The runner names its results file after the pytest test (1.9.2 appends ".None"):
    # the folder holds that one file.
    for old in tests.iterdir():
        if old.is_file():
            old.unlink()
    summary = build / "summary.jsonl"
    summary.unlink(missing_ok=True)
    if str(HERE) not in sys.path:  # the runner hands the simulator this process's path
        sys.path.insert(0, str(HERE))

    runner = get_runner("icarus")
    started = time.monotonic()
    runner.build(
        verilog_sources=sources,
        includes=[rtl],
        hdl_toplevel=TOP,
        build_dir=build,
        parameters={"CLK_NS": CLK_NS},
        timescale=("1ns", "1ps"),
        always=True,
    )
    try:
        runner.test(
            hdl_toplevel=TOP,
            test_module="fitkit_tb",
            build_dir=build,
            test_dir=tests,
            extra_env={"FITKIT_COCOTB_SUMMARY": str(summary)},
        )
        failed: list[str] = []
    except SystemExit:  # the runner's way of saying a test failed, under pytest
        failed = [n for f in tests.iterdir() if f.is_file() for n in failed_tests(f)]
        failed = failed or [f"the simulation wrote no results into {tests}"]
    seconds = time.monotonic() - started

    rows = (
        [json.loads(line) for line in summary.read_text().splitlines()] if summary.exists() else []
    )
    jobs = [r for r in rows if "writes" in r]
    # cocotb 1.9's results file has no failure message: the tests write theirs here.
    messages = [
        r["failure"] if r["failure"].startswith(r["test"]) else f"{r['test']}: {r['failure']}"
        for r in rows
        if "failure" in r
    ]
    with capsys.disabled():
        print(
            f"\ncocotb (Icarus): {len(jobs)} jobs, {sum(r['writes'] for r in jobs)} writes, "
            f"{sum(r['pixels'] for r in jobs)} read-back pixels and "
            f"{sum(r['counters'] for r in jobs)} counters compared, "
            f"{sum(r['spi_bytes'] for r in jobs)} SPI bytes; {seconds:.1f} s"
        )
    assert not failed, f"cocotb tests {', '.join(failed)} failed:\n" + "\n".join(messages)
