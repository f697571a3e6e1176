"""Stopping a run: Ctrl-C (SIGINT) and a request from `on_step` end it after the current step with
every complete step's outputs and a summary that says so."""

import json
import os
import signal
import threading
import time

import pytest

import cosserat
from conftest import STRIP

#: 400 steps of the coarse strip.
LONG = {"mesh.nx": 8, "mesh.ny": 2, "time.end": 4.0}
#: 4000 steps: far longer than a signal sent from another thread takes to arrive.
LONGER = {**LONG, "time.end": 40.0}


def check_interrupted(out, n_steps):
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert "SIGINT" in summary["reason"]
    assert summary["n_steps"] == n_steps
    # Probes of the initial state and of the completed steps, up to the last one.
    rows = (out / "probes.csv").read_text().splitlines()
    assert len(rows) >= 2 and float(rows[-1].split(",")[0]) <= summary["stopped_at"]
    assert list((out / "frames").glob("*.pvd"))


def test_ctrl_c_while_stepping_stops_the_run_after_the_step(tmp_path):
    sim = cosserat.Simulation.load(STRIP, overrides=LONGER)
    out = tmp_path / "run"
    seen = []

    def on_step(info):
        seen.append(info.step)
        if info.step == 3:
            # Another thread sends the signal, as a terminal would, while the run goes on in Rust.
            threading.Thread(target=os.kill, args=(os.getpid(), signal.SIGINT)).start()

    with pytest.raises(KeyboardInterrupt):
        sim.run(out, on_step=on_step)
    assert 3 <= seen[-1] < 4000
    check_interrupted(out, seen[-1])


def test_on_step_returning_false_stops_the_run(tmp_path):
    sim = cosserat.Simulation.load(STRIP, overrides=LONG)
    summary = sim.run(tmp_path / "run", on_step=lambda info: info.step < 4)
    assert summary.status == "interrupted"
    assert summary.n_steps == 4
    assert summary.stopped_at == pytest.approx(0.04)


def test_an_exception_in_on_step_stops_the_run_and_is_raised(tmp_path):
    sim = cosserat.Simulation.load(STRIP, overrides=LONG)

    def on_step(info):
        if info.step == 2:
            raise ZeroDivisionError("controller failed")

    with pytest.raises(ZeroDivisionError):
        sim.run(tmp_path / "run", on_step=on_step)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["status"] == "interrupted" and summary["n_steps"] == 2


def test_a_controller_in_a_run_sets_targets(tmp_path, strip_overrides):
    """`on_step` may set targets for the next step; holding the twisted end still changes the run."""
    free = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    held = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    x_free, x_held = free.positions, held.positions
    free.run(tmp_path / "free")
    held.set_motion("right_twist", angle=0.0)
    held.run(tmp_path / "held", on_step=lambda info: held.set_motion("right_twist", angle=0.0))
    # Clamped at both ends and not turned: the strip stays at rest.
    assert (abs(x_held - held.rest_positions) < 1e-12).all()
    assert not (abs(x_free - free.rest_positions) < 1e-6).all()


def test_steps_release_the_gil():
    """Python threads run while a simulation steps: the steps run without the GIL."""
    sim = cosserat.Simulation.load(STRIP, overrides=LONG)
    done = threading.Event()
    worker = threading.Thread(target=lambda: (sim.run_until(2.0), done.set()))
    ticks = 0
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert sim.time == pytest.approx(2.0)
    # 200 steps: the main thread ran between and during them (with the GIL held throughout the run
    # it could not tick before the run returned).
    assert ticks > 20
