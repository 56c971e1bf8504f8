"""``passive-assoc locate MEAS --sensors SENS``: formation targets from one snapshot of 2-D
bearings of three or more sensors (METHODS §3: the modified baseline least-distance method,
with emitter attributes when the file has them).

Writes, in ``--out`` (``<prefix>``: MEAS's file name without its extension, or ``--prefix``):

* ``<prefix>.locate.csv`` — every input row once: row, sensor, time, azimuth and
  ``group`` (the baseline report whose target it was assigned to, or −1: clutter);
* ``<prefix>.locate.json`` — per baseline report: whether it was associated, its rows, the ML
  position and covariance, the cluster radius and the attribute supports.
"""

from __future__ import annotations

import argparse
import dataclasses
from typing import Any

import numpy as np

from .._params import field_defaults
from ..formation import FormationLocator, FormationResult
from .associate import column_name
from .common import (
    EXAMPLE_FORMATS,
    add_file_arguments,
    add_parameter_options,
    given_parameters,
    outputs_epilog,
    parameter_docs,
    plan_outputs,
    read_inputs,
    row_columns,
    with_geodetic,
    write_outputs,
)

__all__ = ["add_arguments", "main"]

DESCRIPTION = (
    "Locate formation targets from one snapshot of 2-D bearings of three or more sensors, "
    "associating them with emitter attributes when the file has attribute columns (METHODS §3). "
    "Every measurement ends in one target's group or in the clutter set."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.description = DESCRIPTION
    parser.epilog = (
        EXAMPLE_FORMATS
        + "attribute columns (e.g. rf, pw) are used by name with --attributes rf pw; a per-report\n"
        + "std column is named <name>_std.\n\n"
        + outputs_epilog(
            "locate",
            "MEAS",
            "every input row once, with its group (-1: clutter)",
            "per baseline report: associated, rows, position, covariance, radius, support",
        )
        + "\nexample:\n  passive-assoc locate examples/locate_measurements.csv --sensors examples/locate_sensors.csv "
        + "--attributes rf prf pw asp --out out/"
    )
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    add_file_arguments(parser, "locate")
    parser.add_argument(
        "--attributes",
        nargs="*",
        type=column_name,
        metavar="NAME",
        help="attribute columns to gate on (default: the library's)",
    )
    names = add_parameter_options(
        parser, FormationLocator._constraints, field_defaults(FormationLocator), docs=parameter_docs(FormationLocator)
    )
    parser.set_defaults(parameter_names=names)


def main(args: argparse.Namespace) -> int:
    files = plan_outputs(args, {"MEAS": args.measurements, "SENS": args.sensors})
    table, sensors = read_inputs(args)
    parameters = given_parameters(args, args.parameter_names)
    if args.attributes is not None:
        parameters["attributes"] = args.attributes
    result = FormationLocator(**parameters).locate(table, sensors)
    located, clutter = int(np.sum(result.associated)), len(result.clutter)
    write_outputs(
        args,
        files,
        row_columns(table, result.labels, label_name="group"),
        with_geodetic(target_summary(result), "groups", sensors, np.nan_to_num(result.positions)),
        f"{located} of {len(result.baseline_rows)} baseline reports located, {clutter} of {len(table)} "
        "measurements clutter",
    )
    return 0


def target_summary(result: FormationResult) -> dict[str, Any]:
    return {
        "groups": [
            {
                "group": b,
                "baseline_row": result.baseline_rows[b],
                "associated": result.associated[b],
                "rows": result.rows[b][result.rows[b] >= 0],
                "position": result.positions[b],
                "covariance": result.covariances[b],
                "radius": result.radius[b],
                "support": result.support[b],
            }
            for b in range(len(result.baseline_rows))
        ],
        "termination": result.termination,
        "success": result.success,
        "message": result.message,
        "diagnostics": dataclasses.asdict(result.diagnostics),
    }
