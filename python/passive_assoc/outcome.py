"""What every method's result says first, as SciPy's ``OptimizeResult`` does: why the call
stopped (:attr:`Outcome.termination`), whether it met its goal (:attr:`Outcome.success`) and
that in words (:attr:`Outcome.message`).

Every result class of the five methods (initiation, static association, formation location,
track-to-track association) and of the S-D solver derives from :class:`Outcome`; its other
fields come after these three, and its diagnostics are typed fields, not dictionaries.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["COMPLETED", "Outcome"]

#: The termination of a call that ran to its end with nothing to report.
COMPLETED = "completed"


@dataclass(frozen=True, kw_only=True)
class Outcome:
    """Why a call stopped, whether it met its goal, and in words.

    Attributes
    ----------
    termination : str
        A short name for why the call stopped: ``"completed"`` for a method that ran to its
        end; a solver's own reason otherwise (each result class lists its values).
    success : bool
        True when the call met its goal (an S-D solver: optimality proven or the gap within
        its tolerance). A result with ``success=False`` is still a valid answer (every input
        is accounted for), but not the one the method aims at; :attr:`message` says why.
    message : str
        :attr:`termination` in words.
    """

    termination: str
    success: bool
    message: str
