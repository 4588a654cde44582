# Ctrl-C stops a reconstruction cleanly, and the module keeps working.
import os
import signal
import threading
import time

import pytest

import levelfuse
from conftest import sphere_scans


def interrupt_after(seconds):
    timer = threading.Timer(seconds, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    return timer


def test_ctrl_c_raises_keyboard_interrupt_and_leaves_the_module_usable():
    maps = sphere_scans(pixels=96, noise=0.01)
    stages = []
    timer = interrupt_after(0.5)
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        levelfuse.reconstruct(maps, voxel_size=0.01, beta=1.0, progress=lambda p: stages.append(p["stage"]))
    timer.join()
    assert time.monotonic() - started < 30
    assert "done" not in stages
    # Python's own handler is back: the next Ctrl-C outside levelfuse raises as usual.
    with pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1.0)
    assert levelfuse.reconstruct(sphere_scans(pixels=24), voxel_size=0.2, fit=False).summary["scans"] == 6


def test_ctrl_c_stops_the_engine_between_steps():
    import numpy as np
    i, j, k = np.indices((64, 64, 64))
    field = levelfuse.SparseField.from_mask((i - 31.5) ** 2 + (j - 31.5) ** 2 + (k - 31.5) ** 2 < 28**2)
    timer = interrupt_after(0.3)
    with pytest.raises(KeyboardInterrupt):
        field.advance(1e6, force=lambda x, n: np.zeros(len(x)), beta=0.5)
    timer.join()
    assert field.stats["active_set_voxels"] > 0



def test_ctrl_c_just_before_the_work_stops_it_before_it_runs(monkeypatch):
    # The module sends itself SIGINT as the work is about to take it over: Python's handler notes
    # it, and would raise it only at its next bytecode, after the work (a minute of curvature flow
    # here, with no Python code in it to run the handler sooner).
    import numpy as np
    i, j, k = np.indices((64, 64, 64))
    field = levelfuse.SparseField.from_mask((i - 31.5) ** 2 + (j - 31.5) ** 2 + (k - 31.5) ** 2 < 28**2)
    monkeypatch.setenv("LEVELFUSE_TEST_SIGNAL_BEFORE_WORK", "1")
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        field.advance(1e6, beta=0.5)
    assert time.monotonic() - started < 5
    monkeypatch.delenv("LEVELFUSE_TEST_SIGNAL_BEFORE_WORK")
    assert field.advance(1e-3, beta=0.5) >= 1
