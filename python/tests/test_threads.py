"""Native work releases the GIL, and Ctrl-C (SIGINT) interrupts it cleanly."""

import os
import signal
import threading

import pytest

import flexmb


def long_run_model(models):
    return flexmb.load(models / "pendulum.toml")


def test_another_python_thread_runs_during_a_simulation(models):
    # The other thread needs the GIL for 100 short pieces of work; with the GIL held through the run it
    # could only do them after the run returned.
    model = long_run_model(models)
    started, done = threading.Event(), threading.Event()
    finished_during_run = []

    def other_work():
        started.wait()
        total = 0
        for i in range(100):
            total += sum(range(100))
            threading.Event().wait(0.001)
        finished_during_run.append(not done.is_set())

    worker = threading.Thread(target=other_work)
    worker.start()
    started.set()
    results = model.simulate(t_end=2000.0, output_step=1.0)
    done.set()
    worker.join()
    assert results.summary["status"] == "completed"
    assert finished_during_run == [True], "the other thread did its work only after the run returned"


def test_sigint_during_a_run_raises_keyboard_interrupt_with_the_rows_so_far(models):
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("Python handles signals in the main thread only")
    model = long_run_model(models)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as raised:
            model.simulate(t_end=1e6, output_step=1.0)
    finally:
        timer.cancel()
    results = raised.value.results
    summary = results.summary
    assert summary["status"] == "interrupted" and summary["reason"] == "SIGINT"
    assert 0 < len(results) < 1e6
    assert results.time[-1] <= summary["interrupted_at"]
    # The process stays usable: the next run completes.
    assert model.simulate(t_end=0.1).summary["status"] == "completed"


def test_sigint_during_advance_to_leaves_the_simulation_usable(models):
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("Python handles signals in the main thread only")
    model = long_run_model(models)
    simulation = model.simulation(t_end=1e6, output_step=1.0)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            simulation.advance_to(1e6)
    finally:
        timer.cancel()
    stopped = simulation.time
    assert 0 < stopped < 1e6
    assert simulation.advance_to(stopped + 1.0) >= stopped + 1.0
