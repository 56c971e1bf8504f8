"""``passive-assoc initiate MEAS --sensors SENS``: fuzzy track initiation (METHODS §1) on the
user's own files.

Writes, in ``--out`` (``<prefix>``: MEAS's file name without its extension, or ``--prefix``):

* ``<prefix>.initiate.csv`` — every input row once: its row number, sensor, time, angles,
  and ``track`` (the initiated track's index, or −1 for clutter);
* ``<prefix>.initiate.json`` — per track: the initial state at ``t0`` (x, y, [z], vx, vy, [vz]),
  its covariance, the fuzzy closeness, χ² and its rows; and the run's ``t0`` and stage counts.
"""

from __future__ import annotations

import argparse
from typing import Any

from .._params import field_defaults
from ..fti import FuzzyTrackInitiator, InitiationResult
from .common import (
    EXAMPLE_FORMATS,
    add_file_arguments,
    add_parameter_options,
    given_parameters,
    output_path,
    outputs_epilog,
    parameter_docs,
    plan_outputs,
    read_inputs,
    row_columns,
    with_geodetic,
    write_atomically,
    write_outputs,
)

__all__ = ["add_arguments", "main"]

DESCRIPTION = (
    "Initiate tracks from several passive sensors' bearings (and elevations) over a few scans, "
    "with the fuzzy track initiation method (METHODS §1). Every measurement ends in one track or "
    "in the clutter set."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.description = DESCRIPTION
    parser.epilog = (
        EXAMPLE_FORMATS
        + "\n"
        + outputs_epilog(
            "initiate",
            "MEAS",
            "every input row once, with its track (-1: clutter)",
            "per track: initial state at t0, covariance, closeness, chi2, rows",
        )
        + "\nexample:\n  passive-assoc initiate examples/initiate_measurements.csv "
        + "--sensors examples/initiate_sensors.csv --out out/ --plot out/initiate.png"
    )
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    add_file_arguments(parser, "initiate")
    parser.add_argument(
        "--plot", metavar="FILE", type=output_path, help="save a figure of the sensors, lines of sight and tracks"
    )
    names = add_parameter_options(
        parser,
        FuzzyTrackInitiator._constraints,
        field_defaults(FuzzyTrackInitiator),
        docs=parameter_docs(FuzzyTrackInitiator),
    )
    parser.set_defaults(parameter_names=names)


def main(args: argparse.Namespace) -> int:
    files = plan_outputs(args, {"MEAS": args.measurements, "SENS": args.sensors})
    table, sensors = read_inputs(args)
    initiator = FuzzyTrackInitiator(**given_parameters(args, args.parameter_names))
    result = initiator.initiate(table, sensors)
    write_outputs(
        args,
        files,
        row_columns(table, result.labels),
        with_geodetic(track_summary(result), "tracks", sensors, result.states[:, : sensors.ndim]),
        f"{len(result.tracks)} track(s), {len(result.clutter)} of {len(table)} measurements clutter",
    )
    if args.plot:
        from ..plots_data import plot_initiation

        write_atomically(args.plot, lambda p: plot_initiation(table, sensors, result, p))
    return 0


def track_summary(result: InitiationResult) -> dict[str, Any]:
    return {
        "termination": result.termination,
        "success": result.success,
        "message": result.message,
        "t0": result.t0,
        "tracks": [
            {
                "track": k,
                "state": track.state,
                "covariance": track.covariance,
                "closeness": track.closeness,
                "chi2": track.chi2,
                "rows": track.measurements,
            }
            for k, track in enumerate(result.tracks)
        ],
        "clutter_rows": result.clutter,
        "stage_counts": result.diagnostics.stage_counts,
    }
