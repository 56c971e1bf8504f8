"""Smoke runs of the command line: `reproduce fti` and `reproduce intensity` end to end,
through their JSON records and plots (`reproduce formation`'s run is in
tests/experiments/test_formation_experiment.py; here only its help)."""

from __future__ import annotations

import errno
import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from passive_assoc.cli import main as cli_main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
#: The static-association methods `reproduce intensity` reports on.
METHODS = ("intensity", "lagrangian", "exact")


def test_reproduce_fti_smoke(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out_json, out_png = tmp_path / "fti.json", tmp_path / "fti.png"
    assert cli_main(["reproduce", "fti", "--runs", "3", "--json", str(out_json), "--plot", str(out_png)]) == 0
    printed = capsys.readouterr().out
    assert "Table 2" in printed and "Table 3" in printed and "CRLB" in printed
    record = json.loads(out_json.read_text())
    assert record["runs"] == 3 and len(record["found_per_run"]) == 3
    last = printed.splitlines()[-1]  # the run ends with its verdict against the paper, also in the JSON
    assert last == record["verdict"]["line"] and record["verdict"]["reproduces"] in (True, False)
    assert last.startswith(
        ("verdict: consistent with paper 000 at 3 runs", "verdict: does NOT reproduce paper 000 at 3")
    )
    assert np.array(record["rms_perfect"]).shape == (4, 6)
    assert out_png.stat().st_size > 10_000


def test_reproduce_fti_runs_the_papers_formation_unless_told(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`reproduce fti` forms the paper's candidates by default; `--candidates auto` runs the
    library's default (at two sensors, the witnessed formation) on the same runs, and the
    printed header and the JSON settings say which ran. The witnessed formation fits fewer
    candidates a run (the stage counts are in the JSON)."""
    fitted = {}
    for candidates in ("paper", "auto"):
        out_json = tmp_path / f"{candidates}.json"
        extra = [] if candidates == "paper" else ["--candidates", candidates]
        assert cli_main(["reproduce", "fti", "--runs", "2", "--json", str(out_json), *extra]) == 0
        assert f"candidates {candidates}" in capsys.readouterr().out
        record = json.loads(out_json.read_text())
        assert record["settings"]["candidates"] == candidates
        fitted[candidates] = record["mean_stage_counts"]["fitted"]
    assert 0 < fitted["auto"] < fitted["paper"], fitted


def test_reproduce_intensity_smoke(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out_json, out_png = tmp_path / "intensity.json", tmp_path / "intensity.png"
    argv = [
        "reproduce",
        "intensity",
        "--runs",
        "2",
        "--ratios",
        "15",
        "--max-m",
        "12",
        "--time-limit",
        "0.5",
        "--timing-scans",
        "2",
        "--max-iter",
        "50",
        "--sensor-order",
        "given",
        "--polish",
        "--json",
        str(out_json),
        "--plot",
        str(out_png),
    ]
    assert cli_main(argv) == 0
    printed = capsys.readouterr().out
    assert "Table 1" in printed and "Table 2" in printed
    record = json.loads(out_json.read_text())
    cells = record["accuracy"]["15"]
    assert set(cells) == {*METHODS, "truth_costlier_than_optimum_pct", "exact_proven_runs", "ghosts_per_scan_median"}
    assert all(0.0 <= cells[m]["accuracy_pct"] <= 100.0 for m in METHODS)
    assert [row["M"] for row in record["timing"] if row["S"] == 3] == [6, 12]
    assert all(row["scans"] == 2 for row in record["timing"])
    assert all(1 <= row["lagrangian_iterations"] <= 50 for row in record["timing"])  # --max-iter reaches the solver
    assert (record["settings"]["sensor_order"], record["settings"]["polish"]) == ("given", True)
    assert out_png.stat().st_size > 10_000


def test_reproduce_intensity_bayes_bound_smoke(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out_json = tmp_path / "bound.json"
    argv = [
        "reproduce",
        "intensity",
        "--runs",
        "2",
        "--ratios",
        "15",
        "--no-timing",
        "--time-limit",
        "0.5",
        "--bayes-bound",
        "--json",
        str(out_json),
    ]
    assert cli_main(argv) == 0
    assert "exact MAP under the scenario's own model" in capsys.readouterr().out
    bound = json.loads(out_json.read_text())["accuracy"]["15"]["bayes_map"]
    assert set(bound) == {"accuracy_pct", "truth_costlier_pct", "proven_runs"}
    assert 0.0 <= bound["accuracy_pct"] <= 100.0


def test_reproduce_topology_smoke(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out_json, out_png = tmp_path / "t.json", tmp_path / "t.png"
    args = ["reproduce", "topology", "--runs", "2", "--bias", "0", "5", "--coverage", "both"]
    assert cli_main([*args, "--json", str(out_json), "--plot", str(out_png)]) == 0
    text = capsys.readouterr().out
    assert "99.9034 / 99.5362 / 99.7195" in text and "±5°" in text
    record = json.loads(out_json.read_text())
    assert set(record) == {"full", "partial"}
    for coverage in record.values():
        assert [row["bias_deg"] for row in coverage["rows"]] == [0.0, 5.0]
        for row in coverage["rows"]:
            for method in ("paper rule", "topology", "fused", "nearest"):
                assert 0.0 <= row[method]["f1"] <= 100.0
    full = record["full"]["rows"]
    assert full[1]["topology"]["f1"] > full[1]["nearest"]["f1"], "at ±5° topology beats nearest neighbour"
    assert full[1]["fused"]["bias_within_3_std"] >= 0.9
    assert out_png.stat().st_size > 10_000


def test_reproduce_topology_ring_smoke(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out_json = tmp_path / "ring.json"
    args = ["reproduce", "topology", "--scenario", "ring", "--runs", "1", "--bias", "5", "--scans", "20"]
    assert cli_main([*args, "--json", str(out_json)]) == 0
    text = capsys.readouterr().out
    assert "28 radar pairs" in text and "topology (default)" in text and "nearest (default)" in text
    level = json.loads(out_json.read_text())["levels"]["5.0"]
    assert level["topology (default)"]["pair"]["f1"] > level["topology, assignment"]["pair"]["f1"] - 0.05
    assert level["topology (default)"]["bias"]["estimates"] > 20


def test_reproduce_wavelet_smoke(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out_json, out_png = tmp_path / "w.json", tmp_path / "w.png"
    args = ["reproduce", "wavelet", "--runs", "5", "--clutter", "0", "2", "--demo-runs", "2"]
    assert cli_main([*args, "--json", str(out_json), "--plot", str(out_png)]) == 0
    text = capsys.readouterr().out
    assert "paper: wavelet-fuzzy 0.88-0.93, nearest neighbour 0.72-0.85" in text and "2-D radar + passive" in text
    record = json.loads(out_json.read_text())
    assert set(record) == {"settings", "paper", "levels", "passive_2d"}
    assert set(record["levels"]) == {"0", "2"}
    ablations = ("wavelet_paper", "wavelet_per_scan", "wavelet_literal", "wavelet_raw", "combined_raw")
    assert not set(ablations) & set(record["levels"]["2"]), "the ablations run without false tracks only"
    for summary in [*record["levels"].values(), record["passive_2d"]]:
        compared = ("wavelet", "nearest", "chi2", "combined")
        for method in (*compared, *(ablations if summary is not record["levels"]["2"] else ())):
            cell = summary[method]
            assert len(cell["per_scan"]) == 30  # the trackers start from a prior: a track from scan 1
            values = [*cell["per_scan"], cell["mean_6_30"], cell["min_15_30"], cell["gate_keeps_true_6_30"]]
            assert all(0.0 <= v <= 1.0 for v in values)
    assert out_png.stat().st_size > 10_000


def test_reproduce_formation_is_listed_and_its_help_says_what_is_printed(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        cli_main(["reproduce", "--help"])
    assert "formation" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        cli_main(["reproduce", "formation", "--help"])
    text = capsys.readouterr().out
    assert "Table 2 (azimuth only) and Table 3" in text and "'ours / paper'" in text
    assert all(option in text for option in ("--runs", "--seed", "--workers", "--noise", "--plot", "--json"))


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["reproduce", "fti", "--workers", "0"], "--workers: expected an integer >= 1, got 0"),
        (["reproduce", "formation", "--runs", "-4"], "--runs: expected an integer >= 1, got -4"),
        (["reproduce", "wavelet", "--seed", "-1"], "--seed: expected an integer >= 0, got -1"),
        (["reproduce", "topology", "--json", ""], "--json: expected a file name"),
        (["reproduce", "intensity", "--plot", "/no/such/dir/x.png"], "does not exist"),
        (["reproduce", "topology", "--bias", "inf"], "--bias: expected a finite number, got 'inf'"),
        # refused by the library, not argparse: still a usage error, not a traceback
        (["reproduce", "fti", "--runs", "1", "--pd", "2"], "pd: must be in [0, 1], got 2.0"),
    ],
)
def test_bad_options_are_usage_errors(argv: list[str], message: str, capsys: pytest.CaptureFixture[str]) -> None:
    """argparse refuses them before any work (exit status 2, the message on stderr)."""
    with pytest.raises(SystemExit) as exit_info:
        cli_main(argv)
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err


_ASSOCIATE = [
    "associate",
    str(EXAMPLES / "associate_measurements.csv"),
    "--sensors",
    str(EXAMPLES / "associate_sensors.csv"),
]
_INITIATE = [
    "initiate",
    str(EXAMPLES / "initiate_measurements.csv"),
    "--sensors",
    str(EXAMPLES / "initiate_sensors.csv"),
]


@pytest.mark.parametrize(
    ("argv", "module", "extra", "what"),
    [
        (["reproduce", "fti", "--runs", "2", "--plot", "{tmp}/fti.png"], "matplotlib", "plot", "--plot"),
        ([*_ASSOCIATE, "--out", "{tmp}/out", "--plot", "{tmp}/a.png"], "matplotlib", "plot", "--plot"),
        ([*_INITIATE, "--out", "{tmp}/out", "--plot", "{tmp}/i.png"], "matplotlib", "plot", "--plot"),
        (
            ["track", *_INITIATE[1:], "--tracker", "stonesoup", "--out", "{tmp}/out"],
            "stonesoup",
            "stonesoup",
            "--tracker stonesoup",
        ),
        (["reproduce", "topology", "--runs", "1", "--scheduler", "local"], "dask", "dask", "--scheduler"),
        (["reproduce", "wavelet", "--runs", "1", "--scheduler", "local"], "distributed", "dask", "--scheduler"),
        (
            [
                "associate",
                "{tmp}/m.parquet",
                "--sensors",
                str(EXAMPLES / "associate_sensors.csv"),
                "--out",
                "{tmp}/out",
            ],
            "pyarrow",
            "parquet",
            "a .parquet MEAS file",
        ),
    ],
)
def test_a_missing_extra_is_one_line_before_any_work(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    argv: list[str],
    module: str,
    extra: str,
    what: str,
) -> None:
    """The extra is named with the checkout's install command, exit status 2, and nothing ran
    (nothing printed on standard output, nothing written): a missing extra is found before
    the run, not after it with a traceback and status 1."""
    (tmp_path / "m.parquet").write_bytes(b"")  # only its name matters: the check comes first
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == module else real(name, *a))
    before = sorted(tmp_path.iterdir())
    with pytest.raises(SystemExit) as stop:
        cli_main([a.format(tmp=tmp_path) for a in argv])
    out, err = capsys.readouterr()
    assert stop.value.code == 2 and out == ""
    assert err == (
        f"passive-assoc: error: {what} needs {module} (the '{extra}' extra), which is not installed: "
        f"pip install '.[{extra}]' in the passive-assoc checkout\n"
    )
    assert sorted(tmp_path.iterdir()) == before


def test_a_missing_module_is_caught_as_an_import_would_see_it(tmp_path: Path) -> None:
    """The same through the import system: matplotlib made unimportable in a fresh interpreter."""
    code = (
        "import sys\nsys.modules['matplotlib'] = None\nfrom passive_assoc.cli import main\n"
        f"sys.exit(main(['reproduce', 'fti', '--runs', '2', '--plot', {str(tmp_path / 'x.png')!r}]))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert (done.returncode, done.stdout) == (2, "")
    assert done.stderr.splitlines() == [
        "passive-assoc: error: --plot needs matplotlib (the 'plot' extra), which is not installed: "
        "pip install '.[plot]' in the passive-assoc checkout"
    ]


def _run(*argv: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "passive_assoc.cli", *argv], capture_output=True, text=True, timeout=300, cwd=cwd
    )


def test_a_library_warning_is_one_line() -> None:
    """The sensors and measurements swapped: the reader's warning, then the error, one line each
    (the warning without its source file and line or the code line under it)."""
    sensors, meas = str(EXAMPLES / "associate_sensors.csv"), str(EXAMPLES / "associate_measurements.csv")
    done = _run("associate", sensors, "--sensors", meas, "--out", "never")
    assert done.returncode == 2
    assert done.stderr.splitlines() == [
        f"passive-assoc: warning: {meas!r}: ignoring column(s) ['time', 'azimuth', 'elevation', 'truth'] "
        "(not part of a sensor file)",
        f"passive-assoc: error: {meas!r}: missing column 'x' (got ['sensor'])",
    ]


def test_ctrl_c_is_status_130_and_one_line(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """(That Ctrl-C reaches a long compiled call as KeyboardInterrupt is tests/test_interrupt.py's.)"""
    from passive_assoc.commands import associate

    def interrupted(args: object) -> int:
        raise KeyboardInterrupt

    monkeypatch.setattr(associate, "main", interrupted)
    assert cli_main([*_ASSOCIATE, "--out", str(tmp_path)]) == 130
    assert capsys.readouterr().err == "passive-assoc: interrupted\n"


def test_a_closed_standard_output_stops_quietly(tmp_path: Path) -> None:
    """`... --json | head -1`: the reader goes away; no traceback, status 141 as after SIGPIPE."""
    local, system = str(EXAMPLES / "topology_local.csv"), str(EXAMPLES / "topology_system.csv")
    command = [sys.executable, "-m", "passive_assoc.cli", "associate-tracks", local, "--system", system]
    process = subprocess.Popen(
        [*command, "--out", str(tmp_path), "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert process.stdout is not None and process.stderr is not None
    process.stdout.close()
    status, err = process.wait(timeout=300), process.stderr.read()
    process.stderr.close()
    assert status == 141
    assert err.startswith("1538 pairs;") and len(err.splitlines()) == 1, "the report line alone, no traceback"
    assert (tmp_path / "topology_local.associate-tracks.json").exists(), "the outputs were written first"


def test_a_file_that_cannot_be_written_is_one_line_and_status_1(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    from passive_assoc.commands import common

    def full(path: object, columns: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(common, "write_csv", full)
    with pytest.raises(SystemExit) as stop:
        cli_main([*_ASSOCIATE, "--out", str(tmp_path)])
    assert stop.value.code == 1
    assert capsys.readouterr().err == "passive-assoc: error: [Errno 28] No space left on device\n"
    assert list(tmp_path.iterdir()) == [], "no temporary file is left behind"


@pytest.mark.parametrize(
    "argv",
    [
        [*_ASSOCIATE, "--out", "{tmp}/out", "--plot", "{tmp}/figure"],
        ["reproduce", "fti", "--runs", "2", "--plot", "{tmp}/fti.txt"],
    ],
)
def test_a_plot_without_a_figure_format_is_refused_before_any_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str]
) -> None:
    """Refused before the run, not after it with "Format 'bc3b8f16' is not supported"
    (matplotlib reading the temporary file's random part as the format) or "Format 'txt'",
    the outputs written."""
    with pytest.raises(SystemExit) as stop:
        cli_main([a.format(tmp=tmp_path) for a in argv])
    out, err = capsys.readouterr()
    assert stop.value.code == 2 and out == "" and list(tmp_path.iterdir()) == []
    assert err.startswith("passive-assoc: error: --plot: ") and "needs a figure format as its extension: " in err
    assert ".pdf" in err and ".png" in err and len(err.splitlines()) == 1
