"""grapebench from Python: scenes, bunches with their exact truth as numpy arrays, the
registered estimators on numpy clouds, and whole runs as pandas DataFrames.

    import grapebench as gb
    scene = gb.Scene.from_file("scenes/default.yaml")
    bunch = gb.synth(scene, 0)            # arrays in metres, bunch["truth"] a dict
    gb.estimate("convex_hull", bunch["berry_centres"])["values"]["volume"]
    results, summary = gb.run(scene)      # results.csv as a DataFrame, summary.json as a dict

Every registered type is also an object with its key table as docstring:
help(gb.estimator.alpha_shape), gb.sensor.kinect_v2.defaults, gb.rig.turntable.spec(views=12).

Bad input raises grapebench.InputError (a ValueError) naming the file, line, key and the
allowed range, as the command line's exit code 2 does. docs/python.md has the rest.
"""
import json
import os
import tempfile
from pathlib import Path

import numpy as np

from . import _grapebench
from ._grapebench import InputError
from . import estimator, filter, protocol, registration, rig, scoring, sensor  # noqa: A004 (types, docs from key tables)

__all__ = ["InputError", "Scene", "synth", "scan", "estimators", "estimate", "run", "estimator", "sensor", "rig",
           "registration", "filter", "protocol", "scoring"]


class Scene:
    """A scene file (YAML) read by the harness's strict reader, its sweep expanded."""

    def __init__(self, source, name="scene.yaml"):
        """source: YAML text or a dict of the same keys (see scenes/README.md)."""
        if isinstance(source, dict):
            source = json.dumps(source)  # JSON is YAML; errors then name the key and its line here
        if not isinstance(source, str):
            raise TypeError("Scene(source): YAML text or a dict; Scene.from_file(path) for a file")
        self._set = _grapebench.parse_scene_set(source, name)

    @classmethod
    def from_text(cls, text, name="scene.yaml"):
        return cls(text, name)

    @classmethod
    def from_file(cls, path):
        scene = cls.__new__(cls)
        scene._set = _grapebench.load_scene_set(os.fspath(path))
        return scene

    name = property(lambda self: self._set.name)
    seed = property(lambda self: self._set.seed)
    protocol = property(lambda self: self._set.protocol)
    conditions = property(lambda self: list(self._set.conditions), doc="the sweep's condition labels")
    bunch_count = property(lambda self: self._set.bunch_count)

    def to_dict(self):
        """Every key with its value in force (defaults filled in), as the run's manifest."""
        return json.loads(self._set.scene_json())

    def __repr__(self):
        return (f"Scene({self.name!r}, protocol={self.protocol!r}, {self.bunch_count} bunches, "
                f"{len(self.conditions)} conditions)")


def synth(scene, index=0, mesh=False):
    """Bunch `index` of the scene, exactly as `grapebench run` makes it: berry_centres
    (N x 3, m), berry_radii (N, m), stem_starts / stem_ends (M x 3, m), stem_radii (M, m),
    stem_parts (M names), cutting_point (3, m) and truth (the dict `grapebench synth`
    writes: volume, sizes, berry count, ...). mesh=True adds mesh: the surface `grapebench
    synth` writes, vertices (V x 3, m), faces (F x 3), face_part (F names) and face_berry
    (F, -1 for stems)."""
    d = _grapebench.synth_bunch(_scene_set(scene), index, mesh)
    d["truth"] = json.loads(d.pop("truth_json"))
    return d


def scan(scene, index=0):
    """The scan of bunch `index` as `grapebench run` captures it: one dict per view with
    name, pose (4 x 4 camera to world), intrinsics (width, height, fx, fy, cx, cy; OpenCV's
    pixel centres), and H x W arrays in the sensor frame (x right, y down, z forward):
    valid (uint8), label (uint8, synth's part ids), berry (int32, -1 where none), xyz and
    normal (H x W x 3 float32, m, NaN without a return), rgb (H x W x 3 uint8),
    true_depth (float32, m, noise-free, 0 where nothing is seen); left_image and
    right_image (H x W x 3 uint8) for colour stereo sensors, else None. The arrays share
    the scan's memory (no copies); valid and label are copies."""
    return list(_grapebench.scan_bunch(_scene_set(scene), index))


def estimators():
    """The registered estimator types (a scene's `estimators: [{type: ...}]`)."""
    return list(_grapebench.estimator_types())


INPUTS = ("normals", "viewpoints", "colours", "classes", "train_labels", "left", "right", "camera")


def estimate(type, points=None, **keys):
    """Run a registered estimator on numpy input with its keys, e.g.
    estimate("alpha_shape", pts, alpha=0.01). By the estimator's input kind:
      cloud: points (N x 3, m), and normals / viewpoints (N x 3) where it uses them;
      labelled_cloud: points, colours (N x 3 uint8), classes (K names), train_labels
        (N: a class index, or -1 where to score);
      image: left (H x W x 3 uint8, RGB) and camera {fx, fy, cx, cy} (px, OpenCV's pixel
        centres), right too when it has one;
      stereo_pair: left, right (rectified) and camera {fx, fy, cx, cy, baseline (m)}.
    Returns values ({quantity: SI value}), points (named 3D points), detections,
    instances, class_scores (N x K), notes, error ("" when it succeeded), input (its
    kind) and params (every key in force)."""
    inputs = {k: keys.pop(k) for k in INPUTS if k in keys}
    if points is not None:
        pts = np.ascontiguousarray(points, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise InputError(f"points: expected N x 3 (metres), got shape {pts.shape}")
        inputs["points"] = pts
    for k in ("normals", "viewpoints"):
        if k in inputs:
            inputs[k] = np.ascontiguousarray(inputs[k], dtype=np.float64)
    for k in ("colours", "left", "right"):
        if k in inputs:
            inputs[k] = np.ascontiguousarray(inputs[k], dtype=np.uint8)
    if "train_labels" in inputs:
        inputs["train_labels"] = [int(v) for v in np.asarray(inputs["train_labels"]).ravel()]
    if "classes" in inputs:
        inputs["classes"] = [str(c) for c in inputs["classes"]]
    spec = json.dumps({"type": type, **keys})
    d = _grapebench.estimate(spec, inputs)
    d["params"] = json.loads(d.pop("params_json"))
    return d


def run(scene, out=None, threads=0, quiet=True, progress=True, cycles_cache=None):
    """Run a scene as `grapebench run` does; returns (results, summary): results.csv as a
    pandas DataFrame and summary.json as a dict. out: the results folder (a temporary
    one, removed afterwards, when None); threads 0 uses every core. progress: True for a
    line on stderr updated after each case (in notebooks too), False for none, or a
    callable progress(done, total, detail, failed) called after each case.
    cycles_cache: a folder to keep Cycles' images in and reuse (`renderer: cycles`, as
    `grapebench run --cycles-cache`); None: the results folder's cycles_cache/, so with
    out=None every run renders them again."""
    import pandas as pd

    s = _scene_set(scene)
    if out is None:
        with tempfile.TemporaryDirectory(prefix="grapebench_") as tmp:
            return run(scene, tmp, threads, quiet, progress, cycles_cache)
    callback = _ProgressLine(s.name) if progress is True else progress or None
    cache = "" if cycles_cache is None else os.fspath(cycles_cache)
    _grapebench.run(s, os.fspath(out), threads, quiet, callback, cache)
    if isinstance(callback, _ProgressLine):
        callback.finish()
    folder = Path(out) / s.name
    results = pd.read_csv(folder / "results.csv")
    summary = json.loads((folder / "summary.json").read_text())
    return results, summary


class _ProgressLine:
    """One line on stderr, rewritten after each case: "scene: 12/40 cases, 1 failed"."""

    def __init__(self, name):
        self.name, self.failed, self.shown = name, 0, False

    def __call__(self, done, total, detail, failed):
        import sys
        self.failed += bool(failed)
        tail = ", %d failed" % self.failed if self.failed else ""
        sys.stderr.write("\r%s: %d/%d cases%s (last: %s)" % (self.name, done, total, tail, detail))
        sys.stderr.flush()
        self.shown = True

    def finish(self):
        import sys
        if self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _scene_set(scene):
    if isinstance(scene, Scene):
        return scene._set
    if isinstance(scene, os.PathLike) or (isinstance(scene, str) and "\n" not in scene and _is_file(scene)):
        return Scene.from_file(scene)._set
    return Scene(scene)._set


def _is_file(text):
    try:
        return Path(text).is_file()
    except (OSError, ValueError):  # a name too long, or with a NUL: not a file
        return False
