"""What the initiation reports about its own run: the names of its stages' counts and times,
the warning when pruning leaves no candidate (a scene that usually has a fixable cause), and
the message when the formation stops at ``max_candidates``, in seconds and scan slots."""

from __future__ import annotations

from .._warn import warn_at_caller

__all__ = ["STAGE_COUNT_NAMES", "STAGE_SECOND_NAMES", "empty_stage", "limit_message", "warn_if_no_candidate"]

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
    warn_at_caller(message, UserWarning)


#: Fitted candidates from which :func:`limit_message` prices a candidate: with fewer, the
#: call's fixed costs (tables, indexes) would dominate the figure.
PRICED_FROM = 10_000


def limit_message(
    limit: str, slots: tuple[int, int] | None, seconds: dict[str, float], counts: dict[str, int], n_tracks: int
) -> str:
    """The result's message when the formation stopped at its limit (``limit``, the core's
    words): how long the formation ran and how far through its scan ``slots`` it got, what a
    fitted candidate cost this call with its tests and gates (so what a larger
    ``max_candidates`` would cost; from :data:`PRICED_FROM` candidates on), and the tracks
    found. ``seconds`` and ``counts`` are the diagnostics' ``stage_seconds`` and
    ``stage_counts``."""
    spent = seconds["candidates"] + seconds["fit"] + seconds["support"]
    where = f"after {spent:.1f} s"
    if slots is not None:
        where += f", {slots[0]} of its {slots[1]} scan slots formed in full"
    fitted = counts["fitted"]
    cost = ""
    if fitted >= PRICED_FROM:
        each = spent / fitted
        cost = (
            f", {each * 1e6:.1f} µs a fitted candidate with its tests and gates ({each * 1e5:.2g} s per 100 000 more)"
        )
    return (
        f"the candidate formation stopped at its limit {where}{cost}: {limit}; "
        f"{n_tracks} track(s) from the candidates formed until then"
    )
