"""Assignment: sparse S-D assignment and dense 2-D linear assignment in the Rust core."""

from __future__ import annotations

from .linear import linear_assignment
from .sd import SdAssignment, assign_sd

__all__ = ["SdAssignment", "assign_sd", "linear_assignment"]
