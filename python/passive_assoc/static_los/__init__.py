"""Static line-of-sight association of one scan (METHODS §2)."""

from __future__ import annotations

from .associator import StaticAssociation, associate_static, default_false_alarm_density, enumerate_candidates

__all__ = ["StaticAssociation", "associate_static", "default_false_alarm_density", "enumerate_candidates"]
