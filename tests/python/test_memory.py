# Memory is released: a hundred reconstructions of a small sphere do not grow the process.
import gc
import os

import levelfuse
from conftest import sphere_scans


def resident_bytes():
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def reconstruct_and_use(maps):
    result = levelfuse.reconstruct(maps, voxel_size=0.05, fit=False)
    result.mesh()
    result.vdb_bytes()
    result.grid.active_voxels()
    return result


def growth_over(runs, maps, keep):
    gc.collect()
    before = resident_bytes()
    for _ in range(runs):
        result = reconstruct_and_use(maps)
        if keep is not None:
            keep.append(result)
    del result
    gc.collect()
    return resident_bytes() - before


def test_a_hundred_reconstructions_do_not_leak():
    maps = sphere_scans(pixels=32)
    growth_over(10, maps, None)  # the allocators' pools settle
    released = growth_over(100, maps, None)
    # The ruler: what a run holds when its result is kept, as a leak would keep it.
    kept = []
    per_run = growth_over(20, maps, kept) / 20
    print(f"resident memory over 100 reconstructions: {released / 1e6:.2f} MB; "
          f"{per_run / 1e6:.2f} MB a run with its result kept")
    assert per_run > 1e6
    assert released < 100 * per_run / 20
