"""The process's heap, tuned for the plant's step: :func:`tune_heap`.

Each plant step allocates and frees blocks of a few hundred kB (the contact problem,
its Jacobians, the solver's workspace). With glibc's default thresholds (128 kB) a
block that large is mmap-ed and unmapped at every step, and the heap's free top is
given back to the system and taken again, so every step touches fresh pages: a
`fill_bin` run took about 74,000 minor page faults, and a run was 10-20 % slower
than the same run in a process that happened to have freed a large block before
(glibc then raises its thresholds by itself; computing the cell's convex hulls
did that, until they came from the disk memo). Fixed thresholds make the step's
memory reused from one step to the next in every process: about 400 faults a run
(figures: bench/README.md, "Speed, round three").

Only on glibc. It overrides glibc's ``MALLOC_*_THRESHOLD_`` variables, which Dask
sets for its workers (a trim threshold of 64 kB, to give memory back: a batch run
would fault at every step again); ``OMTP_DRAKE_HEAP=glibc`` keeps glibc's settings.
"""

from __future__ import annotations

import ctypes
import os
import platform

#: Blocks below this are taken from the heap, not mmap-ed (glibc's M_MMAP_THRESHOLD).
MMAP_THRESHOLD = 4 << 20
#: Free memory at the heap's top kept for the next step (glibc's M_TRIM_THRESHOLD).
TRIM_THRESHOLD = 32 << 20

#: glibc's mallopt parameters.
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
#: The environment variable that keeps glibc's settings, and its value for that.
OPT_OUT = ("OMTP_DRAKE_HEAP", "glibc")


def tune_heap() -> bool:
    """Sets the thresholds (module doc) for this process; whether they were set (False
    off glibc or with :data:`OPT_OUT`). Harmless to call again."""
    name, keep = OPT_OUT
    if platform.libc_ver()[0] != "glibc" or os.environ.get(name) == keep:
        return False
    mallopt = ctypes.CDLL(None).mallopt
    mallopt.argtypes, mallopt.restype = (ctypes.c_int, ctypes.c_int), ctypes.c_int
    mmap_set = mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD)
    return bool(mmap_set) and bool(mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD))
