"""cocotb tests of the FITkit raster block (``fitkit_sim_top``, the block and its
simulation RAM, inside ``fitkit_cocotb_top``, which makes its clock), with the fpgfx
golden model as the scoreboard.

Each generated job goes into the block as its controller sends it (``fpgfx.pack``: one
SPI transaction per FIFO packet, each after a status poll that shows room for it) while
a monitor holds every memory-port write, in order, to the model's
(``fpgfx.raster(job, records=True).records.writes``). Once the block is idle the frame is
read back over SPI and held to the model's RGB332 framebuffer word for word and, widened
to RGB, through ``fpgfx.compare``; the status block's counters are held to the model's.

Run by ``test_fitkit_cocotb.py`` (pytest, cocotb's Python runner, Icarus): docs/cocotb.md.
"""

from __future__ import annotations

import json
import os
import random
from typing import Any

import cocotb
import fpgfx
import numpy as np
from cocotb.regression import TestFactory
from cocotb.triggers import FallingEdge

from fitkit_driver import SCK_HALF_CLKS, DutError, DutTimeout, FitkitBench, WriteMonitor, describe
from jobgen import random_job, rgb332_image

#: The generated jobs' seeds: ``FITKIT_COCOTB_SEEDS`` (comma-separated) overrides them.
SEEDS = [int(s) for s in os.environ.get("FITKIT_COCOTB_SEEDS", "1,2,3,4,5,6,7,8").split(",")]

#: The seed of the job drawn with a stalling memory.
STALL_SEED = 9

#: The status block's counters and the model's names for them (vectors/src/raster.rs's
#: ExpectedStatus). Not end_cycle: the block counts it in wall cycles from the set-up, so
#: it includes the time the SPI takes to deliver each packet (about 30 000 cycles for a
#: job here against the model's 2 000, which assumes every packet already queued).
COUNTERS = {
    "packets": "commands",
    "fragments": "fragments",
    "line_cycles": "cycles_line",
    "triangle_cycles": "cycles_triangle",
    "clear_cycles": "cycles_clear",
}


def record(entry: dict[str, Any]) -> None:
    """Appends one test's figures to the summary the pytest wrapper prints."""
    path = os.environ.get("FITKIT_COCOTB_SUMMARY")
    if path:
        with open(path, "a") as f:
            f.write(json.dumps(entry) + "\n")


def bound_cycles(counters: dict[str, Any], spi_bytes: int) -> int:
    """How long any one wait may take, in clk cycles: four times the model's busy
    cycles and the job's SPI traffic, plus room for a few status polls. Generous,
    because it only has to tell a slow block from a stuck one."""
    sck = 2 * 8 * SCK_HALF_CLKS + 40  # a byte's clk cycles, with the master's gaps
    return (
        4 * (int(counters["cycles"]) + 16 * int(counters["commands"]))
        + 4 * sck * spi_bytes
        + 20_000
    )


async def start(dut: Any) -> FitkitBench:
    """A fresh SPI master and a reset (the clock runs in fitkit_cocotb_top)."""
    bench = FitkitBench(dut)
    await bench.reset()
    return bench


async def stall_memory(dut: Any, seed: int, duty: float) -> None:
    """``mem_wait`` high in ``duty`` of the cycles, chosen by ``random.Random(seed)``: the
    memory refusing requests (SDRAM refresh, VGA), which the block must hold."""
    rng = random.Random(seed)
    while True:
        await FallingEdge(dut.clk)
        dut.mem_wait.value = int(rng.random() < duty)


async def run_job(dut: Any, seed: int, stall: bool = False) -> None:
    """One generated job, every check; a failure's message goes into the summary too
    (cocotb 1.9's results file keeps none)."""
    name = f"job seed {seed}" + (" (memory stalls)" if stall else "")
    try:
        await check_job(dut, seed, name, stall)
    except Exception as e:
        record({"test": name, "failure": str(e)})
        raise


async def check_job(dut: Any, seed: int, name: str, stall: bool) -> None:
    """The checks of ``run_job``. With ``stall``, ``mem_wait`` is random while the job
    draws: the same writes, frame, packets and fragments, but the units' busy cycles
    then include the waits, which the model is not told, so those are not compared."""
    job = random_job(seed)
    width, height = job["size"]
    ref = fpgfx.raster(job, records=True, name=name)
    rec = ref.records
    packets = fpgfx.pack(job)
    # The package's packets are the records' own (one home, two views): a check that
    # the stimulus and the scoreboard describe the same job.
    assert [(p.address, list(p.records)) for p in packets] == [
        (tag, list(r)) for tag, r in rec.packets
    ], f"{name}: fpgfx.pack and records.packets disagree"
    assert [p.spi for p in packets] == list(rec.spi), f"{name}: fpgfx.pack and records.spi disagree"

    bench = await start(dut)
    monitor = WriteMonitor(
        dut, rec.writes, name, on_fail=lambda m: record({"test": name, "failure": m})
    )
    monitor.start()
    staller = cocotb.start_soon(stall_memory(dut, seed, 0.25)) if stall else None
    bound = bound_cycles(ref.records.counters, sum(len(p.spi) for p in packets))
    t0 = cocotb.utils.get_sim_time("ns")
    await bench.send_packets(packets, name, bound)
    status = await bench.wait_idle(name, f"the last packet (#{len(packets) - 1})", bound)
    monitor.check_complete()
    monitor.stop()
    if staller is not None:
        staller.kill()
        dut.mem_wait.value = 0

    frame = await bench.read_frame(width, height)
    want = rec.framebuffer
    if not np.array_equal(frame, want):
        ys, xs = np.nonzero(frame != want)
        first = ", ".join(
            f"({x}, {y}) {frame[y, x]:#04x} want {want[y, x]:#04x}"
            for y, x in list(zip(ys, xs))[:5]
        )
        raise AssertionError(f"{name}: {len(ys)} of {want.size} read-back pixels differ: {first}")
    cmp = fpgfx.compare(ref.image, rgb332_image(frame), tolerance=0, raster=job)
    assert cmp, f"{name}: fpgfx.compare: {cmp.failures} pixels fail, first {cmp.mismatches[:3]}"

    after = await bench.status()
    assert after["error"] is None, f"{name}: the read-back latched an error: {describe(after)}"
    compared = {k: m for k, m in COUNTERS.items() if not stall or k in ("packets", "fragments")}
    got = {k: status[k] for k in compared}
    model = {k: int(rec.counters[m]) for k, m in compared.items()}
    assert got == model, f"{name}: status counters {got}, the model's {model}"
    if stall:
        # The waits must have reached the port: the clears' busy cycles include them.
        clear, want_clear = status["clear_cycles"], int(rec.counters["cycles_clear"])
        assert clear > want_clear, f"{name}: {clear} clear cycles, no more than unstalled"

    dut._log.info(
        "%s: %dx%d, %d packets, %d writes, %d pixels, %d counters equal; %d SPI bytes, %d polls, %.0f us",
        name,
        width,
        height,
        len(packets),
        monitor.seen,
        frame.size,
        len(got),
        bench.bytes_moved,
        bench.polls,
        (cocotb.utils.get_sim_time("ns") - t0) / 1000,
    )
    record(
        {
            "test": name,
            "packets": len(packets),
            "writes": monitor.seen,
            "pixels": int(frame.size),
            "counters": len(got),
            "spi_bytes": bench.bytes_moved,
        }
    )


factory = TestFactory(run_job)
factory.add_option("seed", SEEDS)
factory.generate_tests(prefix="generated_")


@cocotb.test()
async def stalled_memory(dut: Any) -> None:
    """A generated job with ``mem_wait`` high in a quarter of the cycles while it draws."""
    await run_job(dut, STALL_SEED, stall=True)


@cocotb.test()
async def block_error_names_the_packet(dut: Any) -> None:
    """A packet cut one byte short is refused by the block (a length error it latches):
    the next status poll must fail with the error's code, message, channel and packet
    index, naming where the driver was."""
    job = random_job(101, commands=4)
    name = "job seed 101 (packet #2 cut short)"
    packets = fpgfx.pack(job)
    bad = packets[2]
    bench = await start(dut)
    await bench.send_packets(packets[:2], name, bound=20_000)
    await bench.transfer(bad.spi[:-1])
    try:
        await bench.send_packets(packets[3:], name, bound=20_000, first=3)
    except DutError as e:
        message = str(e)
    else:
        raise AssertionError(f"{name}: the block took a short packet without an error")
    expect = f"error {fpgfx.fitkit.ERR_LENGTH} (wrong payload length) on channel {bad.address:#04x} at packet #2"
    assert expect in message, message
    dut._log.info("block error: %s", message)
    record({"test": "block error", "message": message})


@cocotb.test()
async def stuck_block_times_out(dut: Any) -> None:
    """A block whose memory never accepts a write (``mem_wait`` held high) never drops
    busy: the wait must end at its bound with a message naming the job, the packet and
    the last status, rather than hang."""
    job = random_job(100, commands=2)
    name = "job seed 100 (mem_wait held high)"
    packets = fpgfx.pack(job)
    bench = await start(dut)
    dut.mem_wait.value = 1
    await bench.send_packets(packets, name, bound=20_000)
    try:
        s = await bench.wait_idle(name, f"the last packet (#{len(packets) - 1})", bound=20_000)
    except DutTimeout as e:
        message = str(e)
    else:
        raise AssertionError(f"{name}: the block went idle with its memory stalled: {describe(s)}")
    assert name in message and "busy" in message and "flags=busy" in message, message
    dut._log.info("stuck block: %s", message)
    record({"test": "stuck", "message": message})
