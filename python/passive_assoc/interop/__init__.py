"""Interop with other tracking libraries, each an optional extra: :mod:`.stonesoup`."""
