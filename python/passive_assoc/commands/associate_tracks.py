"""``passive-assoc associate-tracks LOCAL --system SYSTEM``: track-to-track association of
the user's track files — by reference topology under azimuth bias (METHODS §4), or radar
against ESM tracks with wavelets and fuzzy factors (METHODS §5), or the nearest-neighbour
baseline.

Both files are :class:`~passive_assoc.TrackTable` CSVs (``TrackTable.to_csv``'s columns:
source, track, time, x, y, [z, vx, …, covariance columns]). Writes, in ``--out``
(``<prefix>``: LOCAL's file name without its extension, or ``--prefix``):

* ``<prefix>.associate-tracks.csv`` — every row of LOCAL once: row, source, track, time and
  ``system_track`` (the system track it was paired with at that time, or −1);
* ``<prefix>.associate-tracks.json`` — the pairs with their scores, and the estimated biases.
"""

from __future__ import annotations

import argparse
import inspect
from typing import Any

import numpy as np

from ..data import TrackTable
from ..track_association import TrackAssociation
from ..track_methods import TRACK_METHODS
from .common import (
    add_output_arguments,
    add_parameter_options,
    given_parameters,
    input_file,
    outputs_epilog,
    parameter_docs,
    plan_outputs,
    write_outputs,
)

__all__ = ["add_arguments", "main"]

DESCRIPTION = (
    "Associate the tracks of local sensors with the system picture, scan by scan: by reference "
    "topology, which azimuth bias does not move (METHODS §4, --method topology); by least "
    "position distance within the tracks' covariance gate (--method nearest: unbiased sensors); "
    "or, radar (SYSTEM) against ESM (LOCAL) tracks or raw reports, by wavelets and fuzzy factors (METHODS §5, "
    "--method wavelet), the weighted chi-square test on the states (--method chi2), or the wavelet gate "
    "then the chi-square test (--method combined)."
)
_METHODS: dict[str, Any] = TRACK_METHODS


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.description = DESCRIPTION
    parser.epilog = (
        "track files: TrackTable CSVs (TrackTable.to_csv), columns source, track, time, x, y[, z],\n"
        "  then velocity, acceleration and covariance columns as the method needs them.\n\n"
        + outputs_epilog(
            "associate-tracks",
            "LOCAL",
            "every LOCAL row once, with the system track it was paired with (-1)",
            "the pairs with their scores, and the estimated biases",
        )
        + "\nexamples:\n  passive-assoc associate-tracks examples/topology_local.csv --system "
        "examples/topology_system.csv --method topology --out out/\n"
        "  passive-assoc associate-tracks examples/wavelet_esm.csv --system examples/wavelet_radar.csv "
        "--method wavelet --out out/"
    )
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("local", metavar="LOCAL", type=input_file, help="local (or ESM) tracks CSV")
    parser.add_argument("--system", metavar="SYSTEM", type=input_file, required=True, help="system tracks CSV")
    parser.add_argument("--method", choices=sorted(_METHODS), default="topology", help="(default topology)")
    add_output_arguments(parser, "associate-tracks", "LOCAL")
    names: list[str] = []
    for method, cls in _METHODS.items():
        defaults = {p.name: p.default for p in inspect.signature(cls).parameters.values()}
        title = f"--method {method} parameters"
        group = add_parameter_options(parser, cls._constraints, defaults, title=title, docs=parameter_docs(cls))
        names += [n for n in group if n not in names]
    parser.set_defaults(parameter_names=names)


def main(args: argparse.Namespace) -> int:
    files = plan_outputs(args, {"LOCAL": args.local, "SYSTEM": args.system})
    local, system = TrackTable.from_csv(args.local, sort=True), TrackTable.from_csv(args.system, sort=True)
    cls = _METHODS[args.method]
    allowed = set(cls._constraints)
    given = given_parameters(args, args.parameter_names)
    unused = sorted(set(given) - allowed)
    if unused:
        raise ValueError(
            f"--method {args.method} does not take {', '.join('--' + u.replace('_', '-') for u in unused)}"
        )
    associator = cls(**given)
    result = associator.associate(local=local, system=system)
    columns = local_rows(local, result)
    paired = int(np.sum(columns["system_track"] >= 0))
    write_outputs(
        args,
        files,
        columns,
        {
            "method": args.method,
            "termination": result.termination,
            "success": result.success,
            "message": result.message,
            "pairs": _pairs(result),
            "bias": _bias(result),
        },
        f"{len(result.pairs)} pairs; {paired} of {len(local)} local track states paired",
    )
    return 0


def local_rows(local: TrackTable, result: TrackAssociation) -> dict[str, Any]:
    """Every local row once, with the system track it was paired with at its time (−1)."""
    p = result.pairs
    paired = {
        (float(t), int(s), int(k)): int(m)
        for t, s, k, m in zip(p.time, p.source, p.local_track, p.system_track, strict=True)
    }
    system_track = np.array(
        [
            paired.get((float(t), int(s), int(k)), -1)
            for t, s, k in zip(local.time, local.source, local.track, strict=True)
        ],
        dtype=np.int64,
    )
    return {
        "row": np.arange(len(local), dtype=np.int64),
        "source": local.source,
        "track": local.track,
        "time": local.time,
        "system_track": system_track,
    }


def _pairs(result: TrackAssociation) -> list[dict[str, Any]]:
    p = result.pairs
    return [
        {
            "time": p.time[i],
            "source": p.source[i],
            "local_track": p.local_track[i],
            "system_track": p.system_track[i],
            "score": p.score[i],
        }
        for i in range(len(p))
    ]


def _bias(result: TrackAssociation) -> dict[str, Any]:
    return {str(source): {"rotation_rad": b.rotation} for source, b in result.bias.items()}
