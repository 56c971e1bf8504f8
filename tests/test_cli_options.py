"""Every option of every command is validated by argparse: a bad value ends in a usage error
naming the option (exit 2), never a traceback or a silently accepted value. The options are
read from the parser itself, so a new option without a validating type fails here."""

from __future__ import annotations

import argparse
from collections.abc import Iterator

import pytest
from passive_assoc._params import field_defaults
from passive_assoc.cli import build_parser
from passive_assoc.experiments.common import finite_float, output_file
from passive_assoc.fti import FuzzyTrackInitiator

#: Values each validating type must refuse (integer types: see :func:`bad_values`).
BAD = {
    finite_float: ["nan", "inf", "-inf", "abc", "1e400"],
    output_file: ["", "/nonexistent-directory/out.json"],
}


def bad_values(kind: object) -> list[str] | None:
    """What an option's type must refuse; None if the type validates nothing."""
    minimum = getattr(kind, "minimum", None)
    if minimum is not None:  # experiments.common.int_at_least
        return [str(minimum - 1), str(minimum - 5), "abc", "1.5", ""]
    declared: list[str] | None = getattr(kind, "bad_values", None)  # the file commands' types
    if declared is not None:
        return declared
    return BAD.get(kind)  # type: ignore[call-overload]


def options() -> Iterator[tuple[list[str], argparse.Action]]:
    """(command path, action) of every option that takes a value."""

    def walk(parser: argparse.ArgumentParser, path: list[str]) -> Iterator[tuple[list[str], argparse.Action]]:
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    yield from walk(sub, [*path, name])
            elif action.option_strings and action.nargs != 0:
                yield path, action

    yield from walk(build_parser(), [])


CASES = [
    pytest.param(path, action, id=" ".join([*path, action.option_strings[-1]]))
    for path, action in options()
    if action.choices is None
]


@pytest.mark.parametrize("path,action", CASES)
def test_every_option_refuses_bad_values(
    path: list[str], action: argparse.Action, capsys: pytest.CaptureFixture[str]
) -> None:
    values = bad_values(action.type)
    assert values is not None, f"{action.option_strings[-1]} has type {action.type!r}, which checks nothing"
    option = action.option_strings[-1]
    for value in values:
        with pytest.raises(SystemExit) as stopped:
            build_parser().parse_args([*path, option, value])
        assert stopped.value.code == 2, (option, value)
        assert option in capsys.readouterr().err, (option, value)


def test_the_walk_finds_the_options() -> None:
    found = {" ".join([*path, action.option_strings[-1]]) for path, action in options()}
    assert {"reproduce fti --runs", "reproduce wavelet --workers", "demo --seed"} <= found
    assert len(found) > 40


def test_every_method_parameter_option_says_what_it_is() -> None:
    """The file commands' parameter options carry the first sentence of the parameter's
    docstring entry before the values they take and their default."""

    def walk(parser: argparse.ArgumentParser) -> Iterator[tuple[str, argparse.Action]]:
        for group in parser._action_groups:
            if "parameters" in (group.title or ""):
                for action in group._group_actions:
                    yield action.option_strings[-1], action
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for sub in action.choices.values():
                    yield from walk(sub)

    found = dict(walk(build_parser()))
    assert {"--method", "--spread-factor", "--rings", "--tau", "--eta", "--max-iter"} <= set(found)
    bare = [flag for flag, action in found.items() if not action.help or action.help.startswith("[")]
    assert not bare, bare
    assert all(action.help and action.help.rstrip().endswith("]") for action in found.values())


def test_reproduce_fti_takes_the_initiators_defaults() -> None:
    """`reproduce fti`'s method options default to what FuzzyTrackInitiator declares (one
    declaration): parsing no option gives the class's values and choices."""
    args = build_parser().parse_args(["reproduce", "fti"])
    declared = field_defaults(FuzzyTrackInitiator)
    names = ["refine_passes", "candidate_scans", "descent_scaling", "detection_order", "gate_pd"]
    assert {n: getattr(args, n) for n in names} == {n: declared[n] for n in names}
    assert declared["detection_order"] == "membership"  # the comparison above is not vacuous
