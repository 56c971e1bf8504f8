"""The formation scenes against METHODS §3, and the NumPy comparator of benches/ against a loop
form of the method (the prototype form the paper's tables are reproduced with)."""

from __future__ import annotations

import importlib.util
import itertools
import math
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
from numpy.typing import NDArray
from passive_assoc.simulation import (
    PAPER_ATTRIBUTE_NAMES,
    PAPER_ATTRIBUTE_STD,
    PAPER_FORMATION_ATTRIBUTES,
    PAPER_FORMATION_SENSORS,
    PAPER_FORMATION_TARGETS,
    PAPER_SIGMAS_DEG,
    FormationScene,
    formation_scene,
    paper_formation_scene,
)
from passive_assoc.simulation.formation import EMITTER_BOX


def _load_comparator() -> ModuleType:
    # benches/ is not a package; load the file by path (pytest runs with --import-mode=importlib).
    path = Path(__file__).resolve().parents[2] / "benches" / "formation_numpy.py"
    spec = importlib.util.spec_from_file_location("formation_numpy", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("formation_numpy", module)
    spec.loader.exec_module(module)
    return module


fnp = _load_comparator()


def _truth(scene: FormationScene) -> NDArray[np.int64]:
    truth = scene.measurements.truth
    assert truth is not None
    return truth


def _exact_bearing(scene: FormationScene, row: int) -> float:
    m = scene.measurements
    target = scene.targets[_truth(scene)[row]]
    sensor = scene.sensors.positions[m.sensor[row]]
    return math.atan2(target[1] - sensor[1], target[0] - sensor[0])


def _bearing_errors(scene: FormationScene) -> NDArray[np.float64]:
    m = scene.measurements
    rows = np.flatnonzero(_truth(scene) >= 0)
    exact = np.array([_exact_bearing(scene, int(r)) for r in rows])
    return np.asarray(np.remainder(m.azimuth[rows] - exact + math.pi, 2 * math.pi) - math.pi)


def _attribute_matrix(scene: FormationScene) -> NDArray[np.float64]:
    return np.column_stack([scene.measurements.attributes[name] for name in PAPER_ATTRIBUTE_NAMES])


# --------------------------------------------------------------------------- paper scene


def test_paper_constants() -> None:
    assert PAPER_FORMATION_SENSORS.shape == (3, 2) and PAPER_FORMATION_TARGETS.shape == (6, 2)
    assert PAPER_FORMATION_SENSORS[0].tolist() == [-80e3, -30e3]
    assert PAPER_FORMATION_TARGETS[3].tolist() == [-60e3, 70e3]
    assert PAPER_FORMATION_ATTRIBUTES.shape == (6, 4) and PAPER_FORMATION_ATTRIBUTES[1].tolist() == [
        7991,
        1488,
        6.3,
        5.2,
    ]
    assert PAPER_ATTRIBUTE_NAMES == ("rf", "prf", "pw", "asp") and PAPER_ATTRIBUTE_STD == (10, 5, 0.2, 0.2)
    assert PAPER_SIGMAS_DEG == (0.1, 1.0, 1.5, 2.0)


@pytest.mark.parametrize("noise", ["paper", "realistic"])
def test_noiseless_paper_scene_is_exact(noise: str) -> None:
    scene = paper_formation_scene(0, 0.0, noise)  # type: ignore[arg-type]
    m = scene.measurements
    assert len(m) == 18 and m.ndim == 2 and scene.sensors.ndim == 2
    assert m.sensor.tolist() == [s for s in range(3) for _ in range(6)]
    assert m.truth is not None and m.truth.tolist() == list(range(6)) * 3  # row = s * 6 + t
    assert m.azimuth.tolist() == [_exact_bearing(scene, r) for r in range(18)]
    # σθ = 0 silences the bearings only: realistic attribute noise has its own σ_k.
    exact_attributes = np.array_equal(_attribute_matrix(scene), np.tile(PAPER_FORMATION_ATTRIBUTES, (3, 1)))
    assert exact_attributes == (noise == "paper")
    assert dict(scene.attribute_std) == dict(zip(PAPER_ATTRIBUTE_NAMES, PAPER_ATTRIBUTE_STD, strict=True))
    assert np.array_equal(scene.sensors.positions[:, :2], PAPER_FORMATION_SENSORS)
    assert np.all(scene.sensors.sigma_azimuth == 1e-9)  # the network needs a std > 0
    assert scene.true_tuples().tolist() == [[t, 6 + t, 12 + t] for t in range(6)]
    m.validate_against(scene.sensors)


def test_paper_mode_errors_are_uniform_and_attributes_exact() -> None:
    rng = np.random.default_rng(7)
    scenes = [paper_formation_scene(rng, 1.5) for _ in range(300)]
    errors = np.concatenate([_bearing_errors(s) for s in scenes])
    s_theta = math.radians(1.5)
    assert np.all(np.abs(errors) <= s_theta)
    assert errors.std() == pytest.approx(s_theta / math.sqrt(3), rel=0.04)
    assert np.all(scenes[0].sensors.sigma_azimuth == pytest.approx(s_theta / math.sqrt(3)))
    assert all(np.array_equal(_attribute_matrix(s), np.tile(PAPER_FORMATION_ATTRIBUTES, (3, 1))) for s in scenes)
    assert scenes[0].noise == "paper" and scenes[0].sigma_deg == 1.5


def test_realistic_mode_errors_are_gaussian_and_attributes_perturbed() -> None:
    rng = np.random.default_rng(8)
    scenes = [paper_formation_scene(rng, 1.0, "realistic") for _ in range(300)]
    errors = np.concatenate([_bearing_errors(s) for s in scenes])
    s_theta = math.radians(1.0)
    assert errors.std() == pytest.approx(s_theta, rel=0.04)
    assert np.mean(np.abs(errors) > s_theta) == pytest.approx(0.317, abs=0.03)  # none for a uniform error
    assert np.all(scenes[0].sensors.sigma_azimuth == pytest.approx(s_theta))
    deviation = np.concatenate([_attribute_matrix(s) - np.tile(PAPER_FORMATION_ATTRIBUTES, (3, 1)) for s in scenes])
    assert deviation.std(axis=0) == pytest.approx(PAPER_ATTRIBUTE_STD, rel=0.05)


def test_paper_scene_wraps_and_is_reproducible() -> None:
    a, b = paper_formation_scene(3, 2.0, "realistic"), paper_formation_scene(3, 2.0, "realistic")
    assert a.measurements == b.measurements and a.measurements != paper_formation_scene(4, 2.0).measurements
    assert np.all((a.measurements.azimuth > -math.pi) & (a.measurements.azimuth <= math.pi))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"sigma_deg": -0.1}, "sigma_deg"),
        ({"sigma_deg": math.nan}, "sigma_deg"),
        ({"sigma_deg": 1.0, "noise": "gaussian"}, "noise"),
    ],
)
def test_paper_scene_rejects(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(ValueError, match=match):
        paper_formation_scene(0, **kwargs)  # type: ignore[arg-type]


# --------------------------------------------------------------------------- large scene


def test_formation_scene_shapes_counts_and_truth() -> None:
    scene = formation_scene(11, n_sensors=5, n_emitters=200, sigma_deg=0.5, pd=0.8, clutter_per_sensor=10.0)
    m = scene.measurements
    assert m.truth is not None
    assert scene.targets.shape == (200, 2) and scene.sensors.n_sensors == 5 and scene.noise == "realistic"
    assert np.all(np.diff(m.sensor) >= 0)  # sensor-major
    (x0, x1), (y0, y1) = EMITTER_BOX
    assert np.all((scene.targets[:, 0] >= x0) & (scene.targets[:, 0] <= x1))
    assert np.all((scene.targets[:, 1] >= y0) & (scene.targets[:, 1] <= y1))
    reach = np.hypot(*(scene.targets[:, None, :] - scene.sensors.positions[None, :, :2]).transpose(2, 0, 1))
    assert reach.max() < 200e3  # every emitter within the paper's R_max of every sensor
    detected, clutter = int(np.sum(m.truth >= 0)), int(np.sum(m.truth == -1))
    assert abs(detected - 800) < 5 * math.sqrt(1000 * 0.8 * 0.2) and abs(clutter - 50) < 5 * math.sqrt(50)
    for s in range(5):  # each target at most once per sensor, rows not in target order
        labels = m.truth[(m.sensor == s) & (m.truth >= 0)]
        assert len(np.unique(labels)) == len(labels) and not np.all(np.diff(labels) > 0)
    tuples = scene.true_tuples()
    seen = tuples >= 0
    assert seen.sum() == detected and np.all(m.truth[tuples[seen]] == np.nonzero(seen)[0])
    assert _bearing_errors(scene).std() == pytest.approx(math.radians(0.5), rel=0.1)


def test_formation_scene_defaults_and_reproducibility() -> None:
    a = formation_scene(5, n_sensors=3, n_emitters=30)
    assert len(a.measurements) == 90 and np.all(_truth(a) >= 0)  # pd = 1, no clutter
    assert a.measurements == formation_scene(np.random.default_rng(5), n_sensors=3, n_emitters=30).measurements
    assert np.allclose(a.sensors.positions[:, 1], -30e3) and np.ptp(a.sensors.positions[:, 0]) == 100e3


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"n_sensors": 1}, "n_sensors"),
        ({"n_emitters": 0}, "n_emitters"),
        ({"pd": 0.0}, "pd"),
        ({"pd": 1.5}, "pd"),
        ({"clutter_per_sensor": -1.0}, "clutter_per_sensor"),
        ({"sigma_deg": math.inf}, "sigma_deg"),
        ({"n_types": 0}, "n_types"),
    ],
)
def test_formation_scene_rejects(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(ValueError, match=match):
        formation_scene(0, **kwargs)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="seed"):
        formation_scene(None)  # type: ignore[arg-type]


# --------------------------------------------------------------------------- NumPy comparator


def _oracle(
    az: list[NDArray[np.float64]], pos: NDArray[np.float64], attrs: list[NDArray[np.float64]] | None
) -> list[list[int] | None]:
    """METHODS §3 steps 1–5 as loops, baseline sensor 0 (the prototype's logic)."""
    std = np.array(PAPER_ATTRIBUTE_STD)

    def inter(a: int, ta: float, b: int, tb: float) -> NDArray[np.float64] | None:
        ua, ub = np.array([math.cos(ta), math.sin(ta)]), np.array([math.cos(tb), math.sin(tb)])
        cross = ua[0] * ub[1] - ua[1] * ub[0]
        if abs(cross) < 1e-12:
            return None
        w = pos[b] - pos[a]
        return np.asarray(pos[a] + (w[0] * ub[1] - w[1] * ub[0]) / cross * ua)

    out: list[list[int] | None] = []
    for j in range(len(az[0])):
        subsets: dict[int, list[tuple[int, NDArray[np.float64]]]] = {}
        for k in range(1, len(az)):
            subsets[k] = []
            for l_ in range(len(az[k])):
                if (
                    attrs is not None
                    and 1 - np.prod(1 - np.exp(-((attrs[0][j] - attrs[k][l_]) ** 2) / (4 * std**2))) < 0.6
                ):
                    continue
                p = inter(0, az[0][j], k, az[k][l_])
                if p is not None and math.dist(p, pos[0]) <= 200e3 and math.dist(p, pos[k]) <= 200e3:
                    subsets[k].append((l_, p))
        if any(not v for v in subsets.values()):
            out.append(None)
            continue
        ref = min(subsets, key=lambda k: (len(subsets[k]), k))
        best: tuple[float, list[int]] | None = None
        for l_ref, p_ref in subsets[ref]:
            choice = [j] + [
                l_ref if k == ref else min(subsets[k], key=lambda c: math.dist(c[1], p_ref))[0] for k in subsets
            ]
            pairs = itertools.combinations(range(len(az)), 2)
            pts = np.array([p for a, b in pairs if (p := inter(a, az[a][choice[a]], b, az[b][choice[b]])) is not None])
            radius = math.sqrt(np.sum((pts - pts.mean(0)) ** 2) / len(pts))
            if best is None or radius < best[0]:
                best = (radius, choice)
        out.append(best[1] if best else None)
    return out


def test_comparator_noiseless_paper_scene_with_attributes_is_all_correct() -> None:
    az, pos, attrs, std = fnp.per_sensor(paper_formation_scene(0, 0.0))
    chosen, radius = fnp.locate_formation_numpy(az, pos, attrs, std)
    assert chosen.tolist() == [[t, t, t] for t in range(6)]
    assert np.all(radius < 1e-6)


def test_comparator_matches_loop_form_on_paper_scenes() -> None:
    rng = np.random.default_rng(2024)
    for _ in range(20):
        az, pos, attrs, std = fnp.per_sensor(paper_formation_scene(rng, 1.0))
        for gated in (attrs, None):
            chosen, radius = fnp.locate_formation_numpy(az, pos, gated, std)
            expected = _oracle(az, pos, gated)
            assert [None if np.isnan(r) else c for c, r in zip(chosen.tolist(), radius, strict=True)] == expected
            assert np.all(np.isnan(radius) == np.all(chosen[:, 1:] == -1, axis=1))


def test_comparator_unassociated_report() -> None:
    # Sensor 1's only line is parallel to the baseline line: an empty subset, so no association.
    chosen, radius = fnp.locate_formation_numpy(
        [[math.pi / 2], [-math.pi / 2], [math.pi / 2]], [[0, 0], [1e3, 0], [2e3, 0]]
    )
    assert chosen.tolist() == [[0, -1, -1]] and np.isnan(radius[0])
