"""Gated global nearest neighbour: the least summed NIS inside the gate, a track left unpaired
costing the gate, and its input checks."""

from __future__ import annotations

import numpy as np
import pytest
from passive_assoc.tracking import nearest_neighbour


def test_the_pairing_minimises_the_summed_nis() -> None:
    # Greedy would give report 0 to track 0 (1.0) and leave track 1 with 9.0: total 10.
    # The global pairing crosses them: 2.0 + 2.0.
    assert nearest_neighbour([[1.0, 2.0], [2.0, 9.0]], 16.0).tolist() == [1, 0]


def test_a_report_outside_the_gate_goes_to_no_track() -> None:
    assert nearest_neighbour([[20.0, 3.0]], 16.0).tolist() == [-1, 0]
    assert nearest_neighbour([[np.inf, np.inf]], 16.0).tolist() == [-1, -1]


def test_a_far_pair_is_not_forced_when_leaving_both_unpaired_is_cheaper() -> None:
    # Track 0 wants report 0 (1.0); track 1 could take report 1 only at 15.9 (inside the gate),
    # which beats leaving it unpaired (16): taken. At a gate of 10 it is outside: not.
    assert nearest_neighbour([[1.0, np.inf], [np.inf, 15.9]], 16.0).tolist() == [0, 1]
    assert nearest_neighbour([[1.0, np.inf], [np.inf, 15.9]], 10.0).tolist() == [0, -1]


def test_each_track_takes_at_most_one_report_and_each_report_one_track() -> None:
    rng = np.random.default_rng(0)
    for _ in range(50):
        nis = rng.exponential(8.0, size=(rng.integers(0, 5), rng.integers(0, 6)))
        chosen = nearest_neighbour(nis, 9.0)
        assert len(chosen) == nis.shape[1]
        taken = chosen[chosen >= 0]
        assert len(set(taken.tolist())) == len(taken)
        assert all(nis[k, r] <= 9.0 for r, k in enumerate(chosen.tolist()) if k >= 0)


def test_no_tracks_or_no_reports() -> None:
    assert nearest_neighbour(np.zeros((0, 3)), 16.0).tolist() == [-1, -1, -1]
    assert nearest_neighbour(np.zeros((2, 0)), 16.0).tolist() == []


@pytest.mark.parametrize(
    ("nis", "gate", "exc", "message"),
    [
        ([1.0, 2.0], 16.0, ValueError, r"^nis"),
        ([[1.0, np.nan]], 16.0, ValueError, r"^nis: every value must be >= 0"),
        ([[-1.0]], 16.0, ValueError, r"^nis: every value must be >= 0"),
        ([["a"]], 16.0, TypeError, r"^nis"),
        ([[1.0]], 0.0, ValueError, r"^gate: must be > 0"),
        ([[1.0]], np.inf, ValueError, r"^gate"),
    ],
)
def test_bad_input_names_the_argument(nis: object, gate: float, exc: type[Exception], message: str) -> None:
    with pytest.raises(exc, match=message):
        nearest_neighbour(nis, gate)  # type: ignore[arg-type]
