"""``n_threads`` is validated by one declaration (``_params.Threads``) at every entry point
that takes it: ``True`` is a TypeError and 2**70 a ValueError, each naming ``n_threads``,
never PyO3's OverflowError or a bool read as one thread.

The list below is checked against the package itself: every public callable (and every
configurable class) whose signature has ``n_threads`` must be in it, so a new entry point
cannot skip this test."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
from collections.abc import Callable
from typing import Any

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.evaluation import perfect_association_fit
from passive_assoc.radar_esm import bearing_fixes, coarse_gate, filter_reports
from passive_assoc.simulation import static_scan

SCAN = static_scan(1, n_targets=3)
FTI = pa.paper_fti_scenario(1)
TRACKS = pa.TrackTable.from_arrays([0, 0], [0, 1], [0.0, 0.0], [[0.0, 0.0], [1e3, 0.0]])
REPORTS = pa.TrackTable.from_arrays(
    [0] * 3, [0] * 3, [0.0, 1.0, 2.0], [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]], covariance=np.tile(np.eye(2), (3, 1, 1))
)
STATES = FTI.true_states[:1]


def _gate(n_threads: Any) -> Any:
    x, v = np.zeros((1, 1, 30)), np.ones((1, 1, 30))
    return coarse_gate(x, v, x, v, n_threads=n_threads)


#: (name, call with the given n_threads): every entry point that takes n_threads.
ENTRY_POINTS: dict[str, Callable[[Any], Any]] = {
    "fit_ml": lambda n: pa.fit_ml(FTI.measurements, FTI.sensors, FTI.true_groups(), n_threads=n),
    "closeness": lambda n: pa.closeness(FTI.measurements, FTI.sensors, STATES, n_threads=n),
    "maximize_closeness": lambda n: pa.maximize_closeness(
        FTI.measurements, FTI.sensors, STATES, np.eye(6)[None] * 1e4, n_threads=n
    ),
    "FuzzyTrackInitiator": lambda n: pa.FuzzyTrackInitiator(n_threads=n),
    "initiate_tracks": lambda n: pa.initiate_tracks(FTI.measurements, FTI.sensors, n_threads=n),
    "KalmanFilter": lambda n: pa.KalmanFilter(process_noise=1.0, n_threads=n),
    "StaticAssociator": lambda n: pa.StaticAssociator(n_threads=n),
    "associate_static": lambda n: pa.associate_static(SCAN.measurements, SCAN.sensors, n_threads=n),
    "associate_scans": lambda n: pa.associate_scans(SCAN.measurements, SCAN.sensors, n_threads=n),
    "enumerate_candidates": lambda n: pa.enumerate_candidates(SCAN.measurements, SCAN.sensors, n_threads=n),
    "FormationLocator": lambda n: pa.FormationLocator(n_threads=n),
    "locate_formation": lambda n: pa.locate_formation(SCAN.measurements, SCAN.sensors, n_threads=n),
    "TopologyAssociator": lambda n: pa.TopologyAssociator(n_threads=n),
    "NearestNeighbourAssociator": lambda n: pa.NearestNeighbourAssociator(n_threads=n),
    "associate_tracks": lambda n: pa.associate_tracks(local=TRACKS, system=TRACKS, n_threads=n),
    "WaveletFuzzyAssociator": lambda n: pa.WaveletFuzzyAssociator(n_threads=n),
    "Chi2TrackAssociator": lambda n: pa.Chi2TrackAssociator(n_threads=n),
    "WaveletChi2Associator": lambda n: pa.WaveletChi2Associator(n_threads=n),
    # No row has a track: it returns before any fit, so only the declaration can refuse.
    "bearing_fixes": lambda n: bearing_fixes(
        SCAN.measurements, SCAN.sensors, np.full(len(SCAN.measurements), -1), n_threads=n
    ),
    "coarse_gate": _gate,
    "filter_reports": lambda n: filter_reports(REPORTS, 1.0, n_threads=n),
    # With no track to filter it returned before any check: True passed silently.
    "filter_reports of no reports": lambda n: filter_reports(REPORTS.select(np.zeros(0, dtype=int)), 1.0, n_threads=n),
    "perfect_association_fit": lambda n: perfect_association_fit(FTI, n_threads=n),
}


@pytest.mark.parametrize("name", sorted(ENTRY_POINTS))
def test_a_bool_is_a_type_error_and_a_huge_count_a_value_error(name: str) -> None:
    call = ENTRY_POINTS[name]
    with pytest.raises(TypeError, match=r"^n_threads: expected an integer or None, got bool True"):
        call(True)
    with pytest.raises(ValueError, match=r"^n_threads: 1180591620717411303424 is out of the 64-bit integer range"):
        call(2**70)
    with pytest.raises(ValueError, match=r"^n_threads: must be an integer >= 1 or None, got 0"):
        call(0)


def _public_callables() -> dict[str, Any]:
    """Every public function and class of the package's subpackages, by name."""
    found: dict[str, Any] = {}
    for module_name in ["passive_assoc", *(f"passive_assoc.{m}" for m in pa._SUBMODULES)]:
        module = importlib.import_module(module_name)
        for name in getattr(module, "__all__", []):
            value = getattr(module, name)
            if inspect.isfunction(value) or inspect.isclass(value):
                found[name] = value
    return found


def _takes_threads(value: Any) -> bool:
    if inspect.isclass(value):
        if dataclasses.is_dataclass(value):
            return any(f.name == "n_threads" for f in dataclasses.fields(value))
        return False
    return "n_threads" in inspect.signature(value).parameters


def test_every_entry_point_that_takes_n_threads_is_listed() -> None:
    takes = {name for name, value in _public_callables().items() if _takes_threads(value)}
    assert takes - set(ENTRY_POINTS) == set(), "add these to ENTRY_POINTS"
