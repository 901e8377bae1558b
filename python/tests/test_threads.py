"""Analyses run without the GIL, and Ctrl-C stops them keeping their points."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import nfrc
from conftest import friction_dict


@pytest.mark.parametrize("analysis", [nfrc.trace, lambda case: nfrc.solve_at(case, 0.7)],
                         ids=["trace", "solve_at"])
def test_interrupt_keeps_points(analysis):
    # About 10000 points (minutes): SIGINT after a second must stop it within a point.
    case = nfrc.Case.from_dict(friction_dict())
    case.continuation.update(step=0.001, max_step=0.001)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(nfrc.Interrupted) as caught:
            analysis(case)
    finally:
        timer.cancel()
    elapsed = time.monotonic() - start
    assert isinstance(caught.value, KeyboardInterrupt)
    branch = caught.value.branch
    assert branch.points >= 1 and len(branch.omega) == branch.points
    assert branch.summary.termination == "stopped_by_observer"
    assert "interrupted" in branch.summary.message
    assert branch.omega[-1] < 0.8 and elapsed < 30


def test_trace_releases_the_gil():
    case = nfrc.Case.from_dict(friction_dict(max_harmonic=15, samples=64))
    result = {}
    worker = threading.Thread(target=lambda: result.update(branch=nfrc.trace(case)))
    start = time.monotonic()
    worker.start()
    loops = 0
    while worker.is_alive():  # pure Python: runs only while the trace has released the GIL
        loops += 1
    worker.join()
    elapsed = time.monotonic() - start
    assert result["branch"].summary.success
    # Holding the GIL the trace would leave this loop a few switch intervals at most.
    assert elapsed > 0.05 and loops > 10000, (elapsed, loops)


def test_case_stays_usable_while_traced_in_a_thread():
    case = nfrc.Case.from_dict(friction_dict(max_harmonic=15, samples=64))
    reference = nfrc.trace(case)
    result = {}
    worker = threading.Thread(target=lambda: result.update(branch=nfrc.trace(case)))
    worker.start()
    case.continuation.omega_end = 0.5  # the running trace has its own copy
    worker.join()
    assert list(result["branch"].omega) == list(reference.omega)


def test_stability_threads_change_no_result(source_dir):
    # NLvib's penalty spring: dozens of Neimark-Sacker points, localised while the trace goes on.
    case = nfrc.load_case(str(source_dir / "cases/contact/nlvib.json#penalty"))
    in_turn = nfrc.trace(case, threads=0)
    beside = nfrc.trace(case, threads=2)
    assert len(in_turn.bifurcations) >= 2
    assert np.array_equal(beside.omega, in_turn.omega)
    assert [f.multipliers for f in beside.floquet] == [f.multipliers for f in in_turn.floquet]
    assert ([(b.type, b.omega, b.after_point) for b in beside.bifurcations] ==
            [(b.type, b.omega, b.after_point) for b in in_turn.bifurcations])


@pytest.mark.parametrize("threads, error, message", [(-2, nfrc.InputError, "threads:"),
                                                     (1.5, TypeError, "threads:"),
                                                     (True, TypeError, "threads:")])
def test_stability_threads_are_checked(threads, error, message):
    case = nfrc.Case.from_dict(friction_dict(max_harmonic=3, samples=16))
    with pytest.raises(error, match=message):
        nfrc.trace(case, threads=threads)
