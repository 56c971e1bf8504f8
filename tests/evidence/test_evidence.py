"""passive_assoc.evidence: Dempster's rule on its textbook properties, the two closed forms of
attribute evidence (METHODS §3), a worked example, bad input, and an independent
implementation (py_dempster_shafer's ``pyds``) on random cases."""

from __future__ import annotations

import itertools
import math
import pickle
from collections.abc import Hashable, Iterable

import numpy as np
import pytest
from passive_assoc import evidence
from passive_assoc.evidence import CombinationResult, MassFunction, combine, simple_support_assoc, two_outcome_assoc

FRAME = frozenset(range(4))
CASES = 50
ASSOC = frozenset({"assoc", "not"})


def subsets(frame: Iterable[Hashable]) -> list[frozenset[Hashable]]:
    items = sorted(frame)
    return [frozenset(c) for r in range(len(items) + 1) for c in itertools.combinations(items, r)]


def random_mass(rng: np.random.Generator, frame: frozenset[int] = FRAME, with_frame: bool = True) -> MassFunction:
    """1–4 random non-empty focal sets with Dirichlet masses; some mass on the frame itself when
    ``with_frame`` (so no two such functions are in total conflict)."""
    nonempty = [s for s in subsets(frame) if s]
    picks = rng.choice(len(nonempty), size=rng.integers(1, 5), replace=False)
    focal = [nonempty[k] for k in picks] + ([frame] if with_frame else [])
    weights = rng.dirichlet(np.ones(len(focal)))
    masses: dict[frozenset[Hashable], float] = {}
    for a, w in zip(focal, weights, strict=True):
        masses[a] = masses.get(a, 0.0) + float(w)
    return MassFunction(masses, frame)


def assert_same(a: MassFunction, b: MassFunction, tol: float = 1e-12) -> None:
    assert a.frame == b.frame
    assert set(a.focal_sets) == set(b.focal_sets)
    for s in a.focal_sets:
        assert a.mass(s) == pytest.approx(b.mass(s), abs=tol)


def conjunctive_nary(*masses: MassFunction) -> tuple[dict[frozenset[Hashable], float], float]:
    """The n-ary conjunctive (unnormalised) combination by brute force over one focal set per
    source: the masses of non-empty intersections and the mass on the empty set."""
    joint: dict[frozenset[Hashable], list[float]] = {}
    for choice in itertools.product(*(m.masses.items() for m in masses)):
        meet = frozenset.intersection(*(s for s, _ in choice))
        joint.setdefault(meet, []).append(math.prod(v for _, v in choice))
    empty = math.fsum(joint.pop(frozenset(), []))
    return {s: math.fsum(p) for s, p in joint.items()}, empty


# --------------------------------------------------------------------------- textbook properties


def test_commutative() -> None:
    rng = np.random.default_rng(1)
    for _ in range(CASES):
        a, b = random_mass(rng), random_mass(rng)
        ab, ba = a.combine(b), b.combine(a)
        assert_same(ab.mass, ba.mass)
        assert ab.conflict == pytest.approx(ba.conflict, abs=1e-12)


def test_associative_and_the_total_conflict_is_the_nary_conflict() -> None:
    rng = np.random.default_rng(2)
    for _ in range(CASES):
        a, b, c = random_mass(rng), random_mass(rng), random_mass(rng)
        left, right, joint = combine(combine(a, b).mass, c), combine(a, combine(b, c).mass), combine(a, b, c)
        assert_same(left.mass, right.mass)
        assert_same(left.mass, joint.mass)
        nary, k = conjunctive_nary(a, b, c)
        assert joint.conflict == pytest.approx(k, abs=1e-12)
        steps = [combine(a, b).conflict, left.conflict]
        assert joint.conflict == pytest.approx(1 - (1 - steps[0]) * (1 - steps[1]), abs=1e-12)
        assert_same(joint.mass, MassFunction({s: v / (1 - k) for s, v in nary.items()}, FRAME))


def test_vacuous_is_the_identity() -> None:
    rng = np.random.default_rng(3)
    vacuous = MassFunction.vacuous(FRAME)
    assert vacuous.focal_sets == (FRAME,) and vacuous.mass(FRAME) == 1.0
    for _ in range(CASES):
        m = random_mass(rng, with_frame=False)
        for result in (combine(m, vacuous), combine(vacuous, m)):
            assert_same(result.mass, m, tol=1e-15)
            assert result.conflict == 0.0


def test_belief_plausibility_and_moebius_inversion() -> None:
    """Bel ≤ Pl, Bel(A) = 1 − Pl(Θ ∖ A), Bel(∅) = Pl(∅) = 0, Bel(Θ) = 1, and the masses come
    back from the beliefs by Möbius inversion."""
    rng = np.random.default_rng(4)
    for _ in range(CASES):
        m = random_mass(rng, with_frame=bool(rng.integers(2)))
        for a in subsets(FRAME):
            bel, pl = m.belief(a), m.plausibility(a)
            assert 0.0 <= bel <= pl + 1e-15 and pl <= 1.0 + 1e-15
            assert bel == pytest.approx(1.0 - m.plausibility(FRAME - a), abs=1e-12)
            moebius = sum((-1) ** len(a - b) * m.belief(b) for b in subsets(a))
            assert moebius == pytest.approx(m.mass(a), abs=1e-12)
        assert m.belief(frozenset()) == m.plausibility(frozenset()) == 0.0
        assert m.belief(FRAME) == pytest.approx(1.0, abs=1e-12)


def test_pignistic_is_a_probability_between_belief_and_plausibility() -> None:
    rng = np.random.default_rng(5)
    for _ in range(CASES):
        m = random_mass(rng, with_frame=bool(rng.integers(2)))
        betp = m.pignistic()
        assert set(betp) == FRAME
        assert math.fsum(betp.values()) == pytest.approx(1.0, abs=1e-12)
        for a in subsets(FRAME):
            p = math.fsum(betp[x] for x in a)
            assert m.belief(a) - 1e-12 <= p <= m.plausibility(a) + 1e-12


def test_bayesian_masses_combine_as_normalised_products() -> None:
    rng = np.random.default_rng(6)
    for _ in range(CASES):
        p, q = rng.dirichlet(np.ones(4)), rng.dirichlet(np.ones(4))
        a = MassFunction({(x,): float(p[x]) for x in FRAME}, FRAME)
        b = MassFunction({(x,): float(q[x]) for x in FRAME}, FRAME)
        result = combine(a, b)
        assert result.conflict == pytest.approx(1.0 - float(p @ q), abs=1e-12)
        for x in FRAME:
            assert result.mass.mass({x}) == pytest.approx(p[x] * q[x] / (p @ q), abs=1e-12)


# --------------------------------------------------------------------------- closed forms (METHODS §3)


def random_supports(rng: np.random.Generator) -> np.ndarray:
    s = rng.uniform(size=rng.integers(1, 7))
    s[rng.uniform(size=s.size) < 0.1] = rng.choice([0.0, 1.0])
    return s


def test_simple_support_functions_combine_to_one_minus_the_product() -> None:
    rng = np.random.default_rng(7)
    for _ in range(CASES):
        s = random_supports(rng)
        result = combine(*(MassFunction.simple_support({"assoc"}, float(v), ASSOC) for v in s))
        expected = 1.0 - math.prod(1.0 - s)
        assert result.conflict == 0.0
        assert result.mass.mass({"assoc"}) == pytest.approx(expected, abs=1e-12)
        assert result.mass.mass(ASSOC) == pytest.approx(1.0 - expected, abs=1e-12)
        assert simple_support_assoc(s) == pytest.approx(expected, abs=1e-12)
        assert simple_support_assoc(list(s)) == simple_support_assoc(s)


def test_two_outcome_reading_is_the_normalised_product() -> None:
    rng = np.random.default_rng(8)
    for _ in range(CASES):
        s = np.clip(random_supports(rng), 0.0, 0.999) if rng.integers(2) else random_supports(rng).clip(1e-3, 1.0)
        result = combine(*(MassFunction({("assoc",): float(v), ("not",): 1.0 - float(v)}, ASSOC) for v in s))
        yes, no = math.prod(s), math.prod(1.0 - s)
        assert result.conflict == pytest.approx(1.0 - yes - no, abs=1e-12)
        assert result.mass.mass({"assoc"}) == pytest.approx(yes / (yes + no), abs=1e-12)
        assert two_outcome_assoc(s) == pytest.approx(yes / (yes + no), abs=1e-12)


def test_closed_forms_with_no_or_many_supports() -> None:
    assert simple_support_assoc([]) == 0.0 and two_outcome_assoc([]) == 0.5
    assert simple_support_assoc([1e-20] * 3) == pytest.approx(3e-20, rel=1e-12)  # 1 − Π(1 − s) would round to 0
    # 0.6⁵⁰⁰ · 0.4⁵⁰⁰ underflows, so the direct quotient is 0/0; the log-odds are exactly 0.
    assert two_outcome_assoc([0.6, 0.4] * 500) == pytest.approx(0.5, abs=1e-12)
    assert two_outcome_assoc([0.6] * 1000) == 1.0
    assert two_outcome_assoc([0.3, 1.0]) == 1.0 and two_outcome_assoc([0.3, 0.0]) == 0.0
    assert simple_support_assoc(np.array([0.2, 1.0])) == 1.0


# --------------------------------------------------------------------------- worked examples


def test_zadehs_example() -> None:
    """Zadeh (1984): two experts who each all but exclude B agree on B with certainty."""
    frame = {"A", "B", "C"}
    m1 = MassFunction({("A",): 0.99, ("B",): 0.01}, frame)
    m2 = MassFunction({("C",): 0.99, ("B",): 0.01}, frame)
    result = m1.combine(m2)
    assert isinstance(result, CombinationResult)
    assert result.mass.focal_sets == (frozenset({"B"}),)
    assert result.mass.mass({"B"}) == pytest.approx(1.0, abs=1e-12)
    assert result.conflict == pytest.approx(0.9999, abs=1e-12)


def test_docstring_example_by_hand() -> None:
    """m1: 0.8 on {a}, 0.2 on Θ; m2: 0.5 {a}, 0.2 {n}, 0.3 Θ. K = 0.8·0.2 = 0.16."""
    m1 = MassFunction.simple_support({"a"}, 0.8, {"a", "n"})
    m2 = MassFunction({("a",): 0.5, ("n",): 0.2, ("a", "n"): 0.3})
    result = combine(m1, m2)
    assert result.conflict == pytest.approx(0.16, abs=1e-15)
    assert result.mass.mass({"a"}) == pytest.approx(0.74 / 0.84, abs=1e-15)
    assert result.mass.mass({"n"}) == pytest.approx(0.04 / 0.84, abs=1e-15)
    assert result.mass.pignistic()["a"] == pytest.approx((0.74 + 0.03) / 0.84, abs=1e-15)


# --------------------------------------------------------------------------- the value type


def test_mass_function_is_an_immutable_value() -> None:
    m = MassFunction({("b", "a"): 0.25, ("a", "b"): 0.25, ("c",): 0.5})
    assert m.mass({"a", "b"}) == 0.5 and m.mass({"a"}) == 0.0
    assert m == eval(repr(m), {"MassFunction": MassFunction})
    assert pickle.loads(pickle.dumps(m)) == m and hash(pickle.loads(pickle.dumps(m))) == hash(m)
    with pytest.raises(AttributeError, match="immutable"):
        m._masses = {}  # type: ignore[misc]
    with pytest.raises(TypeError):
        m.masses[frozenset({"c"})] = 1.0  # type: ignore[index]
    assert MassFunction({("a",): 1.0, ("b",): 0.0}).focal_sets == (frozenset({"a"}),)
    assert MassFunction({("a",): 1.0}, frame={"a", "b"}) != MassFunction({("a",): 1.0})
    assert all(hasattr(evidence, name) for name in evidence.__all__)


# --------------------------------------------------------------------------- errors


def test_total_conflict_is_a_value_error() -> None:
    a, b = MassFunction({("x",): 1.0}, {"x", "y"}), MassFunction({("y",): 1.0}, {"x", "y"})
    with pytest.raises(ValueError, match="total conflict"):
        combine(a, b)
    near = MassFunction({("y",): 1 - 1e-13, ("x",): 1e-13}, {"x", "y"})
    with pytest.raises(ValueError, match="total conflict"):
        a.combine(near)
    # Each step leaves 1e-5 of agreement, the three together 1e-15: total conflict overall.
    steps = [MassFunction({(k,): 1 - 1e-5, ("x",): 1e-5}, {"x", "y", "z", "w"}) for k in "yzw"]
    assert combine(*steps[:2]).conflict == pytest.approx(1 - 1e-10, abs=1e-12)
    with pytest.raises(ValueError, match="total conflict"):
        combine(*steps)
    with pytest.raises(ValueError, match="total conflict"):
        two_outcome_assoc([0.5, 1.0, 0.0])


BAD_MASSES = [
    ({("a",): 0.5, ("b",): 0.4}, ValueError, r"masses: must sum to 1 .*got 0\.9"),
    ({("a",): 1.5, ("b",): -0.5}, ValueError, r"masses\[\{'b'\}\]: must be finite and ≥ 0"),
    ({("a",): math.nan}, ValueError, r"masses\[\{'a'\}\]: must be finite"),
    ({("a",): math.inf}, ValueError, r"masses\[\{'a'\}\]: must be finite"),
    ({(): 0.2, ("a",): 0.8}, ValueError, "masses: the empty set has mass"),
    ({"ab": 1.0}, TypeError, "masses: 'ab' is a string"),
    ({3: 1.0}, TypeError, "masses: expected an iterable"),
    ({("a",): True}, TypeError, r"masses\[\{'a'\}\]: expected a real number"),
    ({("a",): "1"}, TypeError, r"masses\[\{'a'\}\]: expected a real number"),
    ([(("a",), 1.0)], TypeError, "masses: expected a mapping"),
    ({}, ValueError, "masses: must sum to 1"),
]


@pytest.mark.parametrize(("masses", "error", "message"), BAD_MASSES)
def test_bad_masses(masses: object, error: type[Exception], message: str) -> None:
    with pytest.raises(error, match=message):
        MassFunction(masses)  # type: ignore[arg-type]


def test_bad_frames_subsets_and_operands() -> None:
    m = MassFunction({("a",): 1.0}, frame={"a", "b"})
    with pytest.raises(ValueError, match=r"masses: elements \{'c'\} are not in frame"):
        MassFunction({("c",): 1.0}, frame={"a", "b"})
    with pytest.raises(TypeError, match="frame: 'ab' is a string"):
        MassFunction({("a",): 1.0}, frame="ab")
    with pytest.raises(ValueError, match="subset: elements"):
        m.belief({"z"})
    with pytest.raises(ValueError, match="other: its frame"):
        m.combine(MassFunction({("a",): 1.0}))
    with pytest.raises(TypeError, match="other: expected a MassFunction"):
        m.combine({("a",): 1.0})  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="masses"):
        combine()
    with pytest.raises(ValueError, match="frame: must have at least one element"):
        MassFunction.vacuous([])
    with pytest.raises(ValueError, match=r"s: must be in \[0, 1\]"):
        MassFunction.simple_support({"a"}, 1.2, {"a", "b"})
    with pytest.raises(ValueError, match="focal: must be a non-empty"):
        MassFunction.simple_support(set(), 0.5, {"a", "b"})
    with pytest.raises(ValueError, match="focal: elements"):
        MassFunction.simple_support({"c"}, 0.5, {"a", "b"})


@pytest.mark.parametrize(
    ("supports", "error", "message"),
    [
        ([0.5, 1.2], ValueError, r"supports\[1\]: must be in \[0, 1\], got 1\.2"),
        ([-0.1], ValueError, r"supports\[0\]: must be in \[0, 1\]"),
        ([0.5, math.nan], ValueError, r"supports\[1\]: must be in \[0, 1\], got nan"),
        ([[0.5, 0.5]], ValueError, "supports: expected a 1-D sequence"),
        (0.5, ValueError, "supports: expected a 1-D sequence"),
        ([[0.5], [0.5, 0.2]], ValueError, "supports: cannot be converted"),
        (["a"], TypeError, "supports: expected real numbers"),
        ([True, False], TypeError, "supports: expected real numbers"),
    ],
)
def test_bad_supports(supports: object, error: type[Exception], message: str) -> None:
    for closed_form in (simple_support_assoc, two_outcome_assoc):
        with pytest.raises(error, match=message):
            closed_form(supports)  # type: ignore[arg-type]


# --------------------------------------------------------------------------- independent implementation


def test_agrees_with_pyds() -> None:
    """py_dempster_shafer (Reineking's ``pyds``) on random cases: Dempster's rule (pairs and
    triples), the conflict, belief, plausibility and the pignistic probability."""
    pyds = pytest.importorskip("pyds", reason="py_dempster_shafer is in the test extra")
    if not hasattr(pyds, "MassFunction"):
        pytest.skip("the installed pyds is not py_dempster_shafer's")
    rng = np.random.default_rng(9)
    for _ in range(CASES):
        ours = [random_mass(rng, with_frame=bool(rng.integers(2))) for _ in range(3)]
        theirs = [pyds.MassFunction({tuple(s): v for s, v in m.masses.items()}) for m in ours]
        for m, t in zip(ours, theirs, strict=True):
            for a in subsets(FRAME):
                assert m.belief(a) == pytest.approx(t.bel(a), abs=1e-12)
                assert m.plausibility(a) == pytest.approx(t.pl(a), abs=1e-12)
            ours_betp, theirs_betp = m.pignistic(), t.pignistic()
            assert all(ours_betp[x] == pytest.approx(theirs_betp[{x}], abs=1e-12) for x in FRAME)
        for group in (ours[:2], ours):
            k = theirs[0].combine_conjunctive(theirs[1 : len(group)], normalization=False)[frozenset()]
            result, expected = combine(*group), theirs[0].combine_conjunctive(theirs[1 : len(group)])
            assert result.conflict == pytest.approx(k, abs=1e-12)
            assert {s for s, v in expected.items() if v > 0} == set(result.mass.focal_sets)
            assert all(result.mass.mass(s) == pytest.approx(v, abs=1e-9) for s, v in expected.items())
