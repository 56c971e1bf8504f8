"""Interop with other tracking libraries, each an optional extra: :mod:`.stonesoup` (detections
and tracks both ways) and :mod:`.stonesoup_tracking` (the initiator inside a Stone Soup
tracker; importing it needs Stone Soup)."""
