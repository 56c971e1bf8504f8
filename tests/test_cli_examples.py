"""Every example command runs: the ``passive-assoc ...`` lines of every ``--help`` text (the
whole parser, walked) and of README.md's bash blocks each run to exit status 0, in a
temporary folder holding a copy of ``examples/`` (so that what they write lands there).

The ``reproduce`` examples are shortened, and the test says how: ``--runs 2`` replaces their
``--runs`` (or is appended), wavelet's 2-D demo runs once (``--demo-runs 1``), and intensity's
timing sweep, which does not follow ``--runs``, stops at M = 12 with one scan per row
(``--max-m 12 --timing-scans 1``). Every other example runs as printed.
"""

from __future__ import annotations

import argparse
import re
import shlex
import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest
from passive_assoc.cli import build_parser
from passive_assoc.cli import main as cli_main

ROOT = Path(__file__).resolve().parents[1]

#: What a `reproduce EXPERIMENT` example gets on top of --runs 2 (see the module docstring).
SHORTER = {"wavelet": ["--demo-runs", "1"], "intensity": ["--max-m", "12", "--timing-scans", "1"]}


def _parsers(parser: argparse.ArgumentParser) -> Iterator[argparse.ArgumentParser]:
    yield parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                yield from _parsers(sub)


def help_examples() -> list[str]:
    """Every line of every --help text that gives a command, from ``passive-assoc`` on."""
    found = []
    for parser in _parsers(build_parser()):
        for line in parser.format_help().splitlines():
            if "passive-assoc " in line and not line.lstrip().startswith(("usage:", "passive-assoc: ")):
                command = line[line.index("passive-assoc ") :].strip()
                if not command.startswith("passive-assoc COMMAND"):  # "'passive-assoc COMMAND --help' describes"
                    found.append(command)
    return found


def readme_examples() -> list[str]:
    """The ``passive-assoc ...`` commands of README.md's bash blocks (also after ``&&``)."""
    found = []
    for block in re.findall(r"```bash\n(.*?)```", (ROOT / "README.md").read_text(), re.S):
        for line in block.splitlines():
            if line.lstrip().startswith("#"):
                continue
            for part in re.split(r"&&|;", line):
                if part.strip().startswith("passive-assoc "):
                    found.append(part.strip())
    return found


def shortened(argv: list[str]) -> list[str]:
    """A `reproduce` example with --runs 2 and :data:`SHORTER`'s options; others as given."""
    if argv[:1] != ["reproduce"]:
        return argv
    out = list(argv)
    if "--runs" in out:
        out[out.index("--runs") + 1] = "2"
    else:
        out += ["--runs", "2"]
    return out + SHORTER.get(argv[1], [])


HELP = help_examples()
README = readme_examples()
EXAMPLES = sorted(set(HELP + README))


def test_examples_are_found() -> None:
    """The extraction sees the examples it must (so a broken pattern cannot pass silently)."""
    assert len(HELP) >= 15 and len(README) >= 6
    commands = {shlex.split(line)[1] for line in EXAMPLES}
    assert commands == {"demo", "initiate", "associate", "locate", "associate-tracks", "track", "reproduce"}
    assert {shlex.split(line)[2] for line in EXAMPLES if " reproduce " in f" {line}"} >= {
        "fti",
        "intensity",
        "topology",
        "wavelet",
        "formation",
    }


@pytest.mark.parametrize("line", [pytest.param(line, id=line) for line in EXAMPLES])
def test_example_runs(
    line: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    argv = shortened(shlex.split(line)[1:])
    assert cli_main(argv) == 0, capsys.readouterr().err
