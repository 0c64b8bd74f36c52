"""Shared fixtures: the repository's paths and the `fpgfx` CLI the bindings are held to."""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def repo():
    return REPO


@pytest.fixture(scope="session")
def fpgfx_cli():
    """Runs the `fpgfx` binary: $FPGFX_BIN (which `cargo xtask test` sets, so there a
    missing binary fails), else one built in target/. Skips when neither exists, so that
    `pytest` after a bare `pip install` still runs every test that needs no CLI."""
    given = os.environ.get("FPGFX_BIN")
    if given:
        path = pathlib.Path(given)
        assert path.is_file(), f"FPGFX_BIN={given} does not exist"
    else:
        found = [REPO / "target" / p / "fpgfx" for p in ("debug", "release")]
        found = [p for p in found if p.is_file()]
        if not found:
            pytest.skip("no fpgfx binary (set FPGFX_BIN or cargo build --bin fpgfx)")
        path = found[0]

    def run(*args, check=True, port="builtin"):
        done = subprocess.run(
            [str(path), "--port", port, *map(str, args)],
            cwd=REPO,
            capture_output=True,
            text=True,
        )
        if check:
            assert done.returncode == 0, f"fpgfx {' '.join(map(str, args))}: {done.stderr}"
        return done

    return run
