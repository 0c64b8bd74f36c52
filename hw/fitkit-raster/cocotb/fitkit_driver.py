"""Drives the FITkit raster block (``fitkit_cocotb_top``: ``fitkit_sim_top`` and a
clock) as its controller does, over SPI with cocotbext-spi's ``SpiMaster``, and watches
its memory port.

Every SPI address, status field and flag comes from ``fpgfx.fitkit`` and every packet's
bytes from ``fpgfx.pack``, the same Rust definitions the block's generated Verilog header
and the controller's firmware use, so the testbench holds no second copy of the map.

Every wait is bounded in clock cycles and fails with the job, the packet and the last
status it read, so a stuck block ends the test with a message instead of a hang.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import cocotb
import fpgfx
import numpy as np
from cocotb.triggers import FallingEdge, RisingEdge, Timer
from cocotb.utils import get_sim_time
from cocotbext.spi import SpiBus, SpiConfig, SpiMaster
from fpgfx import fitkit

#: The block's clock period in ns: 50 MHz, the FITkit's (passed to fitkit_cocotb_top).
CLK_NS = 20
#: SCK half period in clk cycles: the floor docs/rtl.md sets (f_SCK ≤ f_clk / 8), which
#: the Rust bridge's master keeps too. Every transaction starts at a falling clk edge
#: and every interval of the master is a whole number of clk periods, so each SPI edge
#: falls half a clock away from the block's sampling edge: no race, exact counts.
SCK_HALF_CLKS = 4
#: CS_n high between transactions, in clk cycles (docs/rtl.md's floor, 8).
CS_GAP_CLKS = 8


class DutTimeout(AssertionError):
    """The block did not get where a wait wanted it within the bound."""


class DutError(AssertionError):
    """The block latched an error (status flag bit 1), or answered wrongly."""


def describe(status: dict[str, Any]) -> str:
    """A status block as one line, flags by name, for failure messages."""
    names = ("busy", "fifo_empty", "setup_done", "no_line", "no_triangle")
    set_ = ["error"] if status["error"] is not None else []
    flags = "|".join(set_ + [n for n in names if status[n]]) or "none"
    rest = ", ".join(f"{k}={v}" for k, v in status.items() if k != "flags" and k not in names)
    return f"flags={flags} ({status['flags']:#04x}), {rest}"


def cycles() -> int:
    """Clock cycles since the simulation started."""
    return int(get_sim_time("ns")) // CLK_NS


@dataclass
class WriteMonitor:
    """Holds every write the block's memory port issues, in order, to the model's
    ``records.writes`` rows (kind, x, y, RGB332 word). A request counts in the cycle it
    is asserted and ``mem_wait`` is low, as the RAM takes it (docs/rtl.md)."""

    dut: Any
    expected: np.ndarray
    job: str
    #: Called with the failure message before the monitor raises: the test's coroutine is
    #: not the one that raises, so this is how a harness learns the message.
    on_fail: Callable[[str], None] | None = None
    seen: int = 0
    error: str | None = None
    _task: Any = field(default=None, repr=False)

    def start(self) -> None:
        self._task = cocotb.start_soon(self._run())

    def stop(self) -> None:
        if self._task is not None:
            self._task.kill()

    async def _run(self) -> None:
        clk, port, mem_wait = self.dut.clk, self.dut.u_sim, self.dut.mem_wait
        rows = self.expected.tolist()
        while True:
            if not port.mem_we.value:
                # Sleep while the port is quiet (the read-back, the SPI traffic): only
                # the cycles with a write request wake Python.
                await RisingEdge(port.mem_we)
            await RisingEdge(clk)
            # Values read at the edge are those the RAM samples there.
            if not port.mem_we.value or mem_wait.value:
                continue
            addr, word = int(port.mem_addr.value), int(port.mem_wdata.value)
            if self.seen >= len(rows):
                self._fail(
                    f"write #{self.seen} (address {addr:#07x}, word {word:#04x}) "
                    f"after the model's last ({len(rows)} writes)"
                )
            kind, x, y, want = rows[self.seen]
            if (addr, word) != (fitkit.pixel_address(x, y), want):
                what = "clear" if kind == 0 else "fragment"
                got_x, got_y = addr % 512, addr // 512
                self._fail(
                    f"write #{self.seen}: the model's is the {what} ({x}, {y}) = {want:#04x} "
                    f"(address {fitkit.pixel_address(x, y):#07x}); the block wrote "
                    f"({got_x}, {got_y}) = {word:#04x} (address {addr:#07x})"
                )
            self.seen += 1

    def _fail(self, message: str) -> None:
        self.error = f"{self.job}: {message}"
        if self.on_fail is not None:
            self.on_fail(self.error)
        raise AssertionError(self.error)

    def check(self) -> None:
        """Fails with the first difference, if the monitor saw one."""
        if self.error:
            raise AssertionError(self.error)

    def check_complete(self) -> None:
        """Fails unless every expected write was seen (once the block is idle)."""
        self.check()
        if self.seen != len(self.expected):
            kind, x, y, want = self.expected[self.seen].tolist()
            raise AssertionError(
                f"{self.job}: the block wrote {self.seen} of the model's "
                f"{len(self.expected)} writes; the first missing is "
                f"({x}, {y}) = {want:#04x} ({'clear' if kind == 0 else 'fragment'})"
            )


class FitkitBench:
    """The block's pins, driven as the controller drives them over SPI."""

    def __init__(self, dut: Any) -> None:
        self.dut = dut
        bus = SpiBus.from_entity(
            dut,
            sclk_name="spi_sck",
            mosi_name="spi_mosi",
            miso_name="spi_miso",
            cs_name="spi_cs_n",
        )
        self.spi = SpiMaster(
            bus,
            SpiConfig(
                sclk_freq=1e9 / (2 * SCK_HALF_CLKS * CLK_NS),
                cpol=False,
                cpha=False,
                msb_first=True,
                frame_spacing_ns=CS_GAP_CLKS * CLK_NS,
                data_output_idle=0,
            ),
        )
        self.bytes_moved = 0
        self.polls = 0

    async def reset(self) -> None:
        """``rst`` for 4 cycles, then CS_n high for the 8 cycles docs/rtl.md asks for."""
        dut = self.dut
        dut.rst.value = 1
        dut.mem_wait.value = 0
        for _ in range(4):
            await RisingEdge(dut.clk)
        dut.rst.value = 0
        for _ in range(CS_GAP_CLKS):
            await RisingEdge(dut.clk)

    async def transfer(self, tx: bytes) -> bytes:
        """One CS_n-low transaction: ``tx`` out on MOSI, what MISO said back."""
        # Start half a clock away from the block's sampling edge, as spi_tasks.vh does.
        await FallingEdge(self.dut.clk)
        await self.spi.write(tx, burst=True)
        rx = self.spi.read_nowait(len(tx))
        self.bytes_moved += len(tx)
        return bytes(rx)

    async def status(self) -> dict[str, Any]:
        """The status block, decoded by the package."""
        rx = await self.transfer(bytes([fitkit.ADDR_STATUS]) + bytes(fitkit.STATUS_BYTES))
        self.polls += 1
        return fitkit.status(rx[1:])

    async def wait_status(
        self, what: str, done: Callable[[dict[str, Any]], bool], bound: int, where: str
    ) -> dict[str, Any]:
        """Polls the status until ``done(status)`` holds; fails at once on a latched
        error and after ``bound`` clk cycles with the last status read."""
        start = cycles()
        while True:
            s = await self.status()
            if s["error"] is not None:
                e = s["error"]
                raise DutError(
                    f"{where}: the block latched error {e['code']} ({e['message']}) on "
                    f"channel {e['channel']:#04x} at packet #{e['packet']} "
                    f"(status: {describe(s)})"
                )
            if done(s):
                return s
            if cycles() - start > bound:
                raise DutTimeout(
                    f"{where}: still waiting for {what} after {cycles() - start} clk cycles "
                    f"(bound {bound}); last status: {describe(s)}"
                )
            await Timer(50 * CLK_NS, "ns")

    async def send_packets(
        self, packets: list[fpgfx.Packet], job: str, bound: int, first: int = 0
    ) -> None:
        """Each packet's transaction, after a status poll has shown room for all of its
        records: the controller's back-pressure, and an error is caught at the packet
        that caused it. ``first`` is the first packet's index in the job, for messages."""
        for i, p in enumerate(packets, start=first):
            cmd = "" if p.command is None else f", command {p.command}"
            where = f"{job}, packet #{i} ({p.op}{cmd})"
            need = len(p.records)
            await self.wait_status(
                f"{need} free FIFO records", lambda s, need=need: s["free"] >= need, bound, where
            )
            await self.transfer(p.spi)

    async def wait_idle(self, job: str, after: str, bound: int) -> dict[str, Any]:
        """Waits for flag ``busy`` to clear: every packet run and written."""
        return await self.wait_status(
            "busy to drop",
            lambda s: not s["busy"],
            bound,
            f"{job}, after {after}",
        )

    async def read_frame(self, width: int, height: int) -> np.ndarray:
        """The framebuffer's top-left ``width`` × ``height`` RGB332 words, read back over
        SPI (channel ADDR_READ) one row per transaction: rows are 512 words apart in
        memory, so one long read would clock every pixel between them too."""
        rows = []
        for y in range(height):
            header = fitkit.read_header(0, y)
            rx = await self.transfer(header + bytes(width))
            rows.append(np.frombuffer(rx[fitkit.READ_HEADER_BYTES :], dtype=np.uint8))
        return np.stack(rows)
