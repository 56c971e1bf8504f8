"""One contract per role: every method of a role has the role's call, and every result starts
with ``termination``, ``success`` and ``message``."""

from __future__ import annotations

import dataclasses
import inspect

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.outcome import Outcome
from passive_assoc.radar_esm import Chi2TrackAssociator
from passive_assoc.roles import Initiator, Locator, ScanAssociator, TrackAssociator
from passive_assoc.simulation import paper_formation_scene, static_scan

TRACK_ASSOCIATORS = [
    pa.TopologyAssociator,
    pa.NearestNeighbourAssociator,
    pa.WaveletFuzzyAssociator,
    Chi2TrackAssociator,
]


def test_each_method_plays_its_role() -> None:
    assert isinstance(pa.FuzzyTrackInitiator(), Initiator)
    assert isinstance(pa.StaticAssociator(), ScanAssociator)
    assert isinstance(pa.FormationLocator(), Locator)
    for cls in TRACK_ASSOCIATORS:
        assert isinstance(cls(), TrackAssociator), cls


@pytest.mark.parametrize("cls", TRACK_ASSOCIATORS)
def test_track_associators_take_both_sides_by_keyword(cls: type) -> None:
    """``associate(*, local, system)``: the two sides are keyword-only and named alike."""
    parameters = inspect.signature(cls.associate).parameters
    for name in ("local", "system"):
        assert parameters[name].kind is inspect.Parameter.KEYWORD_ONLY, (cls, name)


def _outcome_first(result: Outcome) -> None:
    names = [f.name for f in dataclasses.fields(result)]
    assert names[:3] == ["termination", "success", "message"]
    assert isinstance(result.termination, str) and result.termination
    assert isinstance(result.success, bool) and isinstance(result.message, str) and result.message


@pytest.mark.parametrize("method", ["intensity", "lagrangian", "exact"])
def test_static_association_outcome(method: str) -> None:
    scan = static_scan(3, n_targets=4)
    result = pa.associate_static(scan.measurements, scan.sensors, method)  # type: ignore[arg-type]
    _outcome_first(result)
    assert result.success
    if method == "intensity":
        assert result.termination == "completed" and result.diagnostics.intensity is not None
    else:
        assert result.diagnostics.solver is not None and result.termination in ("optimal", "gap_reached")


def test_other_results_outcome() -> None:
    scene = paper_formation_scene(0, sigma_deg=0.0)
    _outcome_first(pa.locate_formation(scene.measurements, scene.sensors, attribute_std=scene.attribute_std))
    scenario = pa.paper_fti_scenario(seed=1)
    initiated = pa.FuzzyTrackInitiator().initiate(scenario.measurements, scenario.sensors, progress=False)
    _outcome_first(initiated)
    assert initiated.termination == "completed" and str(len(initiated.tracks)) in initiated.message
    empty = pa.TrackTable.from_arrays(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 2)))
    _outcome_first(pa.TopologyAssociator().associate(local=empty, system=empty))


def test_no_candidate_is_a_termination_not_only_a_warning() -> None:
    scenario = pa.paper_fti_scenario(seed=1)
    with pytest.warns(UserWarning, match="no candidate survived"):
        result = pa.FuzzyTrackInitiator(v_max=1e-3).initiate(scenario.measurements, scenario.sensors)
    assert result.termination == "no_candidates" and "v_max" in result.message
    assert len(result.tracks) == 0 and len(result.clutter) == len(scenario.measurements)
