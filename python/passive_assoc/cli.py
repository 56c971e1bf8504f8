"""The ``passive-assoc`` command line.

``passive-assoc demo`` simulates the paper-000 scenario and prints, per target, the ML
estimate with perfect association beside the truth and the CRLB; ``initiate``,
``associate``, ``locate`` and ``associate-tracks`` run a method on the user's own files;
``reproduce`` runs a paper's experiment. ``passive-assoc --help`` lists every command. A
command's modules are imported only when it runs (or its help is asked for), so that the
top-level help answers at once.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import os
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

from . import __version__

#: (name, module with add_arguments/main, one-line summary, example) of every `reproduce`
#: experiment. Modules are imported only for the command being run (or for the whole parser),
#: so that ``passive-assoc --help`` answers at once.
_EXPERIMENTS = [
    (
        "fti",
        "fti",
        "paper 000: fuzzy track initiation, Tables 2-3 (RMS vs perfect association vs CRLB), and a verdict",
        "passive-assoc reproduce fti --runs 100 --plot fti.png --json fti.json",
    ),
    (
        "intensity",
        "intensity",
        "paper 001: static LOS association, Tables 1-2 (time and accuracy of every method)",
        "passive-assoc reproduce intensity --runs 50 --no-timing",
    ),
    (
        "topology",
        "topology",
        "paper 002: track-to-track association under azimuth bias (P, R, F1 vs nearest neighbour)",
        "passive-assoc reproduce topology --runs 20 --bias 0 3 --json topology.json",
    ),
    (
        "wavelet",
        "wavelet",
        "paper 003: radar/ESM association of maneuvering targets (P(correct) per scan, 3 methods)",
        "passive-assoc reproduce wavelet --runs 200 --clutter 0 2",
    ),
    (
        "formation",
        "formation",
        "paper 004: formation targets with emitter attributes, Tables 2-3 and the §2 methods",
        "passive-assoc reproduce formation --runs 200 --noise paper --plot formation.png",
    ),
]

#: (name, module with add_arguments/main, one-line summary) of the commands on the user's files.
_FILE_COMMANDS = [
    ("initiate", "initiate", "initiate tracks from your sensors' measurement file (fuzzy track initiation)"),
    ("associate", "associate", "associate your measurement file scan by scan (static LOS association)"),
    ("locate", "locate", "locate formation targets in your snapshot of bearings (baseline method, attributes)"),
    (
        "associate-tracks",
        "associate_tracks",
        "associate your track files (reference topology, or radar/ESM wavelets)",
    ),
    ("track", "track", "initiate tracks, then carry them on with an EKF tracker (Stone Soup's, or built in)"),
]

#: Optional extras a run needs: (what needs it, whether these arguments need it, the modules,
#: the extra that installs them). Checked once the arguments are parsed, before any work.
_EXTRAS: list[tuple[str, Callable[[argparse.Namespace], bool], tuple[str, ...], str]] = [
    ("--plot", lambda a: getattr(a, "plot", None) is not None, ("matplotlib",), "plot"),
    ("--scheduler", lambda a: getattr(a, "scheduler", None) is not None, ("dask", "distributed"), "dask"),
    (
        "--tracker stonesoup",
        lambda a: getattr(a, "command_name", None) == "track" and getattr(a, "tracker", None) == "stonesoup",
        ("stonesoup",),
        "stonesoup",
    ),
    (
        "a .parquet MEAS file",
        lambda a: str(getattr(a, "measurements", "")).endswith(".parquet"),
        ("pyarrow",),
        "parquet",
    ),
]

EPILOG = """examples:
  passive-assoc demo
  passive-assoc associate examples/associate_measurements.csv --sensors examples/associate_sensors.csv --out out/
  passive-assoc reproduce fti --runs 20

'passive-assoc COMMAND --help' describes a command, its input files, its outputs and examples.

exit status: 0 done; 1 an error while running (e.g. a file that cannot be read or written);
2 a usage error (a bad option, input file or setting, a missing optional extra, an output
that would overwrite an input), reported before any output is written; 130 interrupted
(Ctrl-C); 141 standard output closed early (e.g. piped into head).
"""


class HelpFormatter(argparse.HelpFormatter):
    """Wraps a one-paragraph description to the terminal; keeps text that has its own line
    breaks (the epilogs' file formats, outputs and examples) as written."""

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        if "\n" in text.strip():
            return "".join(indent + line for line in text.splitlines(keepends=True))
        return super()._fill_text(text, width, indent)


_COMPONENTS = ("x0 m", "y0 m", "z0 m", "vx m/s", "vy m/s", "vz m/s")


def _demo(args: argparse.Namespace) -> int:
    import numpy as np

    from .evaluation import perfect_association_fit, target_crlbs
    from .simulation import paper_fti_scenario

    scenario = paper_fti_scenario(seed=args.seed)
    fit = perfect_association_fit(scenario)
    bounds = np.sqrt(np.diagonal(target_crlbs(scenario), axis1=1, axis2=2))
    truth = scenario.measurements.truth
    assert truth is not None  # a simulated table always carries truth
    n_clutter = int(np.sum(truth < 0))
    print(
        f"paper-000 scenario (seed {args.seed}): 2 sensors, 4 targets, {len(scenario.measurements)} measurements "
        f"({n_clutter} clutter), T = 15 s, 8 scans, sigma = 5 mrad"
    )
    print("ML fit of X0 with perfect association; CRLB std = best achievable RMS of an unbiased estimator\n")
    header = f"{'target':>6} {'':>9}" + "".join(f"{c:>11}" for c in _COMPONENTS)
    print(header)
    for k in range(len(scenario.targets)):
        rows = (
            ("truth", scenario.true_states[k]),
            ("estimate", fit.estimates[k]),
            ("error", fit.estimates[k] - scenario.true_states[k]),
            ("CRLB std", bounds[k]),
        )
        for j, (label, values) in enumerate(rows):
            name = str(k + 1) if j == 0 else ""
            print(f"{name:>6} {label:>9}" + "".join(f"{v:11.2f}" for v in values))
        print(
            f"{'':>6} {'status':>9} {fit.termination_names()[k]}, {int(fit.iterations[k])} iterations, "
            f"chi2 = {fit.chi2[k]:.1f} for {2 * len(scenario.true_groups()[k])} angles"
        )
    return 0


def build_parser(only: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The whole command line; with ``only`` (a command, and for ``reproduce`` an experiment,
    as :func:`_requested` reads them off argv) the other commands are listed but carry no
    options, so that their modules are not imported."""

    def wanted(*path: str) -> bool:
        return only is None or tuple(only[: len(path)]) == path

    parser = argparse.ArgumentParser(
        prog="passive-assoc",
        description="Data association and track initiation for passive (angle-only) sensor networks.",
        epilog=EPILOG,
        formatter_class=HelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"passive-assoc {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    demo = commands.add_parser(
        "demo",
        help="fit the paper-000 scenario's targets with perfect association and compare with the CRLB",
        description="Simulate the fuzzy-track-initiation paper's scenario (METHODS §1) and print, per "
        "target, the Gauss-Newton ML estimate of X0 from its true measurements, the truth and the CRLB.",
        epilog="example:\n  passive-assoc demo --seed 3",
        formatter_class=HelpFormatter,
    )
    if wanted("demo"):
        from .experiments.common import seed_int

        demo.add_argument("--seed", type=seed_int, default=0, help="simulation seed (default 0)")
        demo.set_defaults(run=_demo)
    for name, module_name, summary in _FILE_COMMANDS:
        sub = commands.add_parser(name, help=summary)
        if wanted(name):
            module = _module("commands", module_name)
            module.add_arguments(sub)
            sub.formatter_class = HelpFormatter  # its description wrapped, its epilog as written
            sub.set_defaults(run=module.main)
    _add_reproduce(commands, wanted)
    return parser


def _module(package: str, name: str) -> ModuleType:
    return importlib.import_module(f".{package}.{name}", __package__)


def _requested(argv: Sequence[str]) -> list[str]:
    """The command (and ``reproduce``'s experiment) that argv names: its words before the
    first option of the command itself (the top level and ``reproduce`` take only flags)."""
    words = [a for a in argv if not a.startswith("-")]
    return words[:2] if words[:1] == ["reproduce"] else words[:1]


def _add_reproduce(commands: argparse._SubParsersAction[argparse.ArgumentParser], wanted: Callable[..., bool]) -> None:
    reproduce = commands.add_parser(
        "reproduce",
        help="run a paper's experiment and print our figures beside the paper's",
        description="Reproduce a paper's experiment (docs/spec/EXPERIMENTS.md) with fixed seeds.",
        epilog="examples:\n" + "".join(f"  {example}\n" for *_, example in _EXPERIMENTS),
        formatter_class=HelpFormatter,
    )
    experiments = reproduce.add_subparsers(dest="experiment", metavar="EXPERIMENT", required=True)
    for name, module_name, summary, example in _EXPERIMENTS:
        sub = experiments.add_parser(
            name, help=summary, description=summary, epilog=f"example:\n  {example}", formatter_class=HelpFormatter
        )
        if not wanted("reproduce", name):
            continue
        from .experiments.common import scheduler_address

        module = _module("experiments", module_name)
        module.add_arguments(sub)
        sub.add_argument(
            "--scheduler",
            metavar="ADDRESS",
            type=scheduler_address,
            help="run the Monte-Carlo runs on a Dask cluster: its scheduler address, or 'local' for a "
            "local cluster of processes (pip install '.[dask]'); same results as without",
        )
        sub.set_defaults(run=_on_scheduler(module.main))


def _on_scheduler(run: Callable[[argparse.Namespace], int]) -> Callable[[argparse.Namespace], int]:
    """``run``, with its runs on the Dask cluster of ``--scheduler`` when one is given."""

    def wrapped(args: argparse.Namespace) -> int:
        if getattr(args, "scheduler", None) is None:
            return run(args)
        from .distributed import client_for, using

        with client_for(args.scheduler) as client, using(client):
            return run(args)

    return wrapped


def main(argv: Sequence[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(_requested(argv))
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    missing = missing_extra(args) or figure_format_error(args)
    if missing:
        parser.exit(2, f"passive-assoc: error: {missing}\n")
    original_format = warnings.formatwarning
    warnings.formatwarning = _one_line_warning
    try:
        with warnings.catch_warnings():  # warning filters a command sets end with it
            status = int(args.run(args))
        sys.stdout.flush()  # here, so that a closed pipe is reported below, not at exit
        return status
    except ValueError as err:  # a setting the library refused: a usage error, not a traceback
        parser.exit(2, f"passive-assoc: error: {err}\n")
    except KeyboardInterrupt:
        print("passive-assoc: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader of standard output went away (| head): stop quietly
        _silence_stdout()
        return 141  # as a program killed by SIGPIPE
    except OSError as err:  # a file that cannot be read or written: the system's reason, no traceback
        parser.exit(1, f"passive-assoc: error: {err}\n")
    finally:
        warnings.formatwarning = original_format


def missing_extra(args: argparse.Namespace) -> str | None:
    """A one-line error if the arguments need an optional extra that is not installed."""
    for what, needs, modules, extra in _EXTRAS:
        if needs(args):
            absent = [m for m in modules if importlib.util.find_spec(m) is None]
            if absent:
                return (
                    f"{what} needs {' and '.join(absent)} (the '{extra}' extra), which is not installed: "
                    f"pip install '.[{extra}]' in the passive-assoc checkout"
                )
    return None


def figure_format_error(args: argparse.Namespace) -> str | None:
    """A one-line error if ``--plot`` names a file whose suffix is no format matplotlib
    writes (or none: matplotlib would then add ".png" to the temporary file's name)."""
    plot = getattr(args, "plot", None)
    if plot is None:
        return None
    from matplotlib.backend_bases import FigureCanvasBase

    formats = sorted(FigureCanvasBase.get_supported_filetypes())
    if Path(plot).suffix.lower().lstrip(".") in formats:
        return None
    return f"--plot: {str(plot)!r} needs a figure format as its extension: .{', .'.join(formats)}"


def _one_line_warning(message: Warning | str, category: type[Warning], *_: Any, **__: Any) -> str:
    """A library warning as the command line shows it: one line, no source location."""
    return f"passive-assoc: warning: {message}\n"


def _silence_stdout() -> None:
    """Point standard output at /dev/null, so that the interpreter's final flush does not
    raise BrokenPipeError again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # no real file descriptor (e.g. captured in tests)
        pass


if __name__ == "__main__":
    sys.exit(main())
