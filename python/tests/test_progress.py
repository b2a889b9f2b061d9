"""Progress callbacks (tqdm), cancellation by the callback and by Ctrl-C, the GIL released."""

from __future__ import annotations

import os
import signal
import threading
import time

import pytest

import squeal
from conftest import EXAMPLES

TINY = EXAMPLES / "transient" / "tiny-brake.toml"


def test_events_reach_the_callback():
    events = []
    squeal.cea(squeal.Scene.from_file(TINY).set("cea", {}), progress=events.append)
    kinds = {e["kind"] for e in events}
    assert {"begin", "end"} <= kinds
    begins = [e for e in events if e["kind"] == "begin"]
    assert any("Craig" in e["label"] or "mesh" in e["label"] or "complex" in e["label"] for e in begins)


def test_tqdm_progress_draws_the_transient_bar(capsys):
    pytest.importorskip("tqdm")
    p = squeal.TqdmProgress(file=None)
    t = squeal.transient(squeal.Scene.from_file(TINY), progress=p)
    assert t.success
    assert not p._bars  # every bar ended


def test_callback_exception_cancels():
    class Stop(Exception):
        pass

    def cb(e):
        if e["kind"] == "update":
            raise Stop("enough")

    with pytest.raises(Stop):
        squeal.transient(squeal.Scene.from_file(TINY).set("transient.tfinal", 50.0), progress=cb)


def test_keyboard_interrupt_cancels_a_long_run():
    scene = squeal.Scene.from_file(TINY).set("transient.tfinal", 1000.0)
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    t0 = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        squeal.transient(scene)
    assert time.perf_counter() - t0 < 30.0


