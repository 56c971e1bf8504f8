"""Declared parameter constraints, checked in one place.

Each parameter of a configurable class or function is declared once: its name, type,
constraints and default on one line, the constraints as :data:`typing.Annotated` metadata::

    @dataclass(frozen=True)
    class Initiator(Configurable):
        gate_sigmas: Annotated[float, Interval(float, 0.0, None, closed="neither")] = 5.0
        v_max: Annotated[float | None, Interval(float, 0.0, None, closed="neither"), None] = 500.0
        descent_scaling: Annotated[Literal["whitened", "diagonal"], Options("whitened", "diagonal")] = "whitened"

    @checked
    def fit(table, *, max_iter: Annotated[int, Interval(int, 1, None)] = 20) -> ...: ...

:func:`declared` reads the constraint table (name -> constraints, in the spirit of
scikit-learn's ``_parameter_constraints``) off those annotations; :class:`Configurable`
validates a dataclass's fields against it after construction, and :func:`checked` a
function's arguments on each call. :func:`validate` checks values against a table: a value passes when it satisfies any
constraint of its list (``None`` in the list allows ``None``). Wrong *kinds* (a string for a
number, a bool for a count, a float for an int) raise :class:`TypeError`; wrong *values* raise
:class:`ValueError`. Messages start with the parameter's name. The returned values are
normalised (``float``/``int``/``bool``), so NumPy scalars pass and reach the core as plain
Python numbers. Array-valued parameters (per-sensor probabilities, say) are checked where
their shape is known, not here. Pure Python: must not import the compiled extension.
"""

from __future__ import annotations

import functools
import inspect
import math
import numbers
import typing
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any, Literal, TypeVar, cast

import numpy as np

__all__ = [
    "COUNT",
    "POSITIVE",
    "Boolean",
    "Configurable",
    "Constraint",
    "Epoch",
    "Interval",
    "Options",
    "Threads",
    "checked",
    "constraints_of",
    "declared",
    "validate",
]

Closed = Literal["both", "left", "right", "neither"]

#: Largest integer the compiled core accepts.
INT64_MAX = 2**63 - 1
#: The largest finite float, as an exact integer: a larger int has no float (OverflowError).
_FLOAT_MAX = int(np.finfo(np.float64).max)


@dataclass(frozen=True)
class Interval:
    """A real (``float``) or integer (``int``) number in ``[low, high]``, ends open or closed
    as ``closed`` says; ``None`` leaves a side unbounded. Real values must be finite."""

    kind: type[float] | type[int]
    low: float | None
    high: float | None
    closed: Closed = "both"

    def describe(self) -> str:
        """The range in words, e.g. ``> 0``, ``in [0, 1)``, ``an integer >= 1``."""
        low_op = ">=" if self.closed in ("both", "left") else ">"
        high_op = "<=" if self.closed in ("both", "right") else "<"
        if self.high is None and self.low is None:
            text = "any value"
        elif self.high is None:
            text = f"{low_op} {self.low:g}"
        elif self.low is None:
            text = f"{high_op} {self.high:g}"
        else:
            left = "[" if self.closed in ("both", "left") else "("
            right = "]" if self.closed in ("both", "right") else ")"
            text = f"in {left}{self.low:g}, {self.high:g}{right}"
        return f"an integer {text}" if self.kind is int else text

    def accepts_kind(self, value: Any) -> bool:
        kind = type(value)
        if kind is int:  # the common cases first: the ABC checks below cost microseconds
            return True
        if kind is float:
            return self.kind is float
        if isinstance(value, bool):
            return False
        if self.kind is int:
            return isinstance(value, numbers.Integral)
        return isinstance(value, numbers.Real)

    def contains(self, value: float) -> bool:
        if self.kind is float and not math.isfinite(value):
            return False
        low_ok = self.low is None or (value >= self.low if self.closed in ("both", "left") else value > self.low)
        high_ok = self.high is None or (value <= self.high if self.closed in ("both", "right") else value < self.high)
        return low_ok and high_ok

    def normalise(self, value: Any) -> float | int:
        return int(value) if self.kind is int else float(value)


@dataclass(frozen=True, init=False)
class Options:
    """One of a fixed set of strings."""

    choices: tuple[str, ...]

    def __init__(self, *choices: str) -> None:
        object.__setattr__(self, "choices", choices)

    def describe(self) -> str:
        quoted = [repr(c) for c in self.choices]
        return quoted[0] if len(quoted) == 1 else f"{', '.join(quoted[:-1])} or {quoted[-1]}"


@dataclass(frozen=True)
class Boolean:
    """``True`` or ``False`` (a Python or NumPy bool; not ``0``/``1``, not a string)."""

    def describe(self) -> str:
        return "a bool"


Constraint = Interval | Options | Boolean | None

#: A finite number > 0.
POSITIVE = Interval(float, 0.0, None, closed="neither")
#: A count of at least one.
COUNT = Interval(int, 1, None)
#: ``n_threads`` of every parallel entry point: threads to use, None for every core. Results
#: are identical for any value.
Threads = typing.Annotated[int | None, COUNT, None]
#: An epoch ``t0`` in seconds, or None for the data's earliest time. Beyond ±1e12 s (32 000
#: years) an epoch swamps the measurement times: ``t − t0`` keeps no digits of ``t``.
Epoch = typing.Annotated[float | None, Interval(float, -1e12, 1e12), None]


def _check(name: str, value: Any, constraints: Sequence[Constraint]) -> Any:
    if value is None:
        if None in constraints:
            return None
        raise TypeError(f"{name}: expected {_describe(constraints)}, got None")
    kind_matched = False
    for constraint in constraints:
        if isinstance(constraint, Interval) and constraint.accepts_kind(value):
            kind_matched = True
            if constraint.kind is int and abs(int(value)) > INT64_MAX:
                # The core takes 64-bit integers: say so rather than let an OverflowError out.
                raise ValueError(f"{name}: {value} is out of the 64-bit integer range")
            if constraint.kind is float and isinstance(value, numbers.Integral) and abs(int(value)) > _FLOAT_MAX:
                digits = len(str(abs(int(value))))
                raise ValueError(f"{name}: an integer of {digits} digits is beyond the range of a float")
            if constraint.contains(float(value) if constraint.kind is float else int(value)):
                return constraint.normalise(value)
        elif isinstance(constraint, Options) and isinstance(value, str):
            kind_matched = True
            if value in constraint.choices:
                return value
        elif isinstance(constraint, Boolean) and _is_bool(value):
            return bool(value)
    got = repr(value) if isinstance(value, str) else str(value)
    if kind_matched:
        raise ValueError(f"{name}: must be {_describe(constraints)}, got {got}")
    raise TypeError(f"{name}: expected {_kinds(constraints)}, got {type(value).__name__} {got}")


def _is_bool(value: Any) -> bool:
    return isinstance(value, (bool, np.bool_))


def _kinds(constraints: Sequence[Constraint]) -> str:
    """What kinds of value the constraints take, for a TypeError."""
    names = {Boolean: "a bool", Options: "a string"}
    parts = []
    for c in constraints:
        if isinstance(c, Interval):
            part = "an integer" if c.kind is int else "a real number"
        else:
            part = "None" if c is None else names[type(c)]
        if part not in parts:
            parts.append(part)
    return " or ".join(parts)


def _describe(constraints: Sequence[Constraint]) -> str:
    parts = [c.describe() for c in constraints if c is not None]
    if None in constraints:
        parts.append("None")
    return " or ".join(parts)


def validate(values: Mapping[str, Any], constraints: Mapping[str, Sequence[Constraint]]) -> dict[str, Any]:
    """Check every ``values[name]`` against ``constraints[name]``; returns the normalised
    values. A name in ``values`` without a declared constraint is a programming error.

    >>> validate({"n": 3, "mode": "fast"}, {"n": [Interval(int, 1, None)], "mode": [Options("fast", "slow")]})
    {'n': 3, 'mode': 'fast'}
    >>> validate({"tol": 0.0}, {"tol": [Interval(float, 0.0, None, closed="neither")]})
    Traceback (most recent call last):
    ...
    ValueError: tol: must be > 0, got 0.0
    """
    missing = set(values) - set(constraints)
    if missing:
        raise KeyError(f"no constraint declared for {sorted(missing)}")
    return {name: _check(name, value, constraints[name]) for name, value in values.items()}


Table = dict[str, list[Constraint]]


def constraints_of(hint: Any) -> list[Constraint]:
    """The constraints an ``Annotated`` declaration carries, for a :func:`validate` table:
    ``constraints_of(Threads)`` checks ``n_threads`` as every entry point does.

    >>> constraints_of(Threads)
    [Interval(kind=<class 'int'>, low=1, high=None, closed='both'), None]
    """
    found = _constraints_in(hint)
    if found is None:
        raise TypeError(f"{hint!r} declares no constraints")
    return found


def _constraints_in(hint: Any) -> list[Constraint] | None:
    """The constraints an ``Annotated[...]`` hint carries, or None if it carries none."""
    if typing.get_origin(hint) is not typing.Annotated:
        return None
    found = [m for m in hint.__metadata__ if m is None or isinstance(m, (Interval, Options, Boolean))]
    return found or None


#: Each class's or function's table, read once.
_TABLES: dict[object, Table] = {}


def declared(owner: object) -> Table:
    """The constraint table a class or function declares in its annotations: every parameter
    annotated ``Annotated[type, constraint, ...]``, in declaration order (a class's inherited
    parameters first). Parameters without constraints (arrays checked against the data, say)
    are not in it.

    >>> def f(n: typing.Annotated[int, Interval(int, 1, None)] = 1, name: str = "x") -> None: ...
    >>> declared(f)
    {'n': [Interval(kind=<class 'int'>, low=1, high=None, closed='both')]}
    """
    table = _TABLES.get(owner)
    if table is None:
        hints = typing.get_type_hints(owner, include_extras=True)
        table = {name: c for name, hint in hints.items() if (c := _constraints_in(hint)) is not None}
        _TABLES[owner] = table
    return table


def field_defaults(cls: type[Any]) -> dict[str, Any]:
    """Each field's default of the dataclass ``cls``, by name: what a command line shows and
    falls back on, read from the one declaration."""
    return {f.name: f.default for f in fields(cls)}


class _DeclaredTable:
    """``cls._constraints``: the class's :func:`declared` table, read off its annotations on
    first use (the names they mention exist by then)."""

    def __get__(self, instance: object, owner: type) -> Table:
        return declared(owner)


class Configurable:
    """Base of the configured (frozen dataclass) classes: each field declared once with its
    constraints (see the module); after construction every declared field is validated and
    normalised (NumPy scalars become ``int``/``float``/``bool``). A subclass with checks of its
    own calls ``super().__post_init__()`` first."""

    _constraints: typing.ClassVar[_DeclaredTable] = _DeclaredTable()

    def __post_init__(self) -> None:
        table = declared(type(self))
        values = validate({name: getattr(self, name) for name in table}, table)
        for name, value in values.items():
            object.__setattr__(self, name, value)


F = TypeVar("F", bound=Callable[..., Any])


def checked(function: F) -> F:
    """Decorator: validate (and normalise) the arguments of ``function``'s declared parameters
    on every call, against the constraints in its annotations."""
    signature = inspect.signature(function)

    @functools.wraps(function)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        table = declared(function)
        bound = signature.bind(*args, **kwargs)
        given = {name: value for name, value in bound.arguments.items() if name in table}
        bound.arguments.update(validate(given, table))
        return function(*bound.args, **bound.kwargs)

    return cast(F, wrapper)
