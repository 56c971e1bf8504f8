"""Each Python default equals the compiled core's recommended value for the same option.

The core's options structs carry the project's defaults (`recommended()`; `Default` is it) and
the published method's settings (`paper()`); `_core.option_defaults()` reports them by Python
parameter name. The Python classes and functions pass every option to the core explicitly, so
a drift between the two would not show in any result: this test is where it shows.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

import pytest
from passive_assoc import _core
from passive_assoc.assignment.sd import SdParameters
from passive_assoc.estimation.fitting import fit_ml
from passive_assoc.estimation.kalman import KalmanFilter
from passive_assoc.formation.locator import FormationLocator
from passive_assoc.fti import maximize_closeness
from passive_assoc.fti.initiator import FuzzyTrackInitiator
from passive_assoc.radar_esm import WaveletFuzzyAssociator, coarse_gate
from passive_assoc.static_los.associator import StaticAssociator
from passive_assoc.topology.associator import TopologyAssociator

#: Options kind (a core options struct) → the Python classes and functions whose parameters
#: it holds. A kind's every value must be a parameter of at least one of them.
COUNTERPARTS: dict[str, list[Callable[..., Any]]] = {
    "initiation": [FuzzyTrackInitiator],  # InitiationOptions (its descent as descent_*)
    "descent": [maximize_closeness],  # DescentOptions
    "enumeration": [StaticAssociator],  # static_los EnumerateOptions
    "intensity": [StaticAssociator],  # static_los IntensityOptions
    "lagrangian": [SdParameters, StaticAssociator],  # LagrangianOptions (assign_sd's keywords)
    "branch_bound": [SdParameters, StaticAssociator],  # BranchBoundOptions
    "formation": [FormationLocator],  # FormationOptions
    "topology": [TopologyAssociator],  # TopologyOptions
    "decision": [TopologyAssociator],  # topology DecisionOptions
    "fit": [fit_ml],  # FitOptions
    "kalman": [KalmanFilter],  # KalmanOptions
    "coarse": [coarse_gate, WaveletFuzzyAssociator],  # radar_esm CoarseOptions
}


def _python_default(target: Callable[..., Any], name: str) -> Any:
    return inspect.signature(target).parameters[name].default


def _as_core(kind: str, target: Callable[..., Any], name: str) -> Any:
    """The Python default of `name`, in the core's terms where the two express it differently."""
    value = _python_default(target, name)
    if (kind, name) == ("decision", "threshold"):
        # TopologyAssociator's threshold is λ, a fraction of the grid's rings·sectors cells;
        # the core's decision threshold is absolute (W is a sum over the cells), λ·M·N, which
        # the associator computes the same way, so the two agree to the bit.
        return value * _python_default(target, "rings") * _python_default(target, "sectors")
    return value


def test_every_kind_has_its_python_counterparts() -> None:
    assert set(_core.option_defaults()) == set(COUNTERPARTS)
    assert set(_core.option_defaults(paper=True)) == set(COUNTERPARTS)


@pytest.mark.parametrize("kind", sorted(COUNTERPARTS))
def test_python_defaults_are_the_core_recommended_values(kind: str) -> None:
    core = _core.option_defaults()[kind]
    assert core, f"{kind}: the core reports no option"
    compared = set()
    for target in COUNTERPARTS[kind]:
        parameters = inspect.signature(target).parameters
        for name, value in core.items():
            if name not in parameters:
                continue
            python = _as_core(kind, target, name)
            assert python is not inspect.Parameter.empty, f"{target.__name__}({name}) has no default"
            assert python == value and type(python) is type(value), (
                f"{kind}: {target.__name__}({name}={python!r}) but the core recommends {value!r}"
            )
            compared.add(name)
    assert compared == set(core), f"{kind}: no Python parameter for {sorted(set(core) - compared)}"


@pytest.mark.parametrize("kind", sorted(COUNTERPARTS))
def test_paper_settings_cover_the_same_options(kind: str) -> None:
    assert set(_core.option_defaults(paper=True)[kind]) == set(_core.option_defaults()[kind])


def test_options_without_a_default_have_none_on_either_side() -> None:
    # The Kalman filter's process noise depends on the targets: Python requires it, and the
    # core's KalmanOptions has no Default (recommended() takes it). The coarse gate's χ²
    # threshold is computed in Python from gate_probability and the coefficients' count.
    assert _python_default(KalmanFilter, "process_noise") is inspect.Parameter.empty
    assert "process_noise" not in _core.option_defaults()["kalman"]
    assert "threshold" not in _core.option_defaults()["coarse"]


def test_paper_settings_are_the_published_rules() -> None:
    """A few of the published method's settings the reproductions rely on."""
    paper = _core.option_defaults(paper=True)
    assert paper["intensity"] == {"vote_fraction": 0.5, "valid_airspace": True, "max_chains": None}
    assert paper["initiation"]["detection_order"] == "closeness"
    assert paper["initiation"]["n_detect"] == 9
    assert paper["initiation"]["refine_passes"] == 0 and paper["initiation"]["candidate_scans"] == 1
    assert paper["decision"]["decision"] == "per_system_track"
    assert paper["kalman"]["motion"] == "ca"
