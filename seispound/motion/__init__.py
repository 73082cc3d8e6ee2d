"""Ground motions: PEER ``.AT2`` reading (ObsPy plugin), records and preparation.

Public API
----------
Record
    Immutable ground-acceleration record (m/s²) with provenance.
read_record
    Read one component from any ObsPy-readable file (and PEER ``.AT2``).
ground_acceleration
    Acceleration on an analysis grid ``t = 0, dt, ..., duration``.
G_STANDARD
    Standard gravity, 9.80665 m/s² (3rd CGPM, 1901).
"""

from seispound.motion.record import G_STANDARD, Record, ground_acceleration, read_record

__all__ = ["Record", "read_record", "ground_acceleration", "G_STANDARD"]
