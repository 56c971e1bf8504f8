"""Angle conventions of the user's data, declared once where a table is built.

The library works in one convention (METHODS §0): azimuth counter-clockwise from +x (east),
elevation up from the horizontal plane, radians. A table built from the user's columns says
which convention those columns use:

* ``angle_unit`` — ``"rad"`` (default) or ``"deg"``: the unit of ``azimuth``,
  ``elevation`` and the per-report noise columns ``sigma_azimuth`` / ``sigma_elevation``;
* ``azimuth_convention`` — ``"math"`` (default: counter-clockwise from east) or
  ``"compass"`` (a bearing clockwise from north, as navigation and most ESM report it):
  ``azimuth = π/2 − bearing``. Elevation is the same in both.

A degrees-as-radians mistake (an azimuth beyond ±2π, an elevation beyond ±π/2) gives no
targets and no other symptom, so it is an error unless ``check_angle_unit=False`` says the
values are meant.
"""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "AngleUnit",
    "AzimuthConvention",
    "check_angle_convention",
    "check_angle_range",
    "from_user_azimuth",
    "from_user_angle",
    "to_user_azimuth",
]

AngleUnit = Literal["rad", "deg"]
AzimuthConvention = Literal["math", "compass"]

#: The largest plausible magnitude, radians, of each angle column.
ANGLE_LIMITS = {"azimuth": (2 * math.pi, "±2π"), "elevation": (math.pi / 2, "±π/2")}


def check_angle_convention(angle_unit: Any, azimuth_convention: Any) -> None:
    """ValueError naming the argument when either is not one of its words."""
    if angle_unit not in ("rad", "deg"):
        raise ValueError(f"angle_unit: must be 'rad' or 'deg', got {angle_unit!r}")
    if azimuth_convention not in ("math", "compass"):
        raise ValueError(f"azimuth_convention: must be 'math' or 'compass', got {azimuth_convention!r}")


def from_user_angle(values: Any, angle_unit: AngleUnit) -> NDArray[np.float64]:
    """An elevation or an angle std in the user's unit, in radians."""
    arr = np.asarray(values, dtype=np.float64)
    return np.radians(arr) if angle_unit == "deg" else arr


def from_user_azimuth(values: Any, angle_unit: AngleUnit, azimuth_convention: AzimuthConvention) -> NDArray[np.float64]:
    """An azimuth in the user's unit and convention, counter-clockwise from east in radians."""
    arr = from_user_angle(values, angle_unit)
    return np.pi / 2 - arr if azimuth_convention == "compass" else arr


def to_user_azimuth(
    azimuth: NDArray[np.float64], angle_unit: AngleUnit, azimuth_convention: AzimuthConvention
) -> NDArray[np.float64]:
    """The inverse of :func:`from_user_azimuth` (a compass bearing wrapped to [0, 360) or [0, 2π))."""
    arr = np.pi / 2 - azimuth if azimuth_convention == "compass" else azimuth
    if azimuth_convention == "compass":
        arr = np.mod(arr, 2 * np.pi)
    return np.degrees(arr) if angle_unit == "deg" else arr


def check_angle_range(name: str, values: NDArray[np.float64], where: str = "") -> None:
    """ValueError when ``values`` (radians, column ``name``) go beyond the plausible range:
    almost surely degrees read as radians. ``where`` prefixes the message (a file name)."""
    limit, text = ANGLE_LIMITS[name]
    outside = np.abs(values) > limit * (1 + 1e-12)  # NaN (a 2-D elevation) compares False
    if outside.any():
        i = int(np.flatnonzero(outside)[0])
        raise ValueError(
            f"{where}{name}[{i}] = {float(values[i])!r} rad is beyond {text}: were the angles given in degrees? "
            "Declare them with angle_unit='deg', or pass check_angle_unit=False to keep them as they are"
        )
