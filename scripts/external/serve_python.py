#!/usr/bin/env python3
"""Serve an in-process Python estimator (a function of a scene's `type: python` entry,
algorithms/external/python_estimator.h) as a persistent external program (`type: external,
version: 2, persistent: true`): each request line's files are read into the arrays the
in-process request holds, the function is called, its answer written as a line.
Usage: serve_python.py [--path DIR]... MODULE [FUNCTION]   (FUNCTION defaults to estimate)
The same function then runs both ways: sandboxed in its own process, or in the
harness's (bench/perf/python_perf.cpp measures what each costs per call)."""
import argparse
import importlib
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from open3d_estimator import read_ply  # noqa: E402  (the same folder)


def columns(ply, names, dtype):
    return np.ascontiguousarray(np.stack([ply[n] for n in names], axis=1).astype(dtype))


def arrays_of(req):
    """The file-based request (external protocol, version 2) as the in-process one."""
    r = dict(req)
    ply = read_ply(req["cloud"])
    r["cloud"] = columns(ply, ("x", "y", "z"), np.float64)
    names = ply.dtype.names
    if "nx" in names:
        r["normals"] = columns(ply, ("nx", "ny", "nz"), np.float64)
    if "vx" in names:
        r["viewpoints"] = columns(ply, ("vx", "vy", "vz"), np.float64)
    if "red" in names:
        r["colours"] = columns(ply, ("red", "green", "blue"), np.uint8)
    r["views"] = [dict(v, pose=np.asarray(v["pose"], dtype=np.float64),
                       cloud=columns(read_ply(v["cloud"]), ("x", "y", "z"), np.float64))
                  for v in req.get("views", [])]
    if "train_labels" in req:
        r["train_labels"] = np.asarray(req["train_labels"], dtype=np.int64)
    for key in ("stereo", "image"):
        if key in req:
            import cv2
            r[key] = dict(req[key])
            for side in ("left", "right"):
                path = req[key][side]
                r[key][side] = None if path is None else np.ascontiguousarray(cv2.imread(path)[:, :, ::-1])
    r.pop("answer", None)
    return r


def plain(x):
    """numpy values as JSON's (the in-process reader accepts them as they are)."""
    if isinstance(x, dict):
        return {k: plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [plain(v) for v in x]
    return x.tolist() if hasattr(x, "tolist") else x


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--path", action="append", default=[], help="a folder put first on sys.path")
    ap.add_argument("module")
    ap.add_argument("function", nargs="?", default="estimate")
    args = ap.parse_args()
    for folder in reversed(args.path):
        sys.path.insert(0, folder)
    function = getattr(importlib.import_module(args.module), args.function)
    for line in sys.stdin:
        try:
            reply = plain(function(arrays_of(json.loads(line))))
        except Exception as e:  # noqa: BLE001 - the harness fails that request, naming it
            reply = {"error": "%s: %s" % (type(e).__name__, e)}
        sys.stdout.write(json.dumps(reply) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
