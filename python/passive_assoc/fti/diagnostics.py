"""What the initiation reports about its own run: the names of its stages' counts and times,
and the warning when pruning leaves no candidate (a scene that usually has a fixable cause)."""

from __future__ import annotations

import warnings

__all__ = ["STAGE_COUNT_NAMES", "STAGE_SECOND_NAMES", "empty_stage", "warn_if_no_candidate"]

#: The stages of :class:`InitiationDiagnostics` ``stage_counts``, in pipeline order.
STAGE_COUNT_NAMES = (
    "raw",
    "ray_gate",
    "behind",
    "v_max",
    "fitted",
    "chi2_gate",
    "supported",
    "optima",
    "merged",
    "detected",
)
#: The timed stages (``stage_seconds`` calls the last one ``"final"``).
STAGE_SECOND_NAMES = ("candidates", "fit", "support", "descent", "detection", "final_fit")


#: What usually empties each pruning stage, for the warning below.
_EMPTIED_BY = {
    "raw": "a sensor of every pair has an empty outer scan",
    "ray_gate": "no two rays meet within ray_gate_sigmas: are the angles radians, the sensor positions metres?",
    "behind": "every crossing is behind a sensor: check the azimuth convention and the sensor positions",
    "v_max": "every candidate moves faster than v_max: raise v_max, or check the times' unit (seconds)",
    "fitted": "no candidate fit converged",
    "chi2_gate": "no candidate fit passes chi2_gate: are the sensors' stds right?",
    "supported": "no candidate is seen in more than n_detect scans: lower n_detect, or check the stds and times",
}


def empty_stage(counts: dict[str, int]) -> str | None:
    """When no candidate survives pruning, why in words: the stage that emptied, the funnel
    and the usual cause (units, conventions, a too-tight bound); None when some survived."""
    for stage, hint in _EMPTIED_BY.items():
        if counts[stage] == 0:
            funnel = " -> ".join(f"{name} {counts[name]}" for name in STAGE_COUNT_NAMES[:7])
            return f"no candidate survived the {stage!r} stage ({funnel}), so no track can be initiated: {hint}"
    return None


def warn_if_no_candidate(message: str) -> None:
    """A scene where no candidate survives pruning gives no track for a reason the user can
    usually fix: say so (``message`` from :func:`empty_stage`)."""
    warnings.warn(message, UserWarning, stacklevel=3)
