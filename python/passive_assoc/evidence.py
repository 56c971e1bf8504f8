"""Dempster-Shafer evidence: mass functions over a finite frame, and Dempster's rule.

In emitter association (METHODS §3) every attribute two reports share — carrier frequency,
PRF, pulse width, antenna scan period — is a separate, partial piece of evidence that they
come from one emitter. Dempster-Shafer theory lets each source put mass on a *set* of
outcomes: an attribute that supports "associated" with strength ``s`` puts ``s`` on
{associated} and leaves ``1 − s`` on the whole frame (it does not claim "not associated").
Dempster's rule pools independent sources, reporting the mass their focal sets put on the
empty set (the conflict ``K``) and renormalising by ``1 − K``.

:class:`MassFunction` is the general form (arbitrary focal sets, belief, plausibility, the
pignistic probability); :func:`simple_support_assoc` and :func:`two_outcome_assoc` are the
closed forms of the two readings of attribute evidence, the first being the library's default.

Examples
--------
>>> from passive_assoc.evidence import MassFunction, combine
>>> rf = MassFunction.simple_support({"assoc"}, 0.8, frame={"assoc", "not"})
>>> pw = MassFunction({("assoc",): 0.5, ("not",): 0.2, ("assoc", "not"): 0.3})
>>> result = combine(rf, pw)
>>> round(result.conflict, 6), round(result.mass.mass({"assoc"}), 6)
(0.16, 0.880952)
>>> round(result.mass.belief({"assoc"}), 6), round(result.mass.plausibility({"assoc"}), 6)
(0.880952, 0.952381)
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Hashable, Iterable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, NoReturn

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["MassFunction", "CombinationResult", "combine", "simple_support_assoc", "two_outcome_assoc"]

#: A focal set (or any subset of the frame).
Focal = frozenset[Hashable]

#: Masses must sum to 1 within this.
SUM_TOLERANCE = 1e-9
#: Combinations whose conflict is within this of 1 are total conflict.
CONFLICT_TOLERANCE = 1e-12


def _as_set(name: str, value: Any) -> Focal:
    """``frozenset(value)``, refusing strings (whose characters would become the elements)."""
    if isinstance(value, str | bytes):
        raise TypeError(f"{name}: {value!r} is a string; write a set of elements, e.g. {{{value!r}}}")
    try:
        return frozenset(value)
    except TypeError as exc:
        raise TypeError(f"{name}: expected an iterable of hashable elements, got {value!r} ({exc})") from None


def _as_mass(name: str, value: Any) -> float:
    """A finite, non-negative real number."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: expected a real number, got {value!r}")
    mass = float(value)
    if not math.isfinite(mass) or mass < 0.0:
        raise ValueError(f"{name}: must be finite and ≥ 0, got {mass!r}")
    return mass


def _ordered(elements: Iterable[Hashable]) -> list[Hashable]:
    """The elements sorted (by ``repr`` when they cannot be compared), for stable output."""
    items = list(elements)
    try:
        return sorted(items)  # type: ignore[type-var]
    except TypeError:
        return sorted(items, key=repr)


def _show(subset: Iterable[Hashable]) -> str:
    return "{" + ", ".join(repr(x) for x in _ordered(subset)) + "}"


def _collect(masses: Mapping[Any, float]) -> dict[Focal, float]:
    """``masses`` checked and keyed by frozenset (repeated sets added up)."""
    if not isinstance(masses, Mapping):
        raise TypeError(f"masses: expected a mapping {{focal set: mass}}, got {type(masses).__name__}")
    summed: dict[Focal, float] = {}
    for key, value in masses.items():
        focal = _as_set("masses", key)
        mass = _as_mass(f"masses[{_show(focal)}]", value)
        if focal or mass > 0.0:
            summed[focal] = summed.get(focal, 0.0) + mass
    if summed.get(frozenset(), 0.0) > 0.0:
        raise ValueError("masses: the empty set has mass; a normalised mass function puts none on it")
    total = math.fsum(summed.values())
    if abs(total - 1.0) > SUM_TOLERANCE:
        raise ValueError(f"masses: must sum to 1 (within {SUM_TOLERANCE:g}), got {total!r}")
    return summed


class MassFunction:
    """A normalised mass function (basic belief assignment) over a finite frame; immutable.

    Parameters
    ----------
    masses : mapping
        ``{focal set: mass}``; each focal set is an iterable of hashable elements (not a
        string). Masses are finite, ≥ 0 and sum to 1 within 1e-9; zero masses are dropped and
        repeated sets (``("a", "b")`` and ``("b", "a")``) add up. The empty set gets no mass.
    frame : iterable, optional
        The frame of discernment Θ; every focal set must lie in it. Default: the union of the
        focal sets.

    Examples
    --------
    >>> m = MassFunction({("a",): 0.5, ("a", "b"): 0.3, ("b", "c"): 0.2})
    >>> m
    MassFunction({('a',): 0.5, ('a', 'b'): 0.3, ('b', 'c'): 0.2}, frame=('a', 'b', 'c'))
    >>> m.belief({"a", "b"}), m.plausibility({"c"})
    (0.8, 0.2)
    >>> {x: round(p, 6) for x, p in m.pignistic().items()}
    {'a': 0.65, 'b': 0.25, 'c': 0.1}
    """

    __slots__ = ("_frame", "_masses", "_order")
    _frame: Focal
    _masses: Mapping[Focal, float]
    _order: tuple[Hashable, ...]

    def __init__(self, masses: Mapping[Any, float], frame: Iterable[Hashable] | None = None) -> None:
        summed = _collect(masses)
        union = frozenset().union(*summed)
        theta = union if frame is None else _as_set("frame", frame)
        if not union <= theta:
            raise ValueError(f"masses: elements {_show(union - theta)} are not in frame {_show(theta)}")
        order = tuple(_ordered(theta))
        rank = {x: k for k, x in enumerate(order)}
        focal_sets = sorted(
            (a for a, v in summed.items() if v > 0.0), key=lambda a: (len(a), sorted(rank[x] for x in a))
        )
        object.__setattr__(self, "_frame", theta)
        object.__setattr__(self, "_order", order)
        object.__setattr__(self, "_masses", MappingProxyType({a: summed[a] for a in focal_sets}))

    def __setattr__(self, name: str, value: object) -> NoReturn:
        raise AttributeError(f"MassFunction is immutable; cannot set {name!r}")

    def __delattr__(self, name: str) -> NoReturn:
        raise AttributeError(f"MassFunction is immutable; cannot delete {name!r}")

    def __reduce__(self) -> tuple[type[MassFunction], tuple[dict[Focal, float], Focal]]:
        return (MassFunction, (dict(self._masses), self._frame))

    @classmethod
    def vacuous(cls, frame: Iterable[Hashable]) -> MassFunction:
        """Total ignorance: mass 1 on the whole (non-empty) ``frame``; the identity of Dempster's rule."""
        theta = _as_set("frame", frame)
        if not theta:
            raise ValueError("frame: must have at least one element")
        return cls({theta: 1.0}, theta)

    @classmethod
    def simple_support(cls, focal: Iterable[Hashable], s: float, frame: Iterable[Hashable]) -> MassFunction:
        """A simple support function: mass ``s`` (in [0, 1]) on ``focal``, ``1 − s`` on ``frame``."""
        subset, theta = _as_set("focal", focal), _as_set("frame", frame)
        if not subset:
            raise ValueError("focal: must be a non-empty set")
        if not subset <= theta:
            raise ValueError(f"focal: elements {_show(subset - theta)} are not in frame {_show(theta)}")
        support = _as_mass("s", s)
        if support > 1.0:
            raise ValueError(f"s: must be in [0, 1], got {support!r}")
        masses = {subset: support}
        masses[theta] = masses.get(theta, 0.0) + (1.0 - support)
        return cls(masses, theta)

    @property
    def frame(self) -> Focal:
        """The frame of discernment Θ."""
        return self._frame

    @property
    def focal_sets(self) -> tuple[Focal, ...]:
        """The sets with positive mass, by size, then in the frame's order."""
        return tuple(self._masses)

    @property
    def masses(self) -> Mapping[Focal, float]:
        """Read-only ``{focal set: mass}``."""
        return self._masses

    def _subset(self, subset: Iterable[Hashable]) -> Focal:
        a = _as_set("subset", subset)
        if not a <= self._frame:
            raise ValueError(f"subset: elements {_show(a - self._frame)} are not in the frame {_show(self._frame)}")
        return a

    def mass(self, subset: Iterable[Hashable]) -> float:
        """``m(A)``: the mass on exactly ``subset`` (0 when it is not focal)."""
        return self._masses.get(self._subset(subset), 0.0)

    def belief(self, subset: Iterable[Hashable]) -> float:
        """``Bel(A) = Σ_{B ⊆ A} m(B)``: the mass that implies ``subset``."""
        a = self._subset(subset)
        return math.fsum(v for b, v in self._masses.items() if b <= a)

    def plausibility(self, subset: Iterable[Hashable]) -> float:
        """``Pl(A) = Σ_{B ∩ A ≠ ∅} m(B) = 1 − Bel(Θ ∖ A)``: the mass consistent with ``subset``."""
        a = self._subset(subset)
        return math.fsum(v for b, v in self._masses.items() if b & a)

    def pignistic(self) -> dict[Hashable, float]:
        """Smets' pignistic probability ``BetP(x) = Σ_{A ∋ x} m(A) / |A|``, for every ``x`` in Θ."""
        shares: dict[Hashable, list[float]] = {x: [] for x in self._order}
        for a, v in self._masses.items():
            for x in a:
                shares[x].append(v / len(a))
        return {x: math.fsum(parts) for x, parts in shares.items()}

    def combine(self, other: MassFunction) -> CombinationResult:
        """Dempster's rule with ``other`` (same frame); see :func:`combine`."""
        return combine(self, other)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, MassFunction):
            return NotImplemented
        return self._frame == other._frame and dict(self._masses) == dict(other._masses)

    def __hash__(self) -> int:
        return hash((self._frame, frozenset(self._masses.items())))

    def __repr__(self) -> str:
        rank = {x: k for k, x in enumerate(self._order)}
        body = ", ".join(f"{tuple(sorted(a, key=rank.__getitem__))!r}: {v!r}" for a, v in self._masses.items())
        return f"MassFunction({{{body}}}, frame={self._order!r})"


@dataclass(frozen=True)
class CombinationResult:
    """The outcome of Dempster's rule.

    Attributes
    ----------
    mass : MassFunction
        The combined, normalised mass function.
    conflict : float
        ``K``: the mass the conjunctive (unnormalised) combination puts on the empty set,
        before normalisation by ``1 − K``. 0 for sources that never contradict each other.
    """

    mass: MassFunction
    conflict: float


def _conjunctive(a: MassFunction, b: MassFunction) -> tuple[dict[Focal, float], float, float]:
    """The conjunctive combination of two mass functions: the masses of its non-empty sets, their
    total ``1 − K`` (accurate when ``K ≈ 1``) and the mass ``K`` on the empty set (0 when no pair
    of focal sets is disjoint)."""
    parts: dict[Focal, list[float]] = {}
    for x, u in a.masses.items():
        for y, v in b.masses.items():
            parts.setdefault(x & y, []).append(u * v)
    conflict = min(math.fsum(parts.pop(frozenset(), [])), 1.0)
    masses = {s: math.fsum(p) for s, p in parts.items()}
    return masses, math.fsum(masses.values()), conflict


def combine(*masses: MassFunction) -> CombinationResult:
    """Dempster's rule over one or more mass functions on the same frame.

    The rule is commutative and associative, so the sources are combined in turn;
    ``conflict`` is the total ``K = 1 − Π(1 − K_i)`` of the steps, which equals the mass the
    n-ary conjunctive combination puts on the empty set.

    Raises
    ------
    TypeError
        An argument is not a :class:`MassFunction` (or none is given).
    ValueError
        The frames differ (naming ``other``), or the sources are in total conflict
        (``K = 1`` within 1e-12: no element is shared by one focal set of each).

    Examples
    --------
    >>> m1 = MassFunction({("A",): 0.99, ("B",): 0.01}, frame=("A", "B", "C"))
    >>> m2 = MassFunction({("C",): 0.99, ("B",): 0.01}, frame=("A", "B", "C"))
    >>> result = combine(m1, m2)  # Zadeh's example
    >>> result.mass, round(result.conflict, 12)
    (MassFunction({('B',): 1.0}, frame=('A', 'B', 'C')), 0.9999)
    """
    if not masses:
        raise TypeError("masses: give at least one MassFunction")
    for k, m in enumerate(masses):
        if not isinstance(m, MassFunction):
            name = "other" if k else "masses[0]"
            raise TypeError(f"{name}: expected a MassFunction, got {type(m).__name__}")
    result, agreement, kept = masses[0], 1.0, 1.0
    for other in masses[1:]:
        if other.frame != result.frame:
            raise ValueError(f"other: its frame {_show(other.frame)} differs from {_show(result.frame)}")
        joint, step, conflict = _conjunctive(result, other)
        agreement, kept = agreement * step, kept * (1.0 - conflict)
        if agreement <= CONFLICT_TOLERANCE:
            raise ValueError(
                "total conflict: the sources' focal sets share no element (K = 1 within "
                f"{CONFLICT_TOLERANCE:g}), so Dempster's rule is undefined"
            )
        result = MassFunction({a: v / step for a, v in joint.items()}, result.frame)
    return CombinationResult(result, 1.0 - kept)  # from the K_i: exactly 0 without conflict


def _supports(supports: ArrayLike) -> np.ndarray[Any, np.dtype[np.float64]]:
    """``supports`` as a 1-D float array with every value in [0, 1]."""
    try:
        arr = np.asarray(supports)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"supports: cannot be converted to an array ({exc})") from None
    if arr.dtype.kind not in "iuf":
        raise TypeError(f"supports: expected real numbers, got an array of dtype {arr.dtype}")
    if arr.ndim != 1:
        raise ValueError(f"supports: expected a 1-D sequence, got shape {arr.shape}")
    values = arr.astype(np.float64)
    bad = np.flatnonzero(~((values >= 0.0) & (values <= 1.0)))  # NaN fails both
    if bad.size:
        raise ValueError(f"supports[{bad[0]}]: must be in [0, 1], got {float(values[bad[0]])!r}")
    return values


def simple_support_assoc(supports: ArrayLike) -> float:
    """``m(assoc) = 1 − Π(1 − s_k)``: the simple-support reading (the library's default).

    Attribute ``k`` is a simple support function: mass ``s_k`` on {associated} and ``1 − s_k``
    on the frame Θ = {associated, not}. These never conflict, and Dempster's rule over the K
    attributes leaves ``1 − Π(1 − s_k)`` on {associated} (METHODS §3, eq. 4).

    Parameters
    ----------
    supports : sequence or 1-D array of float
        The per-attribute supports ``s_k`` in [0, 1]; none gives 0 (no evidence).

    Examples
    --------
    >>> round(simple_support_assoc([0.5, 0.5, 0.2]), 12)
    0.8
    """
    s = _supports(supports)
    if np.any(s == 1.0):
        return 1.0
    return -math.expm1(math.fsum(np.log1p(-s).tolist()))


def two_outcome_assoc(supports: ArrayLike) -> float:
    """``m(assoc) = Π s_k / (Π s_k + Π(1 − s_k))``: the two-outcome reading (an option).

    Attribute ``k`` splits its mass between {associated} (``s_k``) and {not} (``1 − s_k``), a
    Bayesian mass function; Dempster's rule multiplies and renormalises. Stricter than the
    default :func:`simple_support_assoc`: one weak attribute pulls the result towards "not".

    Parameters
    ----------
    supports : sequence or 1-D array of float
        The per-attribute supports ``s_k`` in [0, 1]; none gives 0.5.

    Raises
    ------
    ValueError
        Total conflict: some ``s_k`` is 0 and another is 1 (both products vanish).

    Examples
    --------
    >>> round(two_outcome_assoc([0.9, 0.5, 0.2]), 12)
    0.692307692308
    """
    s = _supports(supports)
    sure, excluded = bool(np.any(s == 1.0)), bool(np.any(s == 0.0))
    if sure and excluded:
        raise ValueError("total conflict: supports has a 1 and a 0, so Π s + Π(1 − s) = 0")
    if sure or excluded:
        return 1.0 if sure else 0.0
    log_odds = math.fsum(np.log(s).tolist()) - math.fsum(np.log1p(-s).tolist())
    if log_odds >= 0.0:
        return 1.0 / (1.0 + math.exp(-log_odds))
    return math.exp(log_odds) / (1.0 + math.exp(log_odds))
