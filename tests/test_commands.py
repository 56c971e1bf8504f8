"""``passive-assoc initiate`` and ``associate`` on the example files: every input row appears
exactly once in the per-measurement output, the JSON agrees with it, bad files end in a usage
error naming the file, and a failed run writes nothing."""

from __future__ import annotations

import json
import os
import shutil
import stat
import warnings
from pathlib import Path

import numpy as np
import pytest
from passive_assoc.cli import main as cli_main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def read_rows(path: Path) -> dict[str, np.ndarray]:
    """The output opens in pandas (the issue's test), column by column as floats."""
    pd = pytest.importorskip("pandas")
    frame = pd.read_csv(path)
    return {name: frame[name].to_numpy(dtype=float) for name in frame.columns}


def test_initiate_writes_every_row_once(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    meas, sensors = EXAMPLES / "initiate_measurements.csv", EXAMPLES / "initiate_sensors.csv"
    assert cli_main(["initiate", str(meas), "--sensors", str(sensors), "--out", str(out), "--json"]) == 0
    printed = capsys.readouterr()
    rows = read_rows(out / "initiate_measurements.initiate.csv")
    n = len(read_rows(meas)["sensor"])
    assert rows["row"].tolist() == list(range(n))
    summary = json.loads((out / "initiate_measurements.initiate.json").read_text())
    assert json.loads(printed.out) == summary, "with --json, standard output is the summary alone"
    assert len(summary["tracks"]) == 4 and "4 track(s)" in printed.err
    for track in summary["tracks"]:
        assert sorted(track["rows"]) == np.flatnonzero(rows["track"] == track["track"]).tolist()
        assert len(track["state"]) == 6 and np.shape(track["covariance"]) == (6, 6)
    assert sorted(summary["clutter_rows"]) == np.flatnonzero(rows["track"] < 0).tolist()
    assert 0 < len(summary["clutter_rows"]) < n


def test_associate_writes_every_row_once(tmp_path: Path) -> None:
    out = tmp_path / "out"
    meas, sensors = EXAMPLES / "associate_measurements.csv", EXAMPLES / "associate_sensors.csv"
    args = ["associate", str(meas), "--sensors", str(sensors), "--out", str(out), "--method", "lagrangian"]
    assert cli_main(args) == 0
    rows = read_rows(out / "associate_measurements.associate.csv")
    table = read_rows(meas)
    assert rows["row"].tolist() == list(range(len(table["sensor"])))
    assert np.array_equal(rows["scan"], np.unique(table["time"], return_inverse=True)[1])
    summary = json.loads((out / "associate_measurements.associate.json").read_text())
    assert summary["scans"] == 3 and len(summary["targets"]) >= 10
    for target in summary["targets"]:
        assert sorted(target["rows"]) == np.flatnonzero(rows["target"] == target["target"]).tolist()
        assert np.all(rows["scan"][target["rows"]] == target["scan"])


def test_associate_by_an_attribute_column_and_a_wrong_one(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    meas = tmp_path / "meas.csv"
    text = (EXAMPLES / "associate_measurements.csv").read_text().splitlines()
    # A scan number column, and every time distinct: grouping by it gives the three scans back.
    lines = [text[0] + ",scan_no"] + [
        f"{line.split(',', 2)[0]},{k},{line.split(',', 2)[2]},{int(float(line.split(',')[1]) // 10)}"
        for k, line in enumerate(text[1:])
    ]
    meas.write_text("\n".join(lines) + "\n")
    sensors = str(EXAMPLES / "associate_sensors.csv")
    out = tmp_path / "out"
    assert cli_main(["associate", str(meas), "--sensors", sensors, "--out", str(out), "--scan-column", "scan_no"]) == 0
    assert json.loads((out / "meas.associate.json").read_text())["scans"] == 3
    with pytest.raises(SystemExit) as stop:
        cli_main(["associate", str(meas), "--sensors", sensors, "--out", str(out), "--scan-column", "nope"])
    assert (
        stop.value.code == 2 and "--scan-column: 'nope' is not 'time' or an attribute column" in capsys.readouterr().err
    )


@pytest.mark.parametrize(
    "measurements,message",
    [
        ("sensor,azimuth\n0,0.5\n", "missing required column 'time'"),
        ("sensor,time,azimuth\n0,0.0,0.5\n5,0.0,0.5\n", "sensor[1] = 5 (row 1) is not a sensor of the network"),
        ("sensor,time,azimuth\n0,0.0,abc\n", "azimuth: line 2 has 'abc', not a number (file"),
        ("", "is empty"),
        ("sensor,time,azimuth\n0,0.0,nan\n", "azimuth"),
    ],
)
def test_bad_files_are_usage_errors_and_write_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], measurements: str, message: str
) -> None:
    meas = tmp_path / "bad.csv"
    meas.write_text(measurements)
    out = tmp_path / "never"
    sensors = str(EXAMPLES / "associate_sensors.csv")
    for command in ("initiate", "associate"):
        with pytest.raises(SystemExit) as stop:
            cli_main([command, str(meas), "--sensors", sensors, "--out", str(out)])
        assert stop.value.code == 2
        assert message in capsys.readouterr().err
        assert not out.exists(), "a failed run created its output folder"


def test_an_existing_output_is_replaced_whole_or_not_at_all(tmp_path: Path) -> None:
    out = tmp_path / "out"
    meas, sensors = EXAMPLES / "associate_measurements.csv", str(EXAMPLES / "associate_sensors.csv")
    assert cli_main(["associate", str(meas), "--sensors", sensors, "--out", str(out)]) == 0
    before = (out / "associate_measurements.associate.csv").read_bytes()
    broken = tmp_path / "broken.csv"
    shutil.copy(meas, broken)
    broken.write_text(broken.read_text() + "0,0.0\n")  # a short last line
    with pytest.raises(SystemExit):
        cli_main(
            ["associate", str(broken), "--sensors", sensors, "--out", str(out), "--prefix", "associate_measurements"]
        )
    assert (out / "associate_measurements.associate.csv").read_bytes() == before
    assert not [p for p in out.iterdir() if p.name.startswith(".")], "a temporary file was left behind"


def test_locate_writes_every_row_once(tmp_path: Path) -> None:
    out = tmp_path / "out"
    meas, sensors = EXAMPLES / "locate_measurements.csv", EXAMPLES / "locate_sensors.csv"
    args = ["locate", str(meas), "--sensors", str(sensors), "--out", str(out), "--attributes", "rf", "prf", "pw", "asp"]
    assert cli_main(args) == 0
    rows = read_rows(out / "locate_measurements.locate.csv")
    assert rows["row"].tolist() == list(range(len(read_rows(meas)["sensor"])))
    summary = json.loads((out / "locate_measurements.locate.json").read_text())
    assert sum(g["associated"] for g in summary["groups"]) == 6
    for group in summary["groups"]:
        assert sorted(group["rows"]) == np.flatnonzero(rows["group"] == group["group"]).tolist()
    with pytest.raises(SystemExit) as stop:
        cli_main([*args[:-4], "--reference", "abc"])
    assert stop.value.code == 2


@pytest.mark.parametrize(
    "method,local,system,extra",
    [
        ("topology", "topology_local.csv", "topology_system.csv", []),
        ("wavelet", "wavelet_esm.csv", "wavelet_radar.csv", ["--process-noise", "169"]),
    ],
)
def test_associate_tracks_writes_every_local_row_once(
    tmp_path: Path, method: str, local: str, system: str, extra: list[str]
) -> None:
    out = tmp_path / "out"
    args = ["associate-tracks", str(EXAMPLES / local), "--system", str(EXAMPLES / system), "--method", method]
    assert cli_main([*args, "--out", str(out), *extra]) == 0
    stem = Path(local).stem
    rows = read_rows(out / f"{stem}.associate-tracks.csv")
    assert rows["row"].tolist() == list(range(len(read_rows(EXAMPLES / local)["time"])))
    pairs = json.loads((out / f"{stem}.associate-tracks.json").read_text())["pairs"]
    assert len(pairs) == int(np.sum(rows["system_track"] >= 0)) > 0


def test_associate_tracks_refuses_another_methods_parameter(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    args = ["associate-tracks", str(EXAMPLES / "wavelet_esm.csv"), "--system", str(EXAMPLES / "wavelet_radar.csv")]
    with pytest.raises(SystemExit) as stop:
        cli_main([*args, "--method", "topology", "--tau", "0.5", "--out", str(tmp_path / "o")])
    assert stop.value.code == 2 and "--method topology does not take --tau" in capsys.readouterr().err


def test_outputs_are_named_after_the_input_so_runs_do_not_collide(tmp_path: Path) -> None:
    """The README's two associate-tracks runs into one folder keep both results, and a run
    into its input's own folder leaves the input as it was."""
    out = tmp_path / "out"
    for local, system, extra in (
        ("topology_local.csv", "topology_system.csv", ["--method", "topology"]),
        ("wavelet_esm.csv", "wavelet_radar.csv", ["--method", "wavelet", "--process-noise", "169"]),
    ):
        args = ["associate-tracks", str(EXAMPLES / local), "--system", str(EXAMPLES / system), "--out", str(out)]
        assert cli_main([*args, *extra]) == 0
    assert sorted(p.name for p in out.iterdir()) == [
        "topology_local.associate-tracks.csv",
        "topology_local.associate-tracks.json",
        "wavelet_esm.associate-tracks.csv",
        "wavelet_esm.associate-tracks.json",
    ]
    meas = tmp_path / "x.csv"
    shutil.copy(EXAMPLES / "associate_measurements.csv", meas)
    before = meas.read_bytes()
    sensors = str(EXAMPLES / "associate_sensors.csv")
    assert cli_main(["associate", str(meas), "--sensors", sensors, "--out", str(tmp_path)]) == 0
    assert meas.read_bytes() == before and (tmp_path / "x.associate.csv").exists()


@pytest.mark.parametrize(
    "extra,message",
    [
        (["--prefix", "x"], "--out/--prefix: the output '{out}/x.associate.csv' would overwrite the input file MEAS"),
        (
            ["--prefix", "s"],
            "--out/--prefix: the output '{out}/s.associate.json' would overwrite the input file SENS",
        ),
        (["--plot", "{out}/s.png"], "--plot: the output '{out}/s.png' would overwrite the input file SENS"),
        # (--plot onto MEAS itself, a .csv, is refused earlier: no figure format; tests/test_cli.py)
    ],
)
def test_an_output_that_would_overwrite_an_input_is_refused_before_any_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: list[str], message: str
) -> None:
    """Exit status 2, a message naming the option and the input, and nothing written; the
    input reached through a symbolic link counts as the input."""
    meas, sensors = tmp_path / "x.associate.csv", tmp_path / "sensors.csv"
    shutil.copy(EXAMPLES / "associate_measurements.csv", meas)
    shutil.copy(EXAMPLES / "associate_sensors.csv", sensors)
    (tmp_path / "s.associate.json").symlink_to(sensors)
    (tmp_path / "s.png").symlink_to(sensors)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    argv = ["associate", str(meas), "--sensors", str(sensors), "--out", str(tmp_path)]
    with pytest.raises(SystemExit) as stop:
        cli_main([*argv, *(e.format(out=tmp_path) for e in extra)])
    assert stop.value.code == 2
    assert message.format(out=tmp_path) in capsys.readouterr().err
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


@pytest.mark.skipif(os.name != "posix", reason="file modes and the umask are POSIX")
@pytest.mark.parametrize("umask", [0o022, 0o027, 0o077, 0o002])
def test_outputs_get_the_mode_the_umask_gives_a_new_file(tmp_path: Path, umask: int) -> None:
    """Written through a temporary file and a rename, the outputs still get 0666 less the
    umask, as open() gives a new file (not the temporary file's 0600 whatever the umask)."""
    meas, sensors = EXAMPLES / "associate_measurements.csv", str(EXAMPLES / "associate_sensors.csv")
    previous = os.umask(umask)
    try:
        assert cli_main(["associate", str(meas), "--sensors", sensors, "--out", str(tmp_path / "out")]) == 0
        (tmp_path / "plain").write_text("")  # what a plain open() gives, for comparison
    finally:
        os.umask(previous)
    outputs = sorted((tmp_path / "out").iterdir())
    assert [p.name for p in outputs] == [
        "associate_measurements.associate.csv",
        "associate_measurements.associate.json",
    ]
    plain = stat.S_IMODE((tmp_path / "plain").stat().st_mode)
    assert plain == 0o666 & ~umask
    assert [stat.S_IMODE(p.stat().st_mode) for p in outputs] == [plain, plain]


def test_degrees_read_as_radians_are_an_error_said_once_as_the_option(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Bearings in degrees read as radians found nothing with exit 0: now the run stops (exit
    2) before any work, saying once which option fixes it; --no-angle-check keeps them."""
    sensors, meas = tmp_path / "s.csv", tmp_path / "m.csv"
    sensors.write_text("sensor,x,y,sigma_azimuth_deg\n0,-20000,0,0.3\n1,20000,0,0.3\n2,0,-25000,0.3\n")
    meas.write_text("sensor,time,azimuth\n0,0,45\n1,0,135\n2,0,90\n")
    argv = ["associate", str(meas), "--sensors", str(sensors), "--out", str(tmp_path / "out")]
    with pytest.raises(SystemExit) as stop:
        cli_main(argv)
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.count("beyond ±2π radians") == 1 and "add --angle-unit deg" in err and str(meas) in err
    assert not (tmp_path / "out").exists()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert cli_main([*argv, "--angle-unit", "deg"]) == 0
        assert json.loads((tmp_path / "out" / "m.associate.json").read_text())["targets"][0]["rows"] == [0, 1, 2]
        assert cli_main([*argv, "--degrees"]) == 0
        assert json.loads((tmp_path / "out" / "m.associate.json").read_text())["targets"][0]["rows"] == [0, 1, 2]
    assert cli_main([*argv, "--no-angle-check"]) == 0  # kept as radians: the user's call
