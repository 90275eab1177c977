# Long calls: the GIL is released while C++ works, Ctrl-C interrupts, progress is reported.
import os
import signal
import threading
import time

import numpy as np
import pytest

import ganzfeld

SPEC = "specular:alpha=8"


class Ticker(threading.Thread):
    """A Python thread counting while it gets the GIL."""

    def __init__(self):
        super().__init__(daemon=True)
        self.ticks = 0
        self.stop = threading.Event()

    def run(self):
        while not self.stop.is_set():
            self.ticks += 1
            time.sleep(0.001)


def ticks_during(work):
    """How often a Python thread counting once a millisecond got the GIL while `work` ran."""
    ticker = Ticker()
    ticker.start()
    try:
        time.sleep(0.05)
        before = ticker.ticks
        work()
        return ticker.ticks - before
    finally:
        ticker.stop.set()
        ticker.join()


# With the GIL held for the whole call the ticker would not move; it ticks about once a ms when
# the GIL is released (the waiting thread takes it only briefly every 50 ms).
def test_a_thread_runs_while_a_bake_does():
    during = ticks_during(lambda: ganzfeld.bake(SPEC, "g", res=(24, 24, 12), tol=1e-9))  # about a second on 2 cores
    assert during >= 50, during


def test_a_thread_runs_while_a_law_is_evaluated():
    during = ticks_during(lambda: ganzfeld.Model(SPEC).g(theta_i=np.linspace(0, 180, 10000), theta_j=60, tol=1e-10))
    assert during >= 50, during


def interrupt_after(seconds):
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


def test_ctrl_c_interrupts_an_evaluation():
    model = ganzfeld.Model(SPEC)
    many = np.linspace(0, 180, 10**6)  # hours of work at this tolerance: only an interruption ends it
    timer = interrupt_after(0.3)
    with pytest.raises(KeyboardInterrupt):
        model.g(theta_i=many, theta_j=60, tol=1e-12)
    timer.join()
    assert model.g(theta_i=60, theta_j=30, tol=1e-8).converged  # the module still works


def test_ctrl_c_interrupts_a_bake():
    timer = interrupt_after(0.3)
    with pytest.raises(KeyboardInterrupt):
        ganzfeld.bake(SPEC, "g", res=(60, 60, 30), tol=1e-12)
    timer.join()


def test_progress_callback():
    calls = []
    ganzfeld.Model(SPEC).g(theta_i=np.linspace(0, 180, 400), theta_j=60, tol=1e-10,
                           progress=lambda done, total: calls.append((done, total)))
    assert calls, "no progress reported"
    assert calls[-1] == (400, 400)
    assert all(a[0] < b[0] for a, b in zip(calls, calls[1:]))
    calls.clear()
    ganzfeld.bake(SPEC, "h", res=64, progress=lambda done, total: calls.append((done, total)))
    assert calls[-1] == (64, 64)


def test_a_raising_progress_callback_cancels():
    class Stop(Exception):
        pass

    def stop(done, total):
        raise Stop()

    with pytest.raises(Stop):
        ganzfeld.Model(SPEC).g(theta_i=np.linspace(0, 180, 10**6), theta_j=60, tol=1e-12, progress=stop)
    with pytest.raises(Stop):
        ganzfeld.bake(SPEC, "g", res=(60, 60, 30), tol=1e-12, progress=stop)


def test_progress_true_changes_no_number():
    """progress=True draws tqdm's bar when tqdm is installed, else the command line's on a terminal."""
    model = ganzfeld.Model(SPEC)
    shown = model.h(theta_j=[10, 20, 30], progress=True)
    plain = model.h(theta_j=[10, 20, 30])
    assert all(np.array_equal(a, b) for a, b in zip(shown, plain))


def test_progress_true_draws_tqdm_when_installed(monkeypatch):
    """progress=True with tqdm importable: one bar, told the total, advanced to it, closed."""
    import sys
    import types

    bars = []

    class FakeBar:
        def __init__(self, total, desc):
            self.total, self.desc, self.n, self.closed = total, desc, 0, False
            bars.append(self)

        def reset(self, total):
            self.total, self.n = total, 0

        def refresh(self):
            pass

        def close(self):
            self.closed = True

    auto = types.ModuleType("tqdm.auto")
    auto.tqdm = FakeBar
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    ganzfeld.Model(SPEC).g(theta_i=np.linspace(0, 180, 300), theta_j=60, tol=1e-9, progress=True)
    assert len(bars) == 1
    assert (bars[0].n, bars[0].total, bars[0].closed) == (300, 300, True)
    assert bars[0].desc == "g of specular:alpha=8"
