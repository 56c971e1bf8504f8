"""A progress bar for one long compiled call. The core reports ``(stage, fraction)`` as it goes
(the binding forwards a report at most every 0.2 s, and each change of stage); this shows them
on one ``tqdm`` bar, a stage at a time, and numbers the passes of a pipeline that runs its
stages more than once."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
from tqdm import tqdm

__all__ = ["ProgressArg", "StageBar", "reporting"]

#: A stage's percentage and the call's elapsed time (a rate or ETA across stages would mislead).
BAR = "{desc}{percentage:3.0f}%|{bar}| {elapsed}"

#: Seconds a call runs before its bar appears when ``progress`` is None: short calls stay quiet.
AUTO_DELAY = 2.0


class StageBar:
    """The callable the core reports to, drawing one bar per call.

    ``first_stage``, when given, begins a new pass each time it comes back ("pass 2:
    candidates"); without it the stage is the whole label. With
    ``always`` the bar is drawn from the first report on any stream; otherwise only on a
    terminal, and only once the call has run :data:`AUTO_DELAY` seconds (no bar is even built
    before: a short call pays one clock reading a report)."""

    def __init__(self, first_stage: str | None, *, always: bool) -> None:
        self.first_stage = first_stage
        self.always = always
        self.started = time.monotonic()
        self.passes = 0
        self.stage: str | None = None
        self.bar: tqdm[Any] | None = None

    def __call__(self, stage: str, fraction: float) -> None:
        percent = round(100 * min(max(fraction, 0.0), 1.0))
        if stage != self.stage:
            self.passes += stage == self.first_stage or self.passes == 0
            self.stage = stage
            if self.bar is not None:  # a new stage is drawn at once, whatever the interval
                # update() also moves tqdm's last drawn count back with a negative step; setting
                # n would leave it at the old stage's end, and the new stage would not redraw.
                self.bar.update(percent - self.bar.n)
                self.bar.set_description(self._label())
                return
        if self.bar is None:
            if not self.always and time.monotonic() - self.started < AUTO_DELAY:
                return
            self.bar = tqdm(
                desc=f"{self._label()}: ",
                total=100,
                file=sys.stderr,
                leave=False,
                miniters=1,
                bar_format=BAR,
                disable=False if self.always else None,  # None: only on a terminal
            )
        # update(), not n = ... and refresh(): update() keeps tqdm's redraw interval.
        self.bar.update(percent - self.bar.n)

    def _label(self) -> str:
        return f"{self.stage}" if self.first_stage is None else f"pass {self.passes}: {self.stage}"

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


#: What a ``progress`` argument may be: a bar on a terminal after a while (None), always
#: (True), never (False), or a callable of your own that receives the ``(stage, fraction)``
#: reports instead (rate-limited by the binding).
ProgressArg = bool | None | Callable[[str, float], object]


@contextmanager
def reporting(progress: ProgressArg, first_stage: str | None = None) -> Iterator[Callable[[str, float], object] | None]:
    """What the core reports to for ``progress`` (checked), closing the bar it draws, if any."""
    if isinstance(progress, np.bool_):
        progress = bool(progress)
    if progress is False:
        yield None  # the core then reports to nobody
    elif progress is None or progress is True:
        bar = StageBar(first_stage, always=progress is True)
        try:
            yield bar
        finally:
            bar.close()
    elif callable(progress):
        yield progress
    else:
        kind = type(progress).__name__
        raise TypeError(f"progress: expected a bool, None or a callable (stage, fraction), got {kind} {progress!r}")
