"""Formation-target scenes with emitter attributes (METHODS §3, EXPERIMENTS ``formation``).

:func:`paper_formation_scene` is the paper's experiment: three 2-D bearing sensors, six
emitters, one snapshot, Pd = 1, no false bearings, in the two noise modes METHODS §3 asks for:

* ``"paper"``: bearing errors uniform on [−σθ, +σθ] and attribute values unperturbed (σ_k
  enters only the support of eq. 3). The paper's tables are reproducible only this way.
* ``"realistic"``: Gaussian bearing errors with std σθ and Gaussian attribute noise with
  std σ_k.

:func:`formation_scene` is a larger scene for benchmarks and tests. Readings chosen here:

* Sensors on a straight baseline: ``x = linspace(−50, 50, n_sensors)`` km, ``y = −30`` km.
* Emitters uniform in the box :data:`EMITTER_BOX` (x ∈ [−60, 60] km, y ∈ [20, 120] km): in
  front of the sensors, and within 186 km of each, so inside the paper's R_max = 200 km.
* Attributes: ``n_types`` emitter types with centres uniform in :data:`TYPE_RANGES`; each
  emitter takes a type and adds a Gaussian spread of ``type_spread · σ_k``, so that emitters
  of one type look alike (their support is often above η) and emitters of different types
  do not. Each report adds Gaussian noise σ_k (:data:`PAPER_ATTRIBUTE_STD`).
* Each (sensor, emitter) report is kept with probability ``pd``. Each sensor adds
  Poisson(``clutter_per_sensor``) false bearings, uniform over the sector the box covers
  from it, with attributes uniform in :data:`TYPE_RANGES`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from .._validation import as_float_scalar, as_int_scalar, readonly
from ..data import MeasurementTable, SensorNetwork
from .scenario import Seed, _check_seed, wrap_angle

__all__ = [
    "PAPER_FORMATION_SENSORS",
    "PAPER_FORMATION_TARGETS",
    "PAPER_FORMATION_ATTRIBUTES",
    "PAPER_ATTRIBUTE_NAMES",
    "PAPER_ATTRIBUTE_STD",
    "PAPER_SIGMAS_DEG",
    "EMITTER_BOX",
    "TYPE_RANGES",
    "FormationScene",
    "paper_formation_scene",
    "formation_scene",
]

NoiseMode = Literal["paper", "realistic"]

#: The paper's sensors (x, y), metres.
PAPER_FORMATION_SENSORS = readonly(np.array([[-80.0, -30.0], [-30.0, -30.0], [20.0, -30.0]]) * 1e3)
#: The paper's six targets (x, y), metres.
PAPER_FORMATION_TARGETS = readonly(
    np.array([[-27.5, 60.0], [-22.5, 60.0], [-17.5, 60.0], [-60.0, 70.0], [-45.0, 70.0], [0.0, 70.0]]) * 1e3
)
#: The targets' attributes: RF (MHz), PRF (Hz), PW (µs), ASP (s), one row per target.
PAPER_FORMATION_ATTRIBUTES = readonly(
    np.array(
        [
            [4008.0, 1005.0, 4.9, 2.2],
            [7991.0, 1488.0, 6.3, 5.2],
            [6011.0, 1211.0, 5.5, 4.3],
            [3987.0, 994.0, 5.1, 1.8],
            [4002.0, 1007.0, 4.6, 1.9],
            [6000.0, 1202.0, 5.3, 4.5],
        ]
    )
)
PAPER_ATTRIBUTE_NAMES = ("rf", "prf", "pw", "asp")
#: σ_k of each attribute, in the order of :data:`PAPER_ATTRIBUTE_NAMES`.
PAPER_ATTRIBUTE_STD = (10.0, 5.0, 0.2, 0.2)
#: The bearing noise levels σθ of the paper's tables, degrees.
PAPER_SIGMAS_DEG = (0.1, 1.0, 1.5, 2.0)

#: Where :func:`formation_scene` puts its emitters: ((x_min, x_max), (y_min, y_max)), metres.
EMITTER_BOX = ((-60e3, 60e3), (20e3, 120e3))
#: Range of each attribute's type centres (and of clutter attributes) in :func:`formation_scene`.
TYPE_RANGES = ((2000.0, 10000.0), (500.0, 3000.0), (1.0, 20.0), (1.0, 10.0))
BASELINE_Y = -30e3
BASELINE_SPREAD = 100e3

# SensorNetwork needs a std > 0; a noiseless scene (σθ = 0) declares this instead. Any ML
# weighting stays uniform, and a χ² gate is as tight as the data are exact.
_NOISELESS_SIGMA = 1e-9


@dataclass(frozen=True, eq=False)
class FormationScene:
    """One snapshot of 2-D bearings with emitter attributes, with its truth.

    Attributes
    ----------
    measurements : MeasurementTable
        Bearings wrapped to (−π, π], the attribute columns of ``attribute_std``, and ``truth``
        = target index or −1 for a false bearing. Rows are sensor-major.
    sensors : SensorNetwork
        2-D. ``sigma_azimuth`` is the bearing errors' actual standard deviation (σθ/√3 in
        paper mode, σθ in realistic mode), because the ML triangulation's covariance and any
        χ² gate read it; a noiseless scene declares 1e-9 rad.
    targets : numpy.ndarray, shape (N, 2)
        True positions, metres.
    attribute_std : mapping of str to float
        σ_k per attribute, the std that eq. 3 uses (whether or not the values are perturbed).
    noise : {"paper", "realistic"}
    sigma_deg : float
        σθ in degrees: the half-width of the uniform error in paper mode, the std otherwise.
    """

    measurements: MeasurementTable
    sensors: SensorNetwork
    targets: NDArray[np.float64]
    attribute_std: Mapping[str, float]
    noise: NoiseMode
    sigma_deg: float

    def true_tuples(self) -> NDArray[np.int64]:
        """Row of each target's report at each sensor, −1 where the sensor missed it: (N, S)."""
        m = self.measurements
        out = np.full((len(self.targets), self.sensors.n_sensors), -1, dtype=np.int64)
        truth = np.asarray(m.truth)
        rows = np.flatnonzero(truth >= 0)
        out[truth[rows], m.sensor[rows]] = rows
        return out


def _check_sigma_deg(sigma_deg: float) -> float:
    sigma = as_float_scalar("sigma_deg", sigma_deg, finite=True)
    if sigma < 0:
        raise ValueError(f"sigma_deg: must be >= 0, got {sigma_deg!r}")
    return sigma


def _true_bearings(sensors_xy: NDArray[np.float64], targets: NDArray[np.float64]) -> NDArray[np.float64]:
    """(S, N) exact bearings of every target from every sensor."""
    rel = targets[None, :, :] - sensors_xy[:, None, :]
    return np.arctan2(rel[..., 1], rel[..., 0])


def _wrap(azimuth: NDArray[np.float64]) -> NDArray[np.float64]:
    """Wrap to (−π, π], leaving in-range values bit-exact (wrap_angle's arithmetic can move them
    by an ulp, and a noiseless scene should hold the exact bearings)."""
    inside = (azimuth > -math.pi) & (azimuth <= math.pi)
    return np.where(inside, azimuth, wrap_angle(azimuth))


def _network(sensors_xy: NDArray[np.float64], std: float) -> SensorNetwork:
    return SensorNetwork.planar(sensors_xy, std if std > 0 else _NOISELESS_SIGMA)


def _std_mapping(std: NDArray[np.float64]) -> Mapping[str, float]:
    return MappingProxyType({name: float(s) for name, s in zip(PAPER_ATTRIBUTE_NAMES, std, strict=True)})


def paper_formation_scene(rng_or_seed: Seed, sigma_deg: float, noise: NoiseMode = "paper") -> FormationScene:
    """The paper's experiment (METHODS §3): 3 sensors, 6 emitters, one snapshot.

    Parameters
    ----------
    rng_or_seed : int or numpy.random.Generator
        Required; draws the bearing errors (S × N, sensor-major), then in realistic mode the
        attribute errors (S × N × K).
    sigma_deg : float
        σθ in degrees, >= 0 (the paper's: :data:`PAPER_SIGMAS_DEG`).
    noise : {"paper", "realistic"}
        See the module docstring.

    Returns
    -------
    FormationScene
        Pd = 1 and no false bearings, so row ``s * 6 + t`` is target ``t`` at sensor ``s``.
    """
    sigma = _check_sigma_deg(sigma_deg)
    if noise not in ("paper", "realistic"):
        raise ValueError(f"noise: expected 'paper' or 'realistic', got {noise!r}")
    rng = _check_seed(rng_or_seed)
    s_theta = math.radians(sigma)
    truth_az = _true_bearings(PAPER_FORMATION_SENSORS, PAPER_FORMATION_TARGETS)
    n_sensors, n_targets = truth_az.shape
    attrs = np.broadcast_to(PAPER_FORMATION_ATTRIBUTES, (n_sensors, n_targets, len(PAPER_ATTRIBUTE_NAMES)))
    attr_std = np.array(PAPER_ATTRIBUTE_STD)
    if noise == "paper":
        azimuth = truth_az + rng.uniform(-s_theta, s_theta, truth_az.shape)
        network_std = s_theta / math.sqrt(3.0)  # the std of U(−σθ, σθ)
    else:
        azimuth = truth_az + s_theta * rng.standard_normal(truth_az.shape)
        attrs = attrs + attr_std * rng.standard_normal(attrs.shape)
        network_std = s_theta
    flat_attrs = attrs.reshape(-1, attrs.shape[-1])
    table = MeasurementTable.from_arrays(
        np.repeat(np.arange(n_sensors), n_targets),
        np.zeros(n_sensors * n_targets),
        _wrap(azimuth.ravel()),
        attributes={name: flat_attrs[:, k] for k, name in enumerate(PAPER_ATTRIBUTE_NAMES)},
        truth=np.tile(np.arange(n_targets), n_sensors),
    )
    return FormationScene(
        measurements=table,
        sensors=_network(PAPER_FORMATION_SENSORS, network_std),
        targets=PAPER_FORMATION_TARGETS,
        attribute_std=_std_mapping(attr_std),
        noise=noise,
        sigma_deg=sigma,
    )


def _check_large_scene(
    n_sensors: int, n_emitters: int, pd: float, clutter_per_sensor: float, n_types: int, type_spread: float
) -> tuple[int, int, float, float, int, float]:
    n_sensors = as_int_scalar("n_sensors", n_sensors, minimum=2)
    n_emitters = as_int_scalar("n_emitters", n_emitters, minimum=1)
    n_types = as_int_scalar("n_types", n_types, minimum=1)
    p = as_float_scalar("pd", pd, finite=True)
    if not 0 < p <= 1:
        raise ValueError(f"pd: must be in (0, 1], got {pd!r}")
    clutter = as_float_scalar("clutter_per_sensor", clutter_per_sensor, finite=True)
    if clutter < 0:
        raise ValueError(f"clutter_per_sensor: must be >= 0, got {clutter_per_sensor!r}")
    spread = as_float_scalar("type_spread", type_spread, finite=True)
    if spread < 0:
        raise ValueError(f"type_spread: must be >= 0, got {type_spread!r}")
    return n_sensors, n_emitters, p, clutter, n_types, spread


def _emitters(
    rng: np.random.Generator, n_emitters: int, n_types: int, spread: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Positions (N, 2) and attributes (N, K): a type centre plus a spread of ``spread · σ_k``."""
    (x0, x1), (y0, y1) = EMITTER_BOX
    positions = np.column_stack([rng.uniform(x0, x1, n_emitters), rng.uniform(y0, y1, n_emitters)])
    low, high = np.array(TYPE_RANGES).T
    centres = rng.uniform(low, high, (n_types, len(TYPE_RANGES)))
    kind = rng.integers(0, n_types, n_emitters)
    attrs = centres[kind] + spread * np.array(PAPER_ATTRIBUTE_STD) * rng.standard_normal((n_emitters, len(low)))
    return positions, attrs


def _box_sector(position: NDArray[np.float64]) -> tuple[float, float]:
    """Bearing interval the emitter box covers from ``position`` (the box is in front, so no wrap)."""
    corners = np.array([[x, y] for x in EMITTER_BOX[0] for y in EMITTER_BOX[1]]) - position
    bearings = np.arctan2(corners[:, 1], corners[:, 0])
    return float(bearings.min()), float(bearings.max())


def _sensor_reports(
    rng: np.random.Generator,
    position: NDArray[np.float64],
    emitters: tuple[NDArray[np.float64], NDArray[np.float64]],
    s_theta: float,
    pd: float,
    clutter: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """One sensor's bearings, attributes (n, K) and truth, rows in a random order."""
    targets, attrs = emitters
    bearing = _true_bearings(position[None, :], targets)[0] + s_theta * rng.standard_normal(len(targets))
    noisy = attrs + np.array(PAPER_ATTRIBUTE_STD) * rng.standard_normal(attrs.shape)
    seen = np.flatnonzero(rng.random(len(targets)) < pd)
    n_false = int(rng.poisson(clutter))
    low, high = np.array(TYPE_RANGES).T
    false_bearing = rng.uniform(*_box_sector(position), n_false)
    false_attrs = rng.uniform(low, high, (n_false, len(low)))
    # Shuffled so that a row's index within a sensor says nothing about its target.
    order = rng.permutation(len(seen) + n_false)
    return (
        np.concatenate([bearing[seen], false_bearing])[order],
        np.concatenate([noisy[seen], false_attrs])[order],
        np.concatenate([seen, np.full(n_false, -1)]).astype(np.int64)[order],
    )


def formation_scene(
    rng_or_seed: Seed,
    n_sensors: int = 5,
    n_emitters: int = 200,
    sigma_deg: float = 0.5,
    pd: float = 1.0,
    clutter_per_sensor: float = 0.0,
    *,
    n_types: int = 8,
    type_spread: float = 2.0,
) -> FormationScene:
    """A large scene of emitters in front of a line of sensors (see the module docstring).

    Parameters
    ----------
    rng_or_seed : int or numpy.random.Generator
        Required; draws the emitters, then each sensor's reports in sensor order.
    n_sensors : int
        S >= 2, evenly spaced along the baseline.
    n_emitters : int
        N >= 1 emitters in :data:`EMITTER_BOX`.
    sigma_deg : float
        Gaussian bearing noise std σθ, degrees, >= 0.
    pd : float
        Probability in (0, 1] that a sensor reports an emitter.
    clutter_per_sensor : float
        Mean number of false bearings per sensor (Poisson), >= 0.
    n_types : int
        Number of emitter types the attributes are drawn around, >= 1.
    type_spread : float
        Std of an emitter's attributes about its type's centre, in units of σ_k, >= 0.

    Returns
    -------
    FormationScene
        Realistic noise; rows sensor-major, in a random order within each sensor.
    """
    sigma = _check_sigma_deg(sigma_deg)
    n_sensors, n_emitters, p, clutter, n_types, spread = _check_large_scene(
        n_sensors, n_emitters, pd, clutter_per_sensor, n_types, type_spread
    )
    rng = _check_seed(rng_or_seed)
    half = BASELINE_SPREAD / 2
    sensors_xy = np.column_stack([np.linspace(-half, half, n_sensors), np.full(n_sensors, BASELINE_Y)])
    emitters = _emitters(rng, n_emitters, n_types, spread)
    s_theta = math.radians(sigma)
    parts = [_sensor_reports(rng, sensors_xy[s], emitters, s_theta, p, clutter) for s in range(n_sensors)]
    attrs = np.concatenate([part[1] for part in parts]).reshape(-1, len(PAPER_ATTRIBUTE_NAMES))
    table = MeasurementTable.from_arrays(
        np.concatenate([np.full(len(part[0]), s) for s, part in enumerate(parts)]),
        np.zeros(len(attrs)),
        _wrap(np.concatenate([part[0] for part in parts])),
        attributes={name: attrs[:, k] for k, name in enumerate(PAPER_ATTRIBUTE_NAMES)},
        truth=np.concatenate([part[2] for part in parts]),
    )
    return FormationScene(
        measurements=table,
        sensors=_network(sensors_xy, s_theta),
        targets=readonly(emitters[0]),
        attribute_std=_std_mapping(np.array(PAPER_ATTRIBUTE_STD)),
        noise="realistic",
        sigma_deg=sigma,
    )
