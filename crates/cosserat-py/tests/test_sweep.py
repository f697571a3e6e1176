"""A sweep of independent runs on Dask distributed: two worker processes, rows gathered in order."""

import json
import os

import pytest

import cosserat
from cosserat import sweep
from conftest import STRIP

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    with distributed.Client(cluster) as client:
        yield client
    cluster.close()


def test_a_two_worker_sweep_gathers_one_table(client, tmp_path):
    assert len(client.scheduler_info()["workers"]) == 2
    runs = cosserat.grid(
        STRIP,
        tmp_path,
        **{"mesh.nx": [8], "mesh.ny": [2], "time.end": [0.03], "material.youngs_modulus": [7e9, 70e9]},
    )
    bad = cosserat.RunDescription.of(STRIP, tmp_path / "bad", {"time.dt": -1}, label="bad")
    rows = sweep.run_sweep(runs + [bad], client)
    assert [r["label"] for r in rows] == [r.label for r in runs] + ["bad"]
    soft, stiff, failed = rows
    assert soft["status"] == stiff["status"] == "ok"
    assert soft["n_steps"] == stiff["n_steps"] == 3
    assert soft["set.material.youngs_modulus"] == 7e9
    assert failed["status"] == "error" and "time.dt" in failed["reason"]
    # Each row carries the final probes; the same description run here gives the same numbers.
    probe_columns = [c for c in soft if c.startswith("probe.")]
    assert probe_columns
    again = runs[0].__class__.of(STRIP, tmp_path / "again", dict(runs[0].params), label="again").run()
    assert [again[c] for c in probe_columns] == [soft[c] for c in probe_columns]
    # The outputs are where the descriptions say, and the table is one CSV.
    assert json.loads((tmp_path / runs[1].label / "summary.json").read_text())["status"] == "ok"
    sweep.to_csv(rows, tmp_path / "sweep.csv")
    assert len((tmp_path / "sweep.csv").read_text().splitlines()) == 4


def test_descriptions_round_trip_through_json(tmp_path):
    runs = cosserat.grid(STRIP, tmp_path, **{"mesh.nx": [4, 8]})
    sweep.save_descriptions(runs, tmp_path / "runs.json")
    loaded = sweep.load_descriptions(tmp_path / "runs.json")
    assert [r.cli_args() for r in loaded] == [r.cli_args() for r in runs]
    assert runs[0].cli_args() == ["run", str(STRIP), "--out", str(tmp_path / "nx=4"), "--set", "mesh.nx=4",
                                  "--threads", "1"]


def test_numpy_values_make_overrides_the_scene_reads(tmp_path):
    np = pytest.importorskip("numpy")
    # np.linspace gives np.float64 values, whose repr `np.float64(0.02)` was passed on as the value.
    (run,) = cosserat.grid(STRIP, tmp_path, **{"time.end": np.linspace(0.02, 0.02, 1),
                                               "mesh.nx": np.array([8]), "mesh.ny": [np.int32(2)],
                                               "gravity": [np.zeros(3)]})
    assert run.overrides == ("time.end=0.02", "mesh.nx=8", "mesh.ny=2", "gravity=[0.0, 0.0, 0.0]")
    row = run.run()
    assert row["status"] == "ok" and row["n_steps"] == 2


@pytest.mark.parametrize("axis, error, message", [
    ("abc", TypeError, "grid axis `name` must be a list of values"),
    (8, TypeError, "grid axis `name` must be a list of values"),
    ([], ValueError, "grid axis `name` has no values"),
])
def test_a_grid_axis_that_is_no_list_of_values_is_refused(tmp_path, axis, error, message):
    # A string was swept character by character, and an empty axis gave an empty sweep.
    with pytest.raises(error, match=message):
        cosserat.grid(STRIP, tmp_path, **{"name": axis})


def test_runs_that_would_share_an_output_directory_are_refused(tmp_path):
    # The second run's outputs replaced the first's.
    with pytest.raises(ValueError, match="runs 0 and 1 both write into"):
        cosserat.grid(STRIP, tmp_path, **{"mesh.nx": [4, 4]})
    same = [cosserat.RunDescription.of(STRIP, tmp_path / "out", {"mesh.nx": n}) for n in (4, 8)]
    with pytest.raises(ValueError, match="runs 0 and 1 both write into"):
        sweep.run_local(same)
    with pytest.raises(ValueError, match="runs 0 and 1 both write into"):
        sweep.run_sweep(same, client=object())


def test_a_label_never_nests_or_leaves_the_output_root(tmp_path):
    runs = cosserat.grid(STRIP, tmp_path, **{"name": ["a/b", "../x"]})
    assert [r.label for r in runs] == ["name=a_b", "name=.._x"]
    assert all(os.path.dirname(r.out_dir) == str(tmp_path) for r in runs)


@pytest.mark.parametrize("overrides, error, message", [
    ("mesh.nx=8", TypeError, "overrides must be a dict"),
    (8, TypeError, "overrides must be a dict"),
    (["mesh.nx"], ValueError, "override `mesh.nx` is not of the form"),
    (["=8"], ValueError, "override `=8` is not of the form"),
    ([8], TypeError, "an override must be a \"key=value\" string"),
])
def test_a_description_with_malformed_overrides_is_refused(tmp_path, overrides, error, message):
    # A string was split into one override per character; an override without `=` broke the run's row
    # (ValueError inside `run`, which on Dask fails the task and the gathering of the whole sweep).
    with pytest.raises(error, match=message):
        cosserat.RunDescription.of(STRIP, tmp_path, overrides)


@pytest.mark.parametrize("threads, error", [(0, ValueError), (-1, ValueError), (10**6, ValueError),
                                            ("2", TypeError), (2.0, TypeError)])
def test_a_description_with_a_bad_thread_count_is_refused(tmp_path, threads, error):
    # -1 raised OverflowError inside `run`, outside the error row.
    with pytest.raises(error, match="RunDescription.threads must be"):
        cosserat.RunDescription.of(STRIP, tmp_path, {"mesh.nx": 8}, threads=threads)
    with pytest.raises(error, match="RunDescription.threads must be"):
        cosserat.grid(STRIP, tmp_path, threads=threads, **{"mesh.nx": [8]})


def test_descriptions_read_from_json_are_checked(tmp_path):
    path = tmp_path / "runs.json"
    path.write_text('{"scene": "a.toml"}')
    with pytest.raises(ValueError, match="expected a JSON list"):
        sweep.load_descriptions(path)
    path.write_text('[{"scene": "a.toml"}]')
    with pytest.raises(ValueError, match="lacks `out_dir`"):
        sweep.load_descriptions(path)
    assert cosserat.RunDescription.of(STRIP, tmp_path, None).overrides == ()
