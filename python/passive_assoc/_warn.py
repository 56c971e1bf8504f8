"""Warnings that point at the user's line: the first frame outside this package, however many
of its functions the call went through (argument checkers, one-line conveniences such as
``initiate_tracks``, the readers' helpers). A fixed ``stacklevel`` is right for one path only."""

from __future__ import annotations

import os
import sys
import warnings

__all__ = ["warn_at_caller"]

#: This package's directory, with a separator: a frame whose file lies under it is the package's.
_PACKAGE = os.path.dirname(os.path.abspath(__file__)) + os.sep


def warn_at_caller(message: str, category: type[Warning] = UserWarning) -> None:
    """``warnings.warn(message, category)`` attributed to the first frame outside the package
    (the outermost of the package's frames when every frame is the package's)."""
    level, frame = 1, sys._getframe(0)  # level 1: this function, as `stacklevel` counts
    while frame.f_back is not None and os.path.abspath(frame.f_code.co_filename).startswith(_PACKAGE):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, category, stacklevel=level)
