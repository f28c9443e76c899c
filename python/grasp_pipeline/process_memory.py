"""Memory settings of a process that runs the simulated pick loop.

Each camera frame allocates and frees a few arrays of several megabytes (depth, points, colour,
their float64 copies). With glibc's defaults such an array is mapped fresh from the kernel and
unmapped when freed, so every frame pays for zeroing new pages again — measured at about 6 % of
a clearing round's CPU. :func:`keep_large_allocations` lets the heap serve and keep them
instead (the process keeps its peak heap, a few hundred megabytes at most for a round).

Python's cyclic garbage collector also runs its young-generation pass every few hundred
allocations of containers (a physics step allocates dozens): :func:`keep_large_allocations`
lets it run less often. (Nothing is frozen out of its sight: objects of extension modules
left in cycles must still be reclaimed before the interpreter exits.)

Neither changes a value anything computes: they decide where memory comes from and when
cyclic garbage is reclaimed (objects are still freed by reference counting at once).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import logging
import os

log = logging.getLogger(__name__)

#: glibc's ``mallopt`` parameters (malloc.h).
_M_TRIM_THRESHOLD, _M_TOP_PAD, _M_MMAP_THRESHOLD = -1, -2, -3
#: Allocations up to this size come from the heap (glibc's largest allowed value on 64 bit).
MMAP_THRESHOLD_BYTES = 32 * 1024 * 1024
#: Free memory at the heap's top is returned to the kernel only beyond this.
TRIM_THRESHOLD_BYTES = 512 * 1024 * 1024
#: The heap grows by at least this much at a time.
TOP_PAD_BYTES = 64 * 1024 * 1024
#: Allocations of containers between two young-generation collections (Python's default: 700).
GC_YOUNG_THRESHOLD = 20000
#: Set to 0 to keep the defaults (for comparisons).
ENV_VAR = "GRASP_PIPELINE_TUNE_MEMORY"


def keep_large_allocations() -> bool:
    """Apply the settings of the module doc to this process; False where they do not apply (not
    glibc, or switched off by ``GRASP_PIPELINE_TUNE_MEMORY=0``). Call it once, early: it affects
    only what is allocated afterwards."""
    if os.environ.get(ENV_VAR, "1").strip() == "0":
        return False
    _, mid, old = gc.get_threshold()
    gc.set_threshold(GC_YOUNG_THRESHOLD, mid, old)
    return _tune_glibc_malloc()


def _tune_glibc_malloc() -> bool:
    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name) if name else None
        mallopt = getattr(libc, "mallopt", None)
    except OSError:
        mallopt = None
    if mallopt is None:
        log.debug("no glibc mallopt here: allocation settings left as they are")
        return False
    accepted = [mallopt(param, value) == 1 for param, value in (  # each tried, whatever the others
        (_M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES), (_M_TRIM_THRESHOLD, TRIM_THRESHOLD_BYTES),
        (_M_TOP_PAD, TOP_PAD_BYTES))]
    ok = all(accepted)
    if not ok:
        log.debug("mallopt refused a setting: allocation settings partly left as they are")
    return ok
