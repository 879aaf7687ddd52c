"""`import grapebench` (python/): every public function against the command line's
answer for the same input, and its errors. Run by ctest (Python.Package) with
PYTHONPATH=<build>/python and GRAPEBENCH=<the grapebench executable>."""
import json
import math
import re
import shutil
import os
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import grapebench as gb

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
EXE = os.environ.get("GRAPEBENCH", str(ROOT / "build" / "bench" / "grapebench"))
TWO = ROOT / "tests" / "bench" / "data" / "two_bunches_hull.yaml"
TINY_CYCLES = ROOT / "tests" / "bench" / "data" / "cycles_pair_tiny.yaml"


def fibonacci_sphere(n, r):
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    phi = math.pi * (3 - math.sqrt(5)) * i
    s = np.sqrt(1 - z * z)
    return r * np.column_stack([s * np.cos(phi), s * np.sin(phi), z])


def test_scene_from_file_text_and_dict_are_the_same_scene():
    a = gb.Scene.from_file(TWO)
    b = gb.Scene(TWO.read_text(), "two.yaml")
    doc = {"name": "two_bunches_hull", "seed": 11, "bunches": [{"preset": "table-red", "count": 2}],
           "sensor": {"type": "ideal", "width": 160, "height": 120},
           "rig": {"type": "turntable", "views": 4, "step_deg": 90, "distance": 0.6},
           "pipeline": {"registration": "true_poses"}, "estimators": [{"type": "convex_hull", "name": "CH"}]}
    c = gb.Scene(doc)
    assert (a.name, a.seed, a.protocol, a.bunch_count) == ("two_bunches_hull", 11, "multi_view", 2)
    assert a.to_dict() == b.to_dict() == c.to_dict()
    assert "Scene('two_bunches_hull'" in repr(a)


def test_a_bad_scene_names_file_line_key_and_range():
    with pytest.raises(gb.InputError) as e:
        gb.Scene("name: x\nseed: 1\nbunches:\n  - preset: table-red\n    count: 0\n", "bad.yaml")
    msg = str(e.value)
    assert "bad.yaml:5" in msg and "count" in msg, msg
    with pytest.raises(gb.InputError, match="frobnicate"):
        gb.Scene("name: x\nseed: 1\nbunches:\n  - preset: table-red\nfrobnicate: 1\n")
    with pytest.raises(ValueError):  # InputError is a ValueError
        gb.Scene.from_file(ROOT / "no_such_scene.yaml")


def test_synth_gives_the_bunch_and_truth_of_grapebench_synth(tmp_path):
    scene = gb.Scene.from_file(TWO)
    b = gb.synth(scene, 1)
    n = b["berry_centres"].shape[0]
    assert b["berry_centres"].shape == (n, 3) and b["berry_radii"].shape == (n,) and n > 10
    assert b["stem_starts"].shape == b["stem_ends"].shape and len(b["stem_parts"]) == b["stem_radii"].shape[0]
    assert {"peduncle", "rachis", "pedicel"} <= set(b["stem_parts"])
    # The command line's truth file for the same scene and bunch is the same document.
    subprocess.run([EXE, "-q", "synth", str(TWO), "--out", str(tmp_path), "--no-mesh"], check=True)
    files = sorted(tmp_path.glob("bunch_*.json"))
    assert len(files) == 2, files
    assert json.loads(files[1].read_text()) == b["truth"]
    assert b["truth"]["berry_count"] == n
    assert np.allclose(b["cutting_point"], b["truth"]["cutting_point_m"], rtol=0, atol=0)
    with pytest.raises(gb.InputError, match=r"out of range \[0, 1\]"):
        gb.synth(scene, 2)


def test_estimate_convex_hull_of_a_sphere():
    assert "convex_hull" in gb.estimators()
    r = 0.05
    e = gb.estimate("convex_hull", fibonacci_sphere(20000, r))
    assert e["error"] == ""
    assert e["values"]["volume"] == pytest.approx(4 / 3 * math.pi * r ** 3, rel=2e-3)
    assert e["params"]["type"] == "convex_hull"


def test_estimate_rejects_bad_points_and_keys():
    with pytest.raises(gb.InputError, match="N x 3"):
        gb.estimate("convex_hull", np.zeros((5, 2)))
    pts = fibonacci_sphere(100, 0.05)
    pts[7, 1] = np.nan
    with pytest.raises(gb.InputError, match="row 7"):
        gb.estimate("convex_hull", pts)
    with pytest.raises(gb.InputError, match="no_such_key"):
        gb.estimate("convex_hull", fibonacci_sphere(100, 0.05), no_such_key=1)
    with pytest.raises(gb.InputError, match="type"):
        gb.estimate("no_such_estimator", fibonacci_sphere(100, 0.05))


def test_run_returns_the_command_lines_results(tmp_path):
    results, summary = gb.run(TWO, out=tmp_path / "py", threads=2)
    subprocess.run([EXE, "-q", "run", str(TWO), "--out", str(tmp_path / "cli")], check=True)
    cli = pd.read_csv(tmp_path / "cli" / "two_bunches_hull" / "results.csv")
    assert len(results) == len(cli) > 0
    cols = ["bunch", "estimator", "quantity", "estimate", "truth"]
    pd.testing.assert_frame_equal(results[cols], cli[cols])
    assert summary["scene"] == "two_bunches_hull" and summary["cases"] == 2, summary["scene"]


def test_run_keeps_cycles_images_in_the_folder_given(tmp_path, monkeypatch):
    # out=None throws the run folder away; cycles_cache keeps the images across runs.
    # A fake Blender answers black images, then crashes: the second run reads the first's.
    if subprocess.run(["bwrap", "--ro-bind", "/", "/", "--dev", "/dev", "--proc", "/proc", "--unshare-all", "true"],
                      capture_output=True).returncode != 0:
        pytest.skip("bubblewrap cannot make namespaces here (Blender runs under it)")
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    shutil.copy(ROOT / "tests" / "bench" / "data" / "fake_blender.sh", bin_dir / "blender")
    (bin_dir / "blender").chmod(0o700)
    monkeypatch.setenv("GRAPEBENCH_BLENDER", str(bin_dir / "blender"))
    first, _ = gb.run(TINY_CYCLES, threads=1, progress=False, cycles_cache=tmp_path / "cache")
    assert len(list((tmp_path / "cache").iterdir())) == 4  # a pair, 2 files an image
    (bin_dir / "crash").touch()
    again, _ = gb.run(TINY_CYCLES, threads=1, progress=False, cycles_cache=tmp_path / "cache")
    pd.testing.assert_frame_equal(first, again)
    assert not first["error"].fillna("").str.contains("Blender").any()


def test_the_interpreter_runs_while_an_estimator_does():
    # The GIL is released inside the C++ call: a Python thread keeps counting meanwhile.
    points = fibonacci_sphere(400000, 0.05)  # made before: only the call is watched
    started, done = threading.Event(), threading.Event()
    count = 0

    def work():
        started.set()
        gb.estimate("convex_hull", points)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    started.wait()
    while not done.is_set():
        count += 1
    t.join()
    # Holding the GIL, the call would leave this loop one turn (5 ms) at most.
    assert count > 100000, count


def test_scan_hands_out_each_views_arrays_without_copies(tmp_path):
    views = gb.scan(gb.Scene.from_file(TWO), 0)
    assert [v["name"] for v in views] == ["view_00", "view_01", "view_02", "view_03"]
    v = views[1]
    h, w = v["intrinsics"]["height"], v["intrinsics"]["width"]
    assert (h, w) == (120, 160) and v["pose"].shape == (4, 4)
    assert v["xyz"].shape == v["normal"].shape == v["rgb"].shape == (h, w, 3)
    assert v["xyz"].dtype == np.float32 and v["berry"].dtype == np.int32 and v["label"].shape == (h, w)
    # No copies: the big arrays are views of the one scan object their base holds.
    for key in ("xyz", "normal", "rgb", "berry", "true_depth"):
        assert not v[key].flags.owndata and v[key].base is v["xyz"].base is not None, key
    valid = v["valid"] == 1
    assert 100 < valid.sum() < h * w
    assert np.isfinite(v["xyz"][valid]).all() and np.isnan(v["xyz"][~valid]).all()
    assert np.allclose(np.linalg.norm(v["normal"][valid], axis=1), 1, atol=1e-5)
    assert v["left_image"] is None  # a depth sensor
    # The points `grapebench scan` writes for that view (its PLY: valid points, sensor frame).
    subprocess.run([EXE, "-q", "scan", str(TWO), "--bunch", "0", "--out", str(tmp_path)], check=True)
    ply = sorted(tmp_path.rglob("*view_01*.ply"))
    assert ply, sorted(p.name for p in tmp_path.rglob("*"))
    data = ply[0].read_bytes()
    header, body = data.split(b"end_header\n", 1)
    assert int(re.search(rb"element vertex (\d+)", header).group(1)) == valid.sum()
    # The arrays outlive the list they came in (their base keeps the scan alive).
    xyz = views[0]["xyz"]
    del views, v
    assert np.isfinite(xyz[~np.isnan(xyz[..., 0])]).all()


def test_run_reports_progress_after_each_case(tmp_path, capsys):
    seen = []
    gb.run(TWO, out=tmp_path / "a", threads=2, progress=lambda *a: seen.append(a))
    assert sorted(s[0] for s in seen) == [1, 2] and {s[1] for s in seen} == {2}
    assert all(s[2].startswith("condition 0, bunch ") and s[3] is False for s in seen)
    gb.run(TWO, out=tmp_path / "b", threads=2)  # the default: a line on stderr
    err = capsys.readouterr().err
    assert "two_bunches_hull: 2/2 cases" in err and err.endswith("\n")

    def broken(*a):
        raise RuntimeError("a progress callback that fails")
    reported = []
    hook, sys.unraisablehook = sys.unraisablehook, reported.append
    try:
        results, _ = gb.run(TWO, out=tmp_path / "c", threads=2, progress=broken)  # the run goes on
    finally:
        sys.unraisablehook = hook
    assert len(results) == 2
    assert len(reported) == 2 and "fails" in str(reported[0].exc_value)


def test_synth_mesh_is_the_surface_grapebench_synth_writes(tmp_path):
    b = gb.synth(gb.Scene.from_file(TWO), 0, mesh=True)
    m = b["mesh"]
    assert m["vertices"].shape[1] == 3 and m["faces"].shape[1] == 3 and m["faces"].max() < len(m["vertices"])
    assert len(m["face_part"]) == len(m["faces"]) == len(m["face_berry"]) and "berry" in set(m["face_part"])
    # Its volume (signed tetrahedra) is the exact solid's, as the truth says it is.
    v = m["vertices"][m["faces"]]
    volume = np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6
    assert volume * 1e6 == pytest.approx(b["truth"]["solid_volume_cm3"], rel=0.02)
    subprocess.run([EXE, "-q", "synth", str(TWO), "--out", str(tmp_path)], check=True)
    ply = sorted(tmp_path.glob("bunch_*.ply"))[0].read_bytes().split(b"end_header", 1)[0]
    assert int(re.search(rb"element vertex (\d+)", ply).group(1)) == len(m["vertices"])
    assert int(re.search(rb"element face (\d+)", ply).group(1)) == len(m["faces"])


def test_image_stereo_and_labelled_estimators_run_on_numpy_input():
    # A labelled cloud: two colour blobs, half of each labelled; the classifier scores all.
    rng = np.random.default_rng(5)
    pts = np.vstack([rng.normal(0, 0.01, (200, 3)), rng.normal(0.1, 0.01, (200, 3))])
    colours = np.vstack([np.tile([40, 30, 80], (200, 1)), np.tile([60, 140, 40], (200, 1))]).astype(np.uint8)
    labels = np.r_[np.where(np.arange(200) % 2 == 0, 0, -1), np.where(np.arange(200) % 2 == 0, 1, -1)]
    e = gb.estimate("dey2012_classification", pts, colours=colours, classes=["berry", "leaf"], train_labels=labels)
    assert e["input"] == "labelled_cloud" and e["class_scores"].shape == (400, 2), e["error"]
    assert (e["class_scores"][:200].argmax(axis=1) == 0).mean() > 0.9
    assert (e["class_scores"][200:].argmax(axis=1) == 1).mean() > 0.9
    # An image estimator on a plain image: it answers (no bunch: no instances) and says so.
    img = np.full((120, 160, 3), 90, np.uint8)
    cam = {"fx": 200.0, "fy": 200.0, "cx": 79.5, "cy": 59.5}
    e = gb.estimate("luo2016_instances", left=img, camera=cam, depth=1.0)  # no right image: its distance
    assert e["input"] == "image" and isinstance(e["instances"], list)
    e = gb.estimate("luo2016_stereo", left=img, right=img, camera=dict(cam, baseline=0.06))
    assert e["input"] == "stereo_pair"
    with pytest.raises(gb.InputError, match="right"):
        gb.estimate("luo2016_stereo", left=img, camera=dict(cam, baseline=0.06))
    with pytest.raises(gb.InputError, match="H x W x 3"):
        gb.estimate("luo2016_instances", left=img[:, :, 0], camera=cam, depth=1.0)
    with pytest.raises(gb.InputError, match="train_labels"):
        gb.estimate("dey2012_classification", pts, colours=colours, classes=["berry", "leaf"],
                    train_labels=np.full(400, 5))
