"""Scene errors reach Python with the file, the line, the field and the reason."""

import pytest

import cosserat
from conftest import STRIP

def test_an_invalid_value_names_file_line_field_and_reason(tmp_path):
    lines = STRIP.read_text().splitlines()
    line = lines.index("dt = 0.01") + 1
    lines[line - 1] = "dt = -0.01"
    path = tmp_path / "bad.toml"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(cosserat.SceneError) as caught:
        cosserat.Simulation.load(path)
    e = caught.value
    assert e.file == str(path)
    assert e.line == line
    assert e.field == "time.dt"
    assert "positive" in e.reason
    assert isinstance(e, ValueError)
    assert f"{path}:{line}" in str(e)


def test_an_unknown_key_is_a_scene_error(tmp_path):
    path = tmp_path / "typo.toml"
    path.write_text(STRIP.read_text().replace("youngs_modulus", "youngs_modulos"))
    with pytest.raises(cosserat.SceneError) as caught:
        cosserat.Simulation.load(path)
    e = caught.value
    assert e.file == str(path) and e.line is not None
    assert "youngs_modulos" in e.reason


def test_an_override_error_names_the_override():
    with pytest.raises(cosserat.SceneError) as caught:
        cosserat.Simulation.load(STRIP, overrides={"time.dt": -1.0})
    e = caught.value
    assert e.override == "time.dt=-1.0"
    assert e.field == "time.dt"
    assert "positive" in e.reason


def test_an_override_of_an_extreme_float_is_quoted_with_an_exponent():
    with pytest.raises(cosserat.SceneError) as caught:
        cosserat.Simulation.load(STRIP, overrides={"time.dt": 1e-300})
    assert caught.value.override == "time.dt=1e-300"
    with pytest.raises(cosserat.SceneError) as caught:
        cosserat.Simulation.load(STRIP, overrides={"gravity": [0.0, 0.0, -1e200]})
    assert caught.value.override == "gravity=[0.0, 0.0, -1e200]"


def test_a_dict_error_names_the_field_without_a_line():
    tomllib = pytest.importorskip("tomllib")

    scene = tomllib.loads(STRIP.read_text())
    scene["time"]["dt"] = -0.01
    with pytest.raises(cosserat.SceneError) as caught:
        cosserat.Simulation.from_dict(scene)
    e = caught.value
    assert e.file is None and e.line is None
    assert e.field == "time.dt"
    # The message cites no line either: the dict has none.
    assert str(e).startswith("scene dict: time.dt: ") and "<dict>" not in str(e)


def test_a_missing_file_is_a_scene_error(tmp_path):
    with pytest.raises(cosserat.SceneError) as caught:
        cosserat.Simulation.load(tmp_path / "missing.toml")
    assert caught.value.file == str(tmp_path / "missing.toml")


@pytest.mark.parametrize("overrides", ["mesh.nx=8", b"mesh.nx=8", 8])
def test_overrides_that_are_neither_a_dict_nor_a_list_of_strings_are_a_type_error(overrides):
    # A string would otherwise be read character by character, as overrides `m`, `e`, ...
    with pytest.raises(TypeError, match="overrides must be a dict"):
        cosserat.Simulation.load(STRIP, overrides=overrides)


def test_override_keys_and_items_that_are_not_strings_are_named():
    with pytest.raises(TypeError, match="overrides: the keys .* must be strings .*int 5"):
        cosserat.Simulation.load(STRIP, overrides={5: 8})
    with pytest.raises(TypeError, match="overrides: every item .* string .*int 5"):
        cosserat.Simulation.load(STRIP, overrides=["mesh.nx=8", 5])


def _scene_dict():
    tomllib = pytest.importorskip("tomllib")
    return tomllib.loads(STRIP.read_text())


@pytest.mark.parametrize("container", [dict, list])
def test_a_scene_dict_that_contains_itself_is_a_scene_error(container):
    scene = _scene_dict()
    if container is dict:
        scene["time"]["self"] = scene["time"]
    else:
        loop = []
        loop.append(loop)
        scene["gravity"] = loop
    # Without a bound on the nesting, the conversion overflowed the stack and killed the interpreter.
    with pytest.raises(cosserat.SceneError, match="nested more than") as caught:
        cosserat.Simulation.from_dict(scene)
    assert caught.value.field.startswith("time.self" if container is dict else "gravity.0")


def test_an_integer_beyond_64_bits_is_a_scene_error_naming_its_field():
    scene = _scene_dict()
    scene["mesh"]["nx"] = 2**64
    with pytest.raises(cosserat.SceneError, match="64-bit") as caught:
        cosserat.Simulation.from_dict(scene)
    assert caught.value.field == "mesh.nx" and caught.value.file is None
    with pytest.raises(cosserat.SceneError) as caught:
        cosserat.Simulation.load(STRIP, overrides={"mesh.nx": 2**64})
    assert caught.value.field == "mesh.nx"


def test_a_value_of_the_wrong_type_in_a_scene_dict_names_its_field():
    scene = _scene_dict()
    scene["boundary"][1]["name"] = None
    with pytest.raises(TypeError, match="`boundary.1.name`: a scene value must be"):
        cosserat.Simulation.from_dict(scene)


@pytest.mark.parametrize("threads", [0, -1, 2**64, 10**6])
def test_a_thread_count_out_of_range_is_a_value_error(tmp_path, strip_overrides, threads):
    # A million threads were spawned (a hang), -1 and 2**64 raised OverflowError, 0 meant all cores.
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    for call in (lambda: sim.step(threads=threads), lambda: sim.run_until(0.02, threads=threads),
                 lambda: sim.run(tmp_path / "out", threads=threads)):
        with pytest.raises(ValueError, match="threads must be from 1 to 1024"):
            call()
    assert sim.time == 0.0


@pytest.mark.parametrize("threads", [2.0, "2", True])
def test_a_thread_count_that_is_not_an_int_is_a_type_error(strip_overrides, threads):
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    with pytest.raises(TypeError, match="threads must be an int or None"):
        sim.step(threads=threads)


@pytest.mark.parametrize("t", [float("nan"), float("inf"), 1e9])
def test_run_until_refuses_a_time_it_would_step_towards_for_ever(strip_overrides, t):
    # NaN and infinity were never reached: the strip was stepped until it failed, 4000 steps later.
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    with pytest.raises(ValueError, match="t must be a finite time up to the scene's end 0.05"):
        sim.run_until(t)
    assert sim.time == 0.0


@pytest.mark.parametrize("t", [-1.0, 0.0, 0.004])
def test_run_until_a_time_already_reached_takes_no_step(strip_overrides, t):
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    assert sim.run_until(t) == 0
    assert sim.time == 0.0
    sim.step()
    assert sim.run_until(t) == 0 and sim.time == pytest.approx(0.01)


def test_run_checks_its_arguments_before_it_starts(tmp_path, strip_overrides):
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    # A callback that is not callable ended the run after its first step and used up the simulation.
    with pytest.raises(TypeError, match="on_step must be callable"):
        sim.run(tmp_path / "out", on_step=5)
    # An empty path wrote the outputs into the current directory.
    with pytest.raises(ValueError, match="out_dir is empty"):
        sim.run("")
    assert not (tmp_path / "out").exists()
    assert sim.run(tmp_path / "out").status == "ok"


def test_a_run_whose_outputs_cannot_be_set_up_may_be_run_again(tmp_path, strip_overrides):
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    with pytest.raises(cosserat.SimulationError, match="cannot create the directory"):
        sim.run(blocker / "out")
    summary = sim.run(tmp_path / "out")
    assert summary.status == "ok" and summary.n_steps == 5


def test_a_rotation_with_an_angle_or_axis_is_refused(strip_overrides):
    # The angle and axis were silently ignored.
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    with pytest.raises(ValueError, match="either `rotation` or `angle` and `axis`"):
        sim.set_motion("right_twist", rotation=[[1, 0, 0], [0, 1, 0], [0, 0, 1]], angle=1.0)
    with pytest.raises(ValueError, match="either `rotation` or `angle` and `axis`"):
        sim.set_motion("right_twist", rotation=[[1, 0, 0], [0, 1, 0], [0, 0, 1]], axis=(1.0, 0.0, 0.0))


def test_targets_after_a_run_are_refused(tmp_path, strip_overrides):
    # They were queued for a step that never comes.
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    sim.run(tmp_path / "out")
    for call in (lambda: sim.set_motion("right_twist", angle=1.0), lambda: sim.reset_motion("right_twist")):
        with pytest.raises(RuntimeError, match="this simulation has run"):
            call()
    plate = cosserat.Simulation.load(STRIP.parent / "plate_under_load.toml",
                                     overrides={"mesh.nx": 8, "mesh.ny": 2, "time.end": 0.01})
    plate.run(tmp_path / "plate")
    with pytest.raises(RuntimeError, match="this simulation has run"):
        plate.set_load_scale("tip_load", 1.0)


def test_a_frame_that_cannot_be_read_is_the_os_error_of_its_cause(tmp_path):
    missing = tmp_path / "missing.vtu"
    with pytest.raises(FileNotFoundError) as caught:
        cosserat.read_vtu(missing)
    assert str(caught.value).count(str(missing)) == 1, str(caught.value)
    not_a_frame = tmp_path / "empty.vtu"
    not_a_frame.write_text("<VTKFile/>")
    with pytest.raises(ValueError) as caught:
        cosserat.read_vtu(not_a_frame)
    assert str(not_a_frame) in str(caught.value)
