# Memory is released: a hundred reconstructions of a small sphere leave the heap as it was.
import ctypes
import gc

import levelfuse
from conftest import sphere_scans


class _Mallinfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in (
        "arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks", "fordblks", "keepcost")]


_libc = ctypes.CDLL("libc.so.6")
_libc.mallinfo2.restype = _Mallinfo2


def live_heap_bytes():
    """Bytes the process's allocations hold now, every arena and mapping (glibc's mallinfo2): unlike
    the resident size, it does not depend on what the allocator keeps for later."""
    gc.collect()
    info = _libc.mallinfo2()
    return info.uordblks + info.hblkhd


def reconstruct_and_use(maps):
    result = levelfuse.reconstruct(maps, voxel_size=0.05, fit=False)
    result.mesh()
    result.vdb_bytes()
    result.grid.active_voxels()
    return result


def growth_over(runs, maps, keep):
    before = live_heap_bytes()
    for _ in range(runs):
        result = reconstruct_and_use(maps)
        if keep is not None:
            keep.append(result)
    del result
    return live_heap_bytes() - before


def test_a_hundred_reconstructions_do_not_leak():
    maps = sphere_scans(pixels=32)
    growth_over(5, maps, None)  # one-time allocations: pools, caches, registries
    released = growth_over(100, maps, None)
    # The ruler: what a run holds when its result is kept, as a leak would keep it.
    kept = []
    per_run = growth_over(10, maps, kept) / 10
    print(f"heap over 100 reconstructions: {released / 1e6:+.3f} MB; {per_run / 1e6:.2f} MB a run with its "
          f"result kept")
    assert per_run > 1e6
    assert released < per_run
