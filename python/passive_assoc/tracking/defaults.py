"""The trackers' defaults, declared once: the built-in tracker, the Stone Soup one
(:mod:`passive_assoc.interop.stonesoup_tracking`) and ``passive-assoc track`` read them."""

from __future__ import annotations

#: Seconds of unassociated reports an initiation takes.
WINDOW = 60.0
#: The constant-velocity model's acceleration noise density, m²/s³ per axis.
PROCESS_NOISE = 0.05
#: The association gate, a Mahalanobis distance.
MISSED_DISTANCE = 4.0
#: Steps without an update before a track is deleted.
DELETE_AFTER = 12
