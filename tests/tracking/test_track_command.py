"""``passive-assoc track`` with the built-in tracker, end to end from CSV files: forced with
``--tracker builtin``, and chosen by ``--tracker auto`` when Stone Soup cannot be imported."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from passive_assoc.cli import main as cli_main
from passive_assoc.evaluation.track_truth import track_targets
from passive_assoc.simulation import Scenario


def _files(scene: Scenario, folder: Path) -> list[str]:
    scene.measurements.to_csv(folder / "reports.csv")  # with the airborne site's positions
    scene.sensors.to_csv(folder / "sites.csv")
    return ["track", str(folder / "reports.csv"), "--sensors", str(folder / "sites.csv"), "--out", str(folder)]


def _outputs(folder: Path) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    table = np.genfromtxt(folder / "reports.track.csv", delimiter=",", names=True)
    rows = {name: table[name] for name in table.dtype.names or ()}
    return rows, json.loads((folder / "reports.track.json").read_text())


def test_the_built_in_tracker_runs_from_files(
    coastal: Scenario, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert cli_main([*_files(coastal, tmp_path), "--tracker", "builtin"]) == 0
    assert capsys.readouterr().out.startswith("builtin tracker: 5 track(s) over 192 time(s); ")
    rows, summary = _outputs(tmp_path)
    table = coastal.measurements
    assert summary["tracker"] == "builtin" and len(summary["tracks"]) == 5
    # Every input row once, in order, each in a track of the summary or in none.
    np.testing.assert_array_equal(rows["row"], np.arange(len(table)))
    np.testing.assert_array_equal(rows["time"], table.time)
    labels = rows["track"].astype(np.int64)
    ids = {track["track"] for track in summary["tracks"]}
    assert set(labels.tolist()) <= ids | {-1} and all((labels == k).any() for k in ids)
    assert table.truth is not None
    assert sorted(track_targets(labels, table.truth).tolist()) == [0, 1, 2, 3, 4]
    real = table.truth >= 0
    assert (labels[real] >= 0).mean() > 0.95 and (labels[~real] >= 0).mean() < 0.1
    assert (labels[real] >= 0).sum() > 0 and (labels < 0).sum() > 0  # neither set empty
    for track in summary["tracks"]:
        assert track["times"][-1] == table.time.max()  # held to the last report time
        assert np.shape(track["states"]) == (len(track["times"]), 4)
        mine = labels == track["track"]
        target = int(np.bincount(table.truth[mine][table.truth[mine] >= 0]).argmax())
        later = (table.truth == target) & (table.time > track["times"][0])
        assert np.mean(labels[later] == track["track"]) > 0.95
        truth = coastal.targets[target].position(np.array([track["times"][-1]]))[0]
        assert np.linalg.norm(np.asarray(track["states"][-1][:2]) - truth) < 250.0


def test_auto_falls_back_to_the_built_in_tracker_without_stone_soup(
    coastal: Scenario, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    forced, auto = tmp_path / "forced", tmp_path / "auto"
    forced.mkdir()
    auto.mkdir()
    assert cli_main([*_files(coastal, forced), "--tracker", "builtin"]) == 0
    monkeypatch.setitem(sys.modules, "stonesoup", None)  # as if not installed: import fails
    assert cli_main(_files(coastal, auto)) == 0
    assert "builtin tracker" in capsys.readouterr().out
    (forced_rows, forced_summary), (auto_rows, auto_summary) = _outputs(forced), _outputs(auto)
    assert auto_summary["tracker"] == "builtin"
    np.testing.assert_array_equal(auto_rows["track"], forced_rows["track"])
    assert auto_summary == forced_summary


def test_auto_takes_stone_soup_when_it_is_installed(coastal: Scenario, tmp_path: Path) -> None:
    pytest.importorskip("stonesoup")
    assert cli_main(_files(coastal, tmp_path)) == 0
    assert _outputs(tmp_path)[1]["tracker"] == "stonesoup"


def test_the_help_states_the_rule(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        cli_main(["track", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--tracker {auto,stonesoup,builtin}" in text
    assert "global nearest neighbour inside the gate" in text and "chi-square gate on its NIS" in text
    assert "auto (default): stonesoup if it is installed, else builtin" in text
