"""What the file commands (``passive-assoc initiate``, ``associate``, ``locate``,
``associate-tracks``) share: reading the user's files, the method's parameters as options
(from the class's declared constraints, so every parameter has an option with the library's
default), and the outputs: named after the input file (``<prefix>.<command>.csv`` and
``.json`` in ``--out``), refused before any work when one would overwrite an input, and
written so that nothing is half-written.
"""

from __future__ import annotations

import argparse
import inspect
import json
import math
import os
import re
import sys
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from .._params import Boolean, Constraint, Interval, Options
from ..data import MeasurementTable, SensorNetwork, SensorTrack
from ..data._io import write_atomically, write_csv
from ..data.angles import AngleUnit
from ..experiments.common import _jsonable

__all__ = [
    "add_file_arguments",
    "add_output_arguments",
    "check_outputs",
    "outputs_epilog",
    "parameter_docs",
    "plan_outputs",
    "add_parameter_options",
    "output_path",
    "given_parameters",
    "prefix_name",
    "prepare",
    "read_inputs",
    "row_columns",
    "write_atomically",
    "write_json",
    "write_outputs",
    "with_geodetic",
]

EXAMPLE_FORMATS = """input files (CSV with a header row; spaces around names are fine):
  sensors: one row per sensor
    sensor,x,y,sigma_azimuth_deg            (2-D; add z and sigma_elevation[_deg] in 3-D)
    0,-20000,0,0.3
  measurements: one row per report
    sensor,time,azimuth                     (add elevation in 3-D; other numeric columns
    0,0.0,45.0                               are kept as attributes)
angles are counter-clockwise from +x (east), elevation up, radians, unless declared otherwise
(--angle-unit deg, --azimuth-convention compass). Header aliases are read: sensor_id, t or
timestamp (seconds or ISO 8601), bearing, sigma_bearing / sigma_az (per-report noise).
"""


def add_file_arguments(parser: argparse.ArgumentParser, command: str) -> None:
    parser.add_argument(
        "measurements", metavar="MEAS", type=input_file, help="measurements CSV file (or .parquet, with pyarrow)"
    )
    parser.add_argument("--sensors", metavar="SENS", type=input_file, required=True, help="sensors CSV file")
    angles = parser.add_argument_group("angle convention of MEAS (declared once, for every angle column)")
    angles.add_argument(
        "--angle-unit",
        choices=("rad", "deg"),
        default="rad",
        help="unit of azimuth, elevation and the sigma_* columns (default rad)",
    )
    angles.add_argument("--degrees", action="store_true", help="the same as --angle-unit deg")
    angles.add_argument(
        "--azimuth-convention",
        choices=("math", "compass"),
        default="math",
        help="math: counter-clockwise from east (default); compass: bearing clockwise from north",
    )
    parser.add_argument(
        "--platforms",
        metavar="FILE",
        type=input_file,
        help="moving sensors: fixes sensor,time,x,y[,z] (or lat,lon[,alt]) interpolated at the report times",
    )
    angles.add_argument(
        "--no-angle-check",
        action="store_true",
        help="keep radian angles beyond ±2π (±π/2 elevation) instead of refusing them as degrees",
    )
    add_output_arguments(parser, command, "MEAS")


def add_output_arguments(parser: argparse.ArgumentParser, command: str, source: str) -> None:
    """``--out``, ``--prefix`` and ``--json`` of a file command whose outputs are named after
    its ``source`` argument (see :func:`plan_outputs`)."""
    parser.add_argument(
        "--out",
        metavar="DIR",
        type=output_folder,
        default=".",
        help="folder for the output files (created if missing; default: .)",
    )
    parser.add_argument(
        "--prefix",
        metavar="NAME",
        type=prefix_name,
        help=f"name the outputs NAME.{command}.csv and NAME.{command}.json "
        f"(default: {source}'s file name without its extension)",
    )
    parser.add_argument(
        "--json",
        action="store_true",
        help="print the JSON summary on standard output (the one-line report then goes to standard error)",
    )
    parser.set_defaults(command_name=command, output_source=source)


def outputs_epilog(command: str, source: str, rows: str, summary: str) -> str:
    """The help's account of the two outputs: ``rows`` says what the CSV holds, ``summary``
    what the JSON file holds."""
    return (
        "outputs, in --out (default .):\n"
        f"  <prefix>.{command}.csv   {rows}\n"
        f"  <prefix>.{command}.json  {summary}\n"
        f"  <prefix> is {source}'s file name without its extension, or --prefix. A run that would\n"
        "  overwrite one of its own input files is refused before any work; an earlier output of\n"
        "  the same name is replaced (whole, or not at all if the run fails).\n"
    )


def prefix_name(text: str) -> str:
    """argparse type: the outputs' name prefix, a plain file name (no folder: that is ``--out``)."""
    name = text.strip()
    if not name or name in (".", "..") or "/" in name or os.sep in name:
        raise argparse.ArgumentTypeError(f"expected a file name without a folder (--out sets the folder), got {text!r}")
    return name


prefix_name.bad_values = ["", "a/b", ".."]  # type: ignore[attr-defined]


def plan_outputs(args: argparse.Namespace, inputs: Mapping[str, str]) -> tuple[Path, Path]:
    """The command's two output files, ``<out>/<prefix>.<command>.csv`` and ``.json``, the
    prefix being ``--prefix`` or the stem of the source input (``args.output_source``'s file).
    Raises ValueError, before any work, when an output (these two or ``--plot``) would
    overwrite a file of ``inputs`` (argument name → path) or two outputs are one file."""
    source = inputs[args.output_source]
    prefix = args.prefix or Path(source).stem
    files = args.out / f"{prefix}.{args.command_name}.csv", args.out / f"{prefix}.{args.command_name}.json"
    outputs = [("--out/--prefix", files[0]), ("--out/--prefix", files[1])]
    if getattr(args, "plot", None) is not None:
        outputs.append(("--plot", args.plot))
    check_outputs(inputs, outputs)
    return files


def check_outputs(inputs: Mapping[str, str], outputs: Sequence[tuple[str, Path]]) -> None:
    """ValueError if an output is one of the input files (the same file, through any link) or
    two outputs are one file; ``outputs`` are (the option that chose it, path) pairs."""
    seen: dict[str, str] = {}
    for option, path in outputs:
        for name, given in inputs.items():
            if path.exists() and os.path.samefile(path, given):
                raise ValueError(
                    f"{option}: the output {str(path)!r} would overwrite the input file {name} ({given!r}); "
                    f"choose another {option}"
                )
        key = os.path.realpath(path)
        if key in seen:
            raise ValueError(f"{option}: the output {str(path)!r} is also the output of {seen[key]}")
        seen[key] = option


def input_file(text: str) -> str:
    """argparse type: an existing file."""
    if not text.strip() or not Path(text).expanduser().is_file():
        raise argparse.ArgumentTypeError(f"no such file: {text!r}")
    return text


input_file.bad_values = ["", "/nonexistent-directory/in.csv"]  # type: ignore[attr-defined]


def read_inputs(args: argparse.Namespace) -> tuple[MeasurementTable, SensorNetwork]:
    """The sensor and measurement files in the declared angle convention, with the moving
    sensors' positions of ``--platforms``; geodetic files in the sensor file's frame. Angles
    beyond ±2π (±π/2) radians are an error naming the option that fixes it, said once, unless
    ``--no-angle-check``."""
    sensors = SensorNetwork.from_csv(args.sensors)
    unit: AngleUnit = "deg" if args.degrees else args.angle_unit
    read = MeasurementTable.from_parquet if str(args.measurements).endswith(".parquet") else MeasurementTable.from_csv
    table = read(
        args.measurements,
        angle_unit=unit,
        azimuth_convention=args.azimuth_convention,
        check_angle_unit=False,
        frame=sensors.frame,
    )
    if args.platforms is not None:
        table = SensorTrack.from_csv(args.platforms, frame=sensors.frame).attach(table)
    table.validate_against(sensors)
    if unit == "rad" and not args.no_angle_check:
        for name, values, limit, text in (
            ("azimuth", table.azimuth, 2 * math.pi, "±2π"),
            ("elevation", table.elevation, math.pi / 2, "±π/2"),
        ):
            largest = max((abs(float(v)) for v in values if math.isfinite(v)), default=0.0)
            if largest > limit * (1 + 1e-12):
                raise ValueError(
                    f"MEAS {str(args.measurements)!r}: {name} values up to {largest:g} are beyond {text} radians: "
                    "if they are degrees, add --angle-unit deg (to keep them as radians: --no-angle-check)"
                )
    return table, sensors


def with_geodetic(record: dict[str, Any], items: str, sensors: SensorNetwork, positions: Any) -> dict[str, Any]:
    """``record`` with, when the sensor file was geodetic, the frame's origin and each of
    ``record[items]`` given ``"geodetic"``: its position (from ``positions``, one row per
    item, in the local frame) as latitude, longitude (degrees) and altitude (m)."""
    if sensors.frame is None:
        return record
    frame = sensors.frame
    record["frame"] = {"latitude": frame.latitude, "longitude": frame.longitude, "altitude": frame.altitude}
    points: Any = frame.to_geodetic(positions) if len(record[items]) else []
    for item, point in zip(record[items], points, strict=True):
        item["geodetic"] = point
    return record


def output_folder(text: str) -> Path:
    """argparse type: the output folder, or one that can be created (its nearest existing
    ancestor a writable folder) — checked before any work starts; created by :func:`prepare`."""
    if not text.strip():
        raise argparse.ArgumentTypeError("expected a folder name, got an empty string")
    folder = Path(text).expanduser().resolve()
    existing = next(p for p in (folder, *folder.parents) if p.exists())
    if not existing.is_dir() or not os.access(existing, os.W_OK):
        raise argparse.ArgumentTypeError(f"cannot write into {str(existing)!r}")
    return folder


output_folder.bad_values = ["", "/dev/null/out"]  # type: ignore[attr-defined]


def output_path(text: str) -> Path:
    """argparse type: a file to write, whose folder exists or can be created (created when the
    file is written)."""
    if not text.strip() or text.endswith(("/", os.sep)):
        raise argparse.ArgumentTypeError(f"expected a file name, got {text!r}")
    given = Path(text).expanduser()
    return output_folder(str(given.parent)) / given.name  # the name as given, not a link's target


output_path.bad_values = ["", "/dev/null/figure.png", "somewhere/"]  # type: ignore[attr-defined]


def prepare(folder: Path) -> Path:
    """Creates the output folder (after the inputs were read)."""
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def row_columns(table: MeasurementTable, labels: Any, label_name: str = "track", **extra: Any) -> dict[str, Any]:
    """The per-measurement output: every input row once, with its row number, sensor, time,
    angles, any ``extra`` columns, and its label (−1: clutter) as ``label_name``."""
    import numpy as np

    columns: dict[str, Any] = {
        "row": np.arange(len(table), dtype=np.int64),
        "sensor": table.sensor,
        "time": table.time,
        "azimuth": table.azimuth,
    }
    if table.ndim == 3:
        columns["elevation"] = table.elevation
    columns.update(extra)
    columns[label_name] = np.asarray(labels, dtype=np.int64)
    return columns


def write_outputs(
    args: argparse.Namespace,
    files: tuple[Path, Path],
    columns: Mapping[str, Any],
    record: Mapping[str, Any],
    headline: str,
) -> None:
    """Every command's ending: ``--out`` created, the per-row CSV and the JSON summary written
    atomically to ``files`` (from :func:`plan_outputs`), ``headline`` and the two paths
    printed; with ``--json`` the summary is printed on standard output and the headline on
    standard error, so that standard output can be piped into a JSON reader."""
    prepare(args.out)
    csv_path, json_path = files
    write_atomically(csv_path, lambda path: write_csv(path, columns))
    write_json(json_path, record)
    print(f"{headline}; wrote {csv_path} and {json_path}", file=sys.stderr if args.json else sys.stdout)
    if args.json:
        json.dump(_jsonable(record), sys.stdout, indent=2)
        print()


def write_json(path: Path, record: Mapping[str, Any]) -> None:
    text = json.dumps(_jsonable(record), indent=2) + "\n"

    def write(temporary: Path) -> None:
        temporary.write_text(text, encoding="utf-8")

    write_atomically(path, write)


def add_parameter_options(
    parser: argparse.ArgumentParser,
    constraints: Mapping[str, list[Constraint]],
    defaults: Mapping[str, Any],
    title: str = "method parameters",
    docs: Mapping[str, str] | None = None,
) -> list[str]:
    """One ``--name`` option per scalar parameter the class declares (what it is, from
    ``docs``, see :func:`parameter_docs`; the values it takes; its default, unset = the
    library's default); returns the parameter names it covers (an option another method
    already added is shared)."""
    group = parser.add_argument_group(f"{title} (default: the library's)")
    added = []
    for name, allowed in constraints.items():
        kinds = [c for c in allowed if c is not None]
        if not kinds or name == "n_threads":
            continue
        flag = "--" + name.replace("_", "-")
        if flag in parser._option_string_actions:  # the same parameter of another method
            added.append(name)
            continue
        default = defaults.get(name)
        default = "none" if default is None else str(default).lower() if isinstance(default, bool) else default
        about = (docs or {}).get(name, "").replace("%", "%%")  # argparse %-formats help texts
        about = f"{about} " if about else ""
        first = kinds[0]
        intervals = [c for c in kinds if isinstance(c, Interval)]
        if isinstance(first, Options) and intervals:  # a word or a number, e.g. reference
            text = "none" if None in allowed else None
            group.add_argument(
                flag,
                type=_word_or_number(first, intervals[0], text),
                metavar="VALUE",
                help=f"{about}[{first.describe()} or {intervals[0].describe()}{' or none' if text else ''};"
                f" default {default}]",
            )
        elif isinstance(first, Boolean):
            group.add_argument(flag, type=_boolean, metavar="{true,false}", help=f"{about}[default {default}]")
        elif isinstance(first, Options):
            group.add_argument(flag, choices=first.choices, help=f"{about}[default {default}]")
        elif isinstance(first, Interval):
            text = "none" if None in allowed else None
            group.add_argument(
                flag,
                type=_number(first, text),
                metavar="INT" if first.kind is int else "X",
                help=f"{about}[{first.describe()}{' or none' if text else ''}; default {default}]",
            )
        else:
            continue
        added.append(name)
    return added


def parameter_docs(documented: object) -> dict[str, str]:
    """The first sentence of each parameter's entry in the "Parameters" section of the
    (NumPy-style) docstring of ``documented``, a class or function, markup removed: what
    ``--help`` says an option is. Names that share an entry (``rings, sectors : int``) share
    its sentence."""
    lines = (inspect.getdoc(documented) or "").splitlines()
    try:
        start = lines.index("Parameters") + 2
    except ValueError:
        return {}
    entries: dict[tuple[str, ...], list[str]] = {}
    names: tuple[str, ...] = ()
    for k in range(start, len(lines)):
        line = lines[k]
        if k + 1 < len(lines) and set(lines[k + 1]) == {"-"}:  # the next section's title
            break
        if line and not line.startswith(" "):
            names = tuple(n.strip() for n in line.split(" : ")[0].split(","))
            entries[names] = []
        elif names and line.strip():
            entries[names].append(line.strip())
    docs = {}
    for group, text in entries.items():
        prose = re.sub(r":\w+:`~?([^`]*)`", r"\1", " ".join(text)).replace("``", "")
        # A sentence ends at a full stop and a space, or at the end: not "eq. 23", "e.g. the".
        sentence = re.split(r"(?<!\beq)(?<!\be\.g)(?<!\bi\.e)(?<!\bcf)\.(?:\s|$)", prose, maxsplit=1)[0]
        docs.update(dict.fromkeys(group, f"{sentence}." if sentence else ""))
    return docs


def given_parameters(args: argparse.Namespace, names: list[str]) -> dict[str, Any]:
    """The parameters the user set (None = not given; the "none" value is passed as None)."""
    out = {}
    for name in names:
        value = getattr(args, name)
        if value is not None:
            out[name] = None if value is _NONE else value
    return out


_NONE = object()


def _boolean(text: str) -> bool:
    lowered = text.strip().lower()
    if lowered in ("true", "yes", "1"):
        return True
    if lowered in ("false", "no", "0"):
        return False
    raise argparse.ArgumentTypeError(f"expected true or false, got {text!r}")


_boolean.bad_values = ["maybe", "", "2"]  # type: ignore[attr-defined]


def _word_or_number(options: Options, interval: Interval, none_text: str | None = None) -> Callable[[str], Any]:
    """argparse type: one of ``options``' words, or a number ``interval`` accepts (or
    ``none_text`` for None)."""
    number = _number(interval, none_text)

    def parse(text: str) -> Any:
        return text if text in options.choices else number(text)

    parse.__name__ = f"{options.describe()} or {interval.describe()}"
    parse.bad_values = ["", "abc"]  # type: ignore[attr-defined]
    return parse


def _number(interval: Interval, none_text: str | None) -> Callable[[str], Any]:
    """argparse type: a number the interval accepts, or ``none_text`` for None."""

    def parse(text: str) -> Any:
        if none_text is not None and text.strip().lower() == none_text:
            return _NONE
        try:
            value = int(text) if interval.kind is int else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {interval.describe()}, got {text!r}") from None
        if not interval.contains(value):
            raise argparse.ArgumentTypeError(f"expected {interval.describe()}, got {text!r}")
        return value

    parse.__name__ = interval.describe()
    bad = ["abc"] + ([] if interval.low is None else [repr(interval.low - 1)])
    parse.bad_values = bad + (["nan"] if interval.kind is float else ["1.5"])  # type: ignore[attr-defined]
    return parse
