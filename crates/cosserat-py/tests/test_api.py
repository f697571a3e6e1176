"""Round trips through the Python API: loading, stepping, arrays, script targets."""

import math
import sys

import numpy as np
import pytest

import cosserat
from conftest import SCENES, STRIP


def test_load_with_overrides_as_dict_or_strings(strip_overrides):
    a = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    b = cosserat.Simulation.load(str(STRIP), overrides=[f"{k}={v}" for k, v in strip_overrides.items()])
    assert a.name == "twisting_strip"
    assert a.boundary_names == ["left_clamp", "right_twist"]
    # 8 × 2 quads of Tri6: 17 × 5 displacement nodes; Tri3 rotations: 9 × 3.
    assert a.positions.shape == (17 * 5, 3)
    assert a.quaternions.shape == (9 * 3, 4)
    for _ in range(2):
        a.step()
        b.step()
    assert np.array_equal(a.positions, b.positions)


def test_each_step_may_name_its_thread_count_and_the_result_does_not_depend_on_it(strip_overrides):
    one = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    two = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    mixed = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    for threads in (1, 2, None, 2):
        one.step(threads=1)
        two.step(threads=2)
        mixed.step(threads=threads)
    assert np.array_equal(one.positions, two.positions)
    assert np.array_equal(one.positions, mixed.positions)
    assert np.array_equal(one.quaternions, mixed.quaternions)
    assert one.run_until(0.05, threads=1) == 1 and two.run_until(0.05, threads=2) == 1
    assert np.array_equal(one.positions, two.positions)


def test_arrays_are_read_only_views_that_follow_the_steps(strip_overrides):
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    x = sim.positions
    assert not x.flags.owndata and not x.flags.writeable
    assert x.base is not None
    assert np.shares_memory(x, sim.positions)
    with pytest.raises(ValueError):
        x[0, 0] = 1.0
    at_rest = x.copy()
    assert np.array_equal(at_rest, sim.rest_positions)
    info = sim.step()
    assert info.step == 1 and info.t == pytest.approx(0.01) and info.newton_iterations >= 1
    assert sim.time == info.t
    # The view shows the new state: the twisted end moved.
    assert not np.array_equal(x, at_rest)
    assert np.array_equal(x, sim.positions)
    assert np.array_equal(sim.displacements, x - sim.rest_positions)
    # Directors are the columns of the nodes' rotations: orthonormal frames.
    d1, d2, d3 = sim.directors
    assert np.allclose(np.einsum("ij,ij->i", d1, d2), 0.0, atol=1e-12)
    assert np.allclose(np.cross(d1, d2), d3, atol=1e-12)
    assert sim.angular_velocities.shape == sim.quaternions[:, :3].shape
    # The view keeps the simulation alive.
    del sim
    assert np.isfinite(x).all()


def test_shells_index_the_state(strip_overrides):
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    (shell,) = sim.shells
    assert shell["name"]
    elements = shell["displacement_nodes"][shell["displacement_elements"]]
    assert elements.shape == (2 * 8 * 2, 6)
    assert elements.max() == len(sim.positions) - 1


@pytest.mark.skipif(sys.version_info < (3, 11), reason="tomllib")
def test_a_dict_scene_runs_like_its_file(strip_overrides):
    import tomllib

    with open(STRIP, "rb") as f:
        scene = tomllib.load(f)
    a = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    b = cosserat.Simulation.from_dict(scene, base_dir=SCENES, overrides=strip_overrides)
    a.run_until(0.03)
    assert b.run_until(0.03) == 3
    assert np.array_equal(a.positions, b.positions)
    assert np.array_equal(a.quaternions, b.quaternions)


def test_a_controller_reproduces_the_scripted_twist(strip_overrides):
    """The scene turns the right end by 2πt at the end of each step; a Python controller that sets the
    same rotation before every step gives the same state, bit for bit."""
    scripted = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    driven = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    dt = 0.01
    for _ in range(4):
        driven.set_motion("right_twist", angle=2 * math.pi * (driven.time + dt), axis=(1.0, 0.0, 0.0))
        driven.step()
        scripted.step()
    assert np.array_equal(driven.positions, scripted.positions)
    assert np.array_equal(driven.quaternions, scripted.quaternions)
    # A different target gives a different state; reset_motion gives the scene's back.
    driven.set_motion("right_twist", angle=0.0, axis=(1.0, 0.0, 0.0))
    driven.step()
    scripted.step()
    assert not np.array_equal(driven.positions, scripted.positions)


def test_load_scales_from_python():
    plate = SCENES / "plate_under_load.toml"
    small = {"mesh.nx": 8, "mesh.ny": 2, "time.end": 0.03}
    held = cosserat.Simulation.load(plate, overrides=small)
    assert held.load_names == ["tip_load"]
    held.set_load_scale("tip_load", 0.0)
    held.run_until(0.03)
    # Unloaded and held at rest: round-off only.
    assert np.abs(held.positions - held.rest_positions).max() < 1e-15
    # A constant scale set from Python runs like the same constant in the scene.
    from_python = cosserat.Simulation.load(plate, overrides=small)
    from_scene = cosserat.Simulation.load(plate, overrides={**small, "load.0.scale": "0.5"})
    from_python.set_load_scale("tip_load", 0.5)
    from_python.run_until(0.03)
    from_scene.run_until(0.03)
    assert np.array_equal(from_python.positions, from_scene.positions)
    assert not np.array_equal(from_python.positions, from_python.rest_positions)


def test_script_targets_are_checked(strip_overrides):
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    with pytest.raises(KeyError, match="right_twist"):
        sim.set_motion("no_such_boundary", angle=1.0)
    with pytest.raises(ValueError, match="finite"):
        sim.set_motion("right_twist", angle=float("nan"))
    with pytest.raises(ValueError, match="rotation"):
        sim.set_motion("right_twist", rotation=[[2.0, 0, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(KeyError):
        sim.set_load_scale("right_twist", 1.0)


def test_a_simulation_runs_once(tmp_path, strip_overrides):
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    sim.step()
    with pytest.raises(RuntimeError, match="load the scene again"):
        sim.run(tmp_path / "out")


def test_run_record_and_quasi_static_runs(tmp_path):
    sim = cosserat.Simulation.load(
        SCENES / "validation" / "cantilever_small_load.toml", overrides={"mesh.nx": 4, "time.n_levels": 3}
    )
    steps = []
    summary = sim.run(tmp_path / "qs", on_step=lambda info: steps.append(info.t))
    assert summary.status == "ok" and summary.reason is None
    assert summary.n_steps == 3 and len(steps) == 3 and steps[-1] == pytest.approx(1.0)
    assert summary.to_dict()["n_steps"] == 3
    # The scene names the paper's pair; the summary says which discretisation ran.
    assert (summary.displacement_element, summary.rotation_element) == ("tri6", "tri3")
    assert summary.strain_interpolation == "paper"
    assert summary.quadrature_points == "3"
    assert (tmp_path / "qs" / "summary.json").is_file()
