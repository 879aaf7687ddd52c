"""Estimators written in Python, run in-process (`type: python`,
algorithms/external/python_estimator.h): through the `grapebench` command (its own interpreter)
and through grapebench.run (the caller's), against the same Open3D hull run as a
persistent external program; errors and determinism."""
import os
import re
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import grapebench as gb

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
EXE = os.environ.get("GRAPEBENCH", str(ROOT / "build" / "bench" / "grapebench"))
SCENE = HERE / "data" / "in_process.yaml"
COLS = ["bunch", "estimator", "quantity", "estimate", "truth", "ok", "watertight", "notes"]


def run_cli(out, threads):
    p = subprocess.run([EXE, "-q", "run", str(SCENE), "--out", str(out), "--threads", str(threads)],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return pd.read_csv(out / "in_process" / "results.csv", keep_default_na=False)


@pytest.fixture(scope="module")
def cli_runs(tmp_path_factory):
    base = tmp_path_factory.mktemp("cli")
    return run_cli(base / "t1", 1), run_cli(base / "t2", 2)


def volumes(results, name):
    rows = results[(results["estimator"] == name) & (results["quantity"] == "volume")]
    return rows.sort_values("bunch")["estimate"].astype(float).tolist()


def test_in_process_gives_the_external_programs_volumes(cli_runs):
    r, _ = cli_runs
    external, in_process = volumes(r, "o3d_persistent"), volumes(r, "o3d_in_process")
    assert len(in_process) == 3 and in_process == external, (in_process, external)
    # Open3D's qhull and the built-in CGAL hull on the same cloud (results.csv's 6 digits).
    assert in_process == pytest.approx(volumes(r, "CH"), rel=1e-5)
    notes = r[r["estimator"] == "o3d_in_process"]["notes"].iloc[0]
    assert "multi_view" in notes and "convex_hull" in notes, notes


def test_keys_numpy_answers_and_several_quantities(cli_runs):
    r, _ = cli_runs
    sizes = r[r["estimator"] == "sizes_in_process"]
    assert sorted(set(sizes["quantity"])) == ["height", "length", "width"]
    assert (sizes["ok"].astype(int) == 1).all(), sizes["message"].tolist()
    h = sizes[sizes["quantity"] == "height"]["estimate"].astype(float)
    w = sizes[sizes["quantity"] == "width"]["estimate"].astype(float)
    assert (h.values > w.values).all()
    count, rest = sizes["notes"].iloc[0].split(" ", 1)
    assert int(count) > 100 and rest.startswith("points"), sizes["notes"].iloc[0]


def test_an_exception_is_a_failed_row_with_the_traceback_tail(cli_runs):
    r, _ = cli_runs
    bad = r[r["estimator"] == "raises"]
    assert len(bad) == 3 and (bad["ok"].astype(int) == 0).all()
    msg = bad["message"].iloc[0]
    assert "ValueError: no volume for" in msg and "in deeper" in msg and "test_estimators.py" in msg, msg
    # The other estimators of the same cases are untouched.
    assert (r[r["estimator"] == "CH"]["ok"].astype(int) == 1).all()


def test_results_do_not_depend_on_the_thread_count(cli_runs):
    one, two = cli_runs
    pd.testing.assert_frame_equal(one[COLS], two[COLS])


def test_grapebench_run_in_python_gives_the_commands_results(cli_runs, tmp_path):
    results, summary = gb.run(SCENE, out=tmp_path, threads=2)
    cli = cli_runs[0]
    assert volumes(results, "o3d_in_process") == pytest.approx(volumes(cli, "o3d_in_process"), rel=1e-12)
    assert summary["cases"] == 3


@pytest.mark.parametrize("entry, message", [
    ("{type: python, module: no_such_module_here}", "No module named 'no_such_module_here'"),
    ("{type: python, module: test_estimators, function: nope}", "has no 'nope'"),
    ("{type: python, module: test_estimators, params: [1, 2]}", "expected a mapping"),
    ("{type: python}", "module"),
])
def test_a_bad_entry_fails_when_the_scene_is_read(tmp_path, entry, message):
    entry = entry.replace("}", ", path: [\"%s\"]}" % (HERE / "data")) if "module" in entry else entry
    text = SCENE.read_text().split("estimators:")[0] + "estimators:\n  - " + entry + "\n"
    scene = tmp_path / "bad_in_process.yaml"
    scene.write_text(text)
    p = subprocess.run([EXE, "-q", "run", str(scene), "--out", str(tmp_path)], capture_output=True, text=True)
    with pytest.raises(gb.InputError, match=re.escape(message)):
        gb.Scene.from_file(scene)
    assert p.returncode == 2, p.stderr
    assert message in p.stderr and "bad_in_process.yaml:" in p.stderr, p.stderr
    assert not (tmp_path / "in_process").exists()


@pytest.mark.parametrize("function, message", [
    ("not_json", "not a JSON value"),
    ("wrong_range", "outside (0, 1000]"),
])
def test_an_answer_outside_the_protocol_fails_its_row(tmp_path, function, message):
    text = SCENE.read_text().split("estimators:")[0] + \
        "estimators:\n  - {type: python, module: test_estimators, function: %s}\n" % function
    results, _ = gb.run(gb.Scene(text.replace("name: in_process", "name: answers"), str(HERE / "data" / "x.yaml")),
                        out=tmp_path)
    assert (results["ok"] == 0).all() and results["message"].str.contains(message, regex=False).all(), \
        results["message"].tolist()
    assert results["message"].str.contains("python estimator 'test_estimators.%s'" % function).all()


def test_arrays_the_function_keeps_stay_its_own(tmp_path):
    import sys
    text = SCENE.read_text().split("estimators:")[0] + \
        "estimators:\n  - {type: python, module: test_estimators, function: keeps_the_cloud}\n"
    results, _ = gb.run(gb.Scene(text.replace("name: in_process", "name: keeps"), str(HERE / "data" / "x.yaml")),
                        out=tmp_path, threads=2)
    assert (results["ok"] == 1).all(), results["message"].tolist()
    kept = sys.modules["test_estimators"].keeps_the_cloud.kept  # the module the harness imported: this process's
    assert len(kept) == 3
    for i, a in enumerate(kept):
        assert a.shape[1] == 3 and np.isfinite(a).all() and np.ptp(a, axis=0).max() < 0.5
        for b in kept[i + 1:]:
            assert not np.shares_memory(a, b)
    # Each is the cloud of a different bunch (pooled memory is never handed out twice).
    assert len({round(float(a.sum()), 9) for a in kept}) == 3


def test_a_second_module_of_the_same_name_is_refused(tmp_path):
    gb.Scene.from_file(SCENE)  # imports tests/python/data/test_estimators.py
    other = tmp_path / "test_estimators.py"
    other.write_text("def principal_sizes(request):\n    return {'volume': 1e-6}\n")
    text = SCENE.read_text().split("estimators:")[0] + \
        "estimators:\n  - {type: python, module: test_estimators, function: principal_sizes}\n"
    with pytest.raises(gb.InputError, match="already imported from .*tests/python/data/test_estimators.py"):
        gb.Scene(text, str(tmp_path / "x.yaml"))


def test_the_time_budget_stops_a_function_that_never_returns(tmp_path):
    text = SCENE.read_text().split("estimators:")[0] + \
        "estimators:\n  - {type: python, module: test_estimators, function: spins, time_budget: 1}\n"
    results, _ = gb.run(gb.Scene(text.replace("name: in_process", "name: spins"), str(HERE / "data" / "x.yaml")),
                        out=tmp_path, threads=2)
    assert (results["ok"] == 0).all() and results["message"].str.contains("time budget").all(), \
        results["message"].tolist()
