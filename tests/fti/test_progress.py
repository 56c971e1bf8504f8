"""The initiation's progress bar (``initiate(progress=...)``): what it shows, that it changes
nothing in the answer, what a failing callback does, and that short calls build no bar."""

from __future__ import annotations

import time

import numpy as np
import passive_assoc as pa
import passive_assoc.fti.initiator as initiator_module
import pytest
from passive_assoc._progress import StageBar
from passive_assoc.fti import FuzzyTrackInitiator


def scene() -> pa.Scenario:
    return pa.bearing_only_2d_scenario(seed=2, n_targets=3)


class Recording(StageBar):
    """Records the reports the binding forwards instead of drawing them."""

    def __init__(self, first_stage: str, *, always: bool) -> None:
        super().__init__(first_stage, always=always)
        self.reports: list[tuple[str, float]] = []

    def __call__(self, stage: str, fraction: float) -> None:
        self.reports.append((stage, fraction))


class Failing(StageBar):
    def __call__(self, stage: str, fraction: float) -> None:
        raise RuntimeError(f"the bar broke at {stage}")


def test_the_bar_shows_each_pass_and_changes_nothing(capsys: pytest.CaptureFixture[str]) -> None:
    s = scene()
    shown = FuzzyTrackInitiator().initiate(s.measurements, s.sensors, progress=True)
    drawn = capsys.readouterr().err
    for label in ("pass 1: candidates", "pass 1: search", "pass 2: candidates", "pass 2: search"):
        assert label in drawn
    quiet = FuzzyTrackInitiator().initiate(s.measurements, s.sensors, progress=False)
    assert capsys.readouterr().err == ""
    assert np.array_equal(shown.labels, quiet.labels) and len(shown.tracks) == 3


def test_reports_go_stage_by_stage_from_0_to_1(monkeypatch: pytest.MonkeyPatch) -> None:
    """The binding forwards each stage's first and last report, in pipeline order."""
    bars: list[Recording] = []

    def recording(progress: bool | None, first_stage: str) -> Recording:
        bars.append(Recording(first_stage, always=False))
        return bars[-1]

    monkeypatch.setattr(initiator_module, "stage_bar", recording)
    s = scene()
    FuzzyTrackInitiator().initiate(s.measurements, s.sensors)
    runs: list[tuple[str, list[float]]] = []
    for stage, fraction in bars[0].reports:
        if runs and runs[-1][0] == stage:
            runs[-1][1].append(fraction)
        else:
            runs.append((stage, [fraction]))
    assert [stage for stage, _ in runs] == ["candidates", "search", "candidates", "search"]
    for stage, fractions in runs:
        assert fractions[0] == 0.0 and fractions[-1] == 1.0, (stage, fractions)
        assert fractions == sorted(fractions), (stage, fractions)


def test_what_the_callback_raises_is_raised(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(initiator_module, "stage_bar", lambda progress, first: Failing(first, always=True))
    s = scene()
    with pytest.raises(RuntimeError, match="the bar broke at candidates"):
        FuzzyTrackInitiator().initiate(s.measurements, s.sensors)


def test_a_short_call_builds_no_bar_and_passes_are_numbered() -> None:
    auto = StageBar("candidates", always=False)
    for stage in ("candidates", "search", "candidates", "search"):
        auto(stage, 0.5)
    assert auto.bar is None and auto.passes == 2
    auto.close()


def test_progress_must_be_a_bool_or_none() -> None:
    s = scene()
    with pytest.raises(TypeError, match="progress: expected a bool"):
        FuzzyTrackInitiator().initiate(s.measurements, s.sensors, progress="yes")  # type: ignore[arg-type]


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
