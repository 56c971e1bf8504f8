"""The initiation's progress reports (``initiate(progress=...)``): the bar, what it shows, that
it changes nothing in the answer, a callable of the user's own, what a failing one does, and
that short calls build no bar."""

from __future__ import annotations

import time

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc._progress import StageBar
from passive_assoc.fti import FuzzyTrackInitiator


def scene() -> pa.Scenario:
    return pa.bearing_only_2d_scenario(seed=2, n_targets=3)


def test_the_bar_shows_each_pass_and_changes_nothing(capsys: pytest.CaptureFixture[str]) -> None:
    s = scene()
    shown = FuzzyTrackInitiator().initiate(s.measurements, s.sensors, progress=True)
    drawn = capsys.readouterr().err
    for label in ("pass 1: candidates", "pass 1: search", "pass 2: candidates", "pass 2: search"):
        assert label in drawn
    quiet = FuzzyTrackInitiator().initiate(s.measurements, s.sensors, progress=False)
    assert capsys.readouterr().err == ""
    assert np.array_equal(shown.labels, quiet.labels) and len(shown.tracks) == 3


def test_a_callable_gets_each_stage_from_0_to_1() -> None:
    """The binding forwards each stage's first and last report, in pipeline order."""
    reports: list[tuple[str, float]] = []
    s = scene()
    FuzzyTrackInitiator().initiate(s.measurements, s.sensors, progress=lambda *r: reports.append(r))
    runs: list[tuple[str, list[float]]] = []
    for stage, fraction in reports:
        if runs and runs[-1][0] == stage:
            runs[-1][1].append(fraction)
        else:
            runs.append((stage, [fraction]))
    assert [stage for stage, _ in runs] == ["candidates", "search", "candidates", "search"]
    for stage, fractions in runs:
        assert fractions[0] == 0.0 and fractions[-1] == 1.0, (stage, fractions)
        assert fractions == sorted(fractions), (stage, fractions)


def test_what_the_callable_raises_is_raised() -> None:
    def failing(stage: str, fraction: float) -> None:
        raise RuntimeError(f"the bar broke at {stage}")

    s = scene()
    with pytest.raises(RuntimeError, match="the bar broke at candidates"):
        FuzzyTrackInitiator().initiate(s.measurements, s.sensors, progress=failing)


def test_a_short_call_builds_no_bar_and_passes_are_numbered() -> None:
    auto = StageBar("candidates", always=False)
    for stage in ("candidates", "search", "candidates", "search"):
        auto(stage, 0.5)
    assert auto.bar is None and auto.passes == 2
    auto.close()


def test_a_new_stage_redraws_as_it_goes(capsys: pytest.CaptureFixture[str]) -> None:
    """After a stage ends at 100 %, the next stage's progress is drawn (tqdm's last drawn count
    follows the bar back to 0)."""
    bar = StageBar("candidates", always=True)
    bar("candidates", 0.0)
    time.sleep(0.15)  # past tqdm's redraw interval
    bar("candidates", 1.0)
    bar("search", 0.0)
    time.sleep(0.15)
    bar("search", 0.5)
    bar.close()
    assert "pass 1: search:  50%" in capsys.readouterr().err


@pytest.mark.parametrize("bad", ["yes", 1, 0.5])
def test_progress_must_be_a_bool_none_or_a_callable(bad: object) -> None:
    s = scene()
    with pytest.raises(TypeError, match="progress: expected a bool, None or a callable"):
        FuzzyTrackInitiator().initiate(s.measurements, s.sensors, progress=bad)  # type: ignore[arg-type]
