"""``passive-assoc track MEAS --sensors SENS``: track initiation, then a tracker that carries
the tracks on through the whole file.

``--tracker`` chooses the tracker: ``stonesoup`` (the ``stonesoup`` extra), ``builtin``, or
``auto`` (the default: Stone Soup when it is installed, else the built-in one). Both run the
same loop, time by time: a constant-velocity EKF on the angle reports, global-nearest-neighbour
association inside a Mahalanobis gate of ``--missed-distance``, deletion after
``--delete-after`` steps without a report, and the fuzzy track initiation over ``--window``
seconds of unassociated reports for new tracks. Stone Soup's is its ``MultiTargetTracker``
(:func:`passive_assoc.interop.stonesoup_tracking.track_measurements`); the built-in one
(:func:`passive_assoc.tracking.track_measurements`, numpy only) gates each report on its NIS
(χ², at ``missed-distance²``) and pairs each sensor's reports of a time with the tracks
separately. Writes, in ``--out``:

* ``<prefix>.track.csv`` — every input row once: row, sensor, time, angles and ``track`` (the
  track it initiated or updated, or −1);
* ``<prefix>.track.json`` — which tracker ran, and per track its states over time (block
  order ``x, y[, z], vx, vy[, vz]``) with their times, and, for a geodetic sensor file, each
  state's latitude, longitude and altitude.
"""

from __future__ import annotations

import argparse
import importlib.util
from typing import Any

import numpy as np

from ..tracking.defaults import DELETE_AFTER, MISSED_DISTANCE, PROCESS_NOISE, WINDOW
from .common import (
    EXAMPLE_FORMATS,
    add_file_arguments,
    outputs_epilog,
    plan_outputs,
    read_inputs,
    row_columns,
    write_outputs,
)

__all__ = ["add_arguments", "main"]

DESCRIPTION = (
    "Initiate tracks from your passive reports, then carry them on through the whole file with a "
    "constant-velocity EKF tracker: Stone Soup's (the stonesoup extra) or a built-in one (numpy "
    "only). Each time step: the tracks are predicted to it; each sensor's reports at that time are "
    "paired with the tracks by global nearest neighbour inside the gate (a report's Mahalanobis "
    "distance to a track's prediction at most --missed-distance, a chi-square gate on its NIS) and "
    "update them; a track without a report in its last --delete-after steps is deleted; reports no "
    "track took wait, and once the waiting ones span --window seconds the fuzzy track initiation "
    "runs on them and starts new tracks."
)


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {text!r}")
    return value


_positive.bad_values = ["0", "-1", "abc", "nan"]  # type: ignore[attr-defined]


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}")
    return value


_count.bad_values = ["0", "1.5", "x"]  # type: ignore[attr-defined]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.description = DESCRIPTION
    parser.epilog = (
        EXAMPLE_FORMATS
        + "\n"
        + outputs_epilog(
            "track",
            "MEAS",
            "every input row once, with the track it initiated or updated (-1: none)",
            "per track: its states over time (and latitude/longitude for a geodetic sensor file)",
        )
        + "\nexample:\n  passive-assoc track examples/initiate_measurements.csv "
        + "--sensors examples/initiate_sensors.csv --window 40 --out out/"
    )
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    add_file_arguments(parser, "track")
    group = parser.add_argument_group("tracker")
    group.add_argument(
        "--tracker",
        choices=("auto", "stonesoup", "builtin"),
        default="auto",
        help="stonesoup: Stone Soup's MultiTargetTracker (needs the stonesoup extra); builtin: the "
        "package's own EKF, which gates and pairs each sensor's reports of a time separately; auto "
        "(default): stonesoup if it is installed, else builtin",
    )
    group.add_argument(
        "--window", type=_positive, default=WINDOW, help=f"seconds of reports an initiation takes ({WINDOW:g})"
    )
    group.add_argument(
        "--process-noise",
        type=_positive,
        default=PROCESS_NOISE,
        help=f"acceleration noise density, m^2/s^3 per axis ({PROCESS_NOISE:g})",
    )
    group.add_argument(
        "--missed-distance",
        type=_positive,
        default=MISSED_DISTANCE,
        help=f"Mahalanobis association gate ({MISSED_DISTANCE:g})",
    )
    group.add_argument(
        "--delete-after",
        type=_count,
        default=DELETE_AFTER,
        help=f"steps without an update before deletion ({DELETE_AFTER})",
    )


def chosen_tracker(name: str) -> str:
    """``stonesoup`` or ``builtin``: ``auto`` is Stone Soup when it is installed."""
    if name == "auto":
        return "stonesoup" if importlib.util.find_spec("stonesoup") is not None else "builtin"
    return name


def main(args: argparse.Namespace) -> int:
    tracker = chosen_tracker(args.tracker)
    if tracker == "stonesoup":
        from ..interop.stonesoup_tracking import track_measurements
    else:
        from ..tracking import track_measurements

    files = plan_outputs(args, {"MEAS": args.measurements, "SENS": args.sensors})
    table, sensors = read_inputs(args)
    tracks, labels = track_measurements(
        table,
        sensors,
        window=args.window,
        process_noise=args.process_noise,
        missed_distance=args.missed_distance,
        delete_after=args.delete_after,
    )
    summary: list[dict[str, Any]] = []
    for k in np.unique(tracks.track).tolist():
        mine = tracks.track == k
        state = np.column_stack([tracks.position[mine], tracks.velocity[mine]])  # type: ignore[index]
        entry: dict[str, Any] = {"track": k, "times": tracks.time[mine], "states": state}
        if sensors.frame is not None:
            entry["geodetic"] = sensors.frame.to_geodetic(tracks.position[mine])
        summary.append(entry)
    write_outputs(
        args,
        files,
        row_columns(table, labels),
        {"tracker": tracker, "tracks": summary, "window": args.window, "process_noise": args.process_noise},
        f"{tracker} tracker: {len(summary)} track(s) over {len(np.unique(table.time))} time(s); "
        f"{int(np.sum(labels < 0))} of {len(table)} reports in no track",
    )
    return 0
