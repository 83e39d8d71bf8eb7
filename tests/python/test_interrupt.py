"""Ctrl-C during a long call raises KeyboardInterrupt within a second, and progress reaches a Python callable
(ctest label python). SIGINT comes from a timer thread, as from a terminal."""
import os
import signal
import threading
import time

import pytest

import rtsdf

DATA = os.environ.get("RTSDF_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "data"))
BUNNY = os.path.join(DATA, "scenes", "bunny.json")
# Calls that run for many seconds uninterrupted on a 2-core CPU: the exact one several seconds at res 256 (full domain),
# the GPU one (lavapipe, res 64) under 0.1 s a frame after a first one of about 1 s (short frames: the stop lands
# between frames even on a loaded machine). A GPU frame is one command buffer that
# runs to its end: the bake polls between frames.
EXACT_LONG = dict(method="exact", res=256, band=0.1, full_domain=True)
# Every pass every frame (full_rebuild): frames at one moment otherwise skip all their passes once the band settled.
GPU_LONG = dict(method="rtsdf", res=64, refine="closest", rays=0, frames=300, full_rebuild=True)


def interrupted_after(seconds, call):
    """Run call() with a SIGINT sent `seconds` after its first progress report (the job has started: the device
    set up, the first block or frame done); returns (seconds from the signal to KeyboardInterrupt, reports seen)."""
    sent = []
    timer = threading.Timer(seconds, lambda: (sent.append(time.monotonic()), os.kill(os.getpid(), signal.SIGINT)))
    reports = []

    def progress(stage, fraction):
        if not reports:
            timer.start()
        reports.append((stage, fraction))

    try:
        with pytest.raises(KeyboardInterrupt):
            call(progress)
        caught = time.monotonic()
    finally:
        timer.cancel()
    assert sent, "the call ended before the signal"
    return caught - sent[0], reports


def test_ctrl_c_stops_an_exact_bake_within_a_second():
    delay, reports = interrupted_after(0.5, lambda progress: rtsdf.bake(BUNNY, progress=progress, **EXACT_LONG))
    assert delay < 1.0, f"KeyboardInterrupt {delay:.2f} s after SIGINT"
    # It had started and was far from done.
    assert reports and all(stage == "exact SDF" for stage, _ in reports) and 0.0 < reports[-1][1] < 0.9


def test_ctrl_c_stops_a_gpu_bake_within_a_second():
    delay, reports = interrupted_after(0.5, lambda progress: rtsdf.bake(BUNNY, progress=progress, **GPU_LONG))
    assert delay < 1.0, f"KeyboardInterrupt {delay:.2f} s after SIGINT"
    assert reports and reports[-1][0] == "refining" and reports[-1][1] < 0.5


def test_progress_reaches_the_callable_in_order():
    reports = []
    rtsdf.bake(BUNNY, method="rtsdf", res=32, refine="closest", rays=0, frames=4,
               progress=lambda stage, fraction: reports.append((stage, fraction)))
    assert reports == [("refining", 0.25), ("refining", 0.5), ("refining", 0.75), ("refining", 1.0)]
    exact = []
    rtsdf.bake(BUNNY, method="exact", res=48, progress=lambda stage, fraction: exact.append(fraction))
    assert len(exact) >= 10 and exact == sorted(exact) and exact[-1] == 1.0


def test_an_error_in_the_callable_stops_the_job_and_is_raised():
    calls = []

    def fail(stage, fraction):
        calls.append(fraction)
        raise ZeroDivisionError("from the callback")

    with pytest.raises(ZeroDivisionError, match="from the callback"):
        rtsdf.bake(BUNNY, method="rtsdf", res=32, refine="closest", rays=0, frames=50, progress=fail)
    assert calls == [0.02]  # the bake stopped at its next poll: no further frame reported
    with pytest.raises(TypeError, match="progress must be a callable"):
        rtsdf.bake(BUNNY, res=16, progress=3)
