"""`grapebench estimate` on clouds Open3D wrote (issue 22): binary and ASCII PLY and PCD
of the harness's own merged scan give the volumes the harness computed in `run` on the
same points, and the convex hull agrees with Open3D's.

usage: estimate_test.py <grapebench> <scene.yaml> <scratch folder>
"""
import csv
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import open3d as o3d


def main():
    exe, scene, scratch = sys.argv[1], sys.argv[2], Path(sys.argv[3])
    shutil.rmtree(scratch, ignore_errors=True)
    quiet = dict(check=True, stdout=subprocess.DEVNULL)
    subprocess.run([exe, "run", scene, "-q", "--out", str(scratch / "run")], **quiet)
    subprocess.run([exe, "scan", scene, "--merged", "-q", "--out", str(scratch / "scan")], **quiet)
    with open(scratch / "run" / "ideal_turntable" / "results.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["quantity"] == "volume"]
    harness = {r["estimator"]: float(r["estimate"]) for r in rows}
    harness_points = {int(r["points"]) for r in rows}
    merged = o3d.io.read_point_cloud(str(scratch / "scan" / "ideal_turntable" / "bunch_0000" / "bunch_0000_merged.ply"))
    assert harness_points == {len(merged.points)}, (harness_points, len(merged.points))
    hull_o3d = merged.compute_convex_hull()[0].get_volume() * 1e6
    files = []
    for name, ascii in [("o3d_binary.ply", False), ("o3d_ascii.ply", True), ("o3d_binary.pcd", False),
                        ("o3d_ascii.pcd", True)]:
        path = scratch / name
        assert o3d.io.write_point_cloud(str(path), merged, write_ascii=ascii)
        files.append(path)
    for path in files:
        answer_file = path.with_suffix(path.suffix + ".json")
        subprocess.run([exe, "estimate", str(path), str(Path(scene)), "--json", str(answer_file)], **quiet)
        answer = json.loads(answer_file.read_text())
        assert answer["points"] == len(merged.points), answer["points"]
        got = {e["name"]: e["values"]["volume"]["value"] for e in answer["estimators"]}
        for name, value in harness.items():
            # results.csv keeps 9 significant digits; ASCII files round coordinates further.
            tol = 1e-4 if "ascii" in path.name else 1e-6
            assert abs(got[name] - value) <= tol * value, (path.name, name, got[name], value)
        assert abs(got["CH"] - hull_o3d) <= 1e-4 * hull_o3d, (path.name, got["CH"], hull_o3d)
        print(f"{path.name}: CH {got['CH']:.4f} cm3 (harness {harness['CH']:.4f}, Open3D {hull_o3d:.4f}), "
              f"AS {got['AS']:.4f} cm3 (harness {harness['AS']:.4f})")


if __name__ == "__main__":
    main()
