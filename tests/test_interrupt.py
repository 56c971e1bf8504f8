"""Ctrl-C during a long compiled call raises KeyboardInterrupt promptly instead of after the
call: each case runs in a subprocess that sends itself SIGINT half a second into a call that
would otherwise run for hours (the subprocess timeout is the hang detector, not a timing
assertion)."""

from __future__ import annotations

import subprocess
import sys

import pytest

_PRELUDE = """
import os, signal, threading, time
import numpy as np
import passive_assoc as pa

def interrupt_soon():
    def fire():
        time.sleep(0.5)
        os.kill(os.getpid(), signal.SIGINT)
    threading.Thread(target=fire, daemon=True).start()

rng = np.random.default_rng(0)
"""

CASES = {
    # Branch-and-bound with no node or time limit on a problem it cannot prove in minutes.
    "exact S-D": """
grid = np.stack(np.meshgrid(*[np.arange(26)] * 3, indexing="ij"), -1).reshape(-1, 3)
grid = grid[(grid > 0).sum(axis=1) >= 2]
tuples = grid[rng.random(len(grid)) < 0.08]
costs = rng.normal(-5.0, 3.0, len(tuples))
interrupt_soon()
pa.assign_sd(tuples, costs, [25, 25, 25], method="exact", exact_backend="branch_bound",
             max_nodes=10**15, time_limit=None)
""",
    # The fuzzy initiation's candidates on 400 clutter bearings per sensor and scan.
    "fuzzy initiation": """
table = pa.MeasurementTable.from_arrays(
    np.repeat([0, 1, 0, 1], 400), np.repeat([0.0, 0.0, 30.0, 30.0], 400), rng.uniform(0.3, 2.8, 1600))
sensors = pa.SensorNetwork.planar(np.array([[-2e4, 0.0], [2e4, 0.0]]), 2e-3)
interrupt_soon()
pa.FuzzyTrackInitiator(v_max=None, max_candidates=10**9, ray_gate_sigmas=None).initiate(table, sensors)
""",
}


@pytest.mark.skipif(sys.platform == "win32", reason="the SIGINT chain is installed on POSIX")
@pytest.mark.parametrize("case", sorted(CASES))
def test_sigint_interrupts_a_long_call(case: str) -> None:
    script = _PRELUDE + "try:\n" + _indent(CASES[case]) + "\nexcept KeyboardInterrupt:\n    print('interrupted')\n"
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == "interrupted", (done.stdout, done.stderr[-2000:])


def _indent(code: str) -> str:
    return "\n".join("    " + line for line in code.strip().splitlines())
