#!/usr/bin/python3
"""Regenerates docs/images/ from scan outputs (Debian's python3-open3d and numpy).

    build/bench/grapebench scan scenes/readme_presets.yaml --out /tmp/readme
    build/bench/grapebench scan scenes/seed000_kinect_turntable.yaml --bunch 0 --out /tmp/readme
    /usr/bin/python3 scripts/make_readme_images.py /tmp/readme docs/images
"""
import json
import sys

import numpy as np
import open3d as o3d

src, dst = sys.argv[1], sys.argv[2]


def save(path, img):
    o3d.io.write_image(path, o3d.geometry.Image(np.ascontiguousarray(img.astype(np.uint8))))


# 1. One colour image per preset (left camera, 0.75 m), cropped to the bunch.
names = ["table-red", "wine-red", "summer-black", "green-table"]
tiles = []
for i, name in enumerate(names):
    img = np.asarray(o3d.io.read_image(f"{src}/readme_presets/bunch_{i:04d}/bunch_{i:04d}_station_0750mm_left.png"))
    tiles.append(img[40:560, 200:600])
save(f"{dst}/presets.png", np.concatenate(tiles, 1))

# 2. A 12-view Kinect v2 turntable scan: views 0, 3, 6 as colour, depth and labels,
#    and all views merged in the world frame, seen from the side.
base = f"{src}/seed000_kinect_turntable/bunch_0000"
manifest = json.load(open(f"{base}/bunch_0000_scan.json"))
palette = np.zeros((256, 3), np.uint8)
palette[:5] = [[200, 60, 160], [200, 220, 50], [40, 160, 40], [140, 90, 30], [150, 150, 150]]
rows = []
for view in ["view_00", "view_03", "view_06"]:
    rgb = np.asarray(o3d.io.read_image(f"{base}/bunch_0000_{view}_rgb.png"))
    d = np.asarray(o3d.io.read_image(f"{base}/bunch_0000_{view}_depth.png")).astype(float)
    lab = np.asarray(o3d.io.read_image(f"{base}/bunch_0000_{view}_label.png"))
    valid = d > 0
    g = np.zeros_like(d)
    lo, hi = np.percentile(d[valid], [1, 99])
    g[valid] = 1 - np.clip((d[valid] - lo) / (hi - lo + 1e-9), 0, 1)
    depth = np.stack([g * 255] * 3, -1)
    depth[~valid] = [90, 0, 0]
    crop = (slice(120, 330), slice(190, 330))
    rows.append(np.concatenate([rgb[crop], depth[crop], palette[lab][crop]], 1))
save(f"{dst}/kinect_views.png", np.kron(np.concatenate(rows, 0), np.ones((2, 2, 1))))

merged, colours, normals = [], [], []
for v in manifest["views"]:
    pcd = o3d.io.read_point_cloud(f"{base}/{v['files'][1]}")
    T = np.array(v["camera_to_world"])
    p = np.asarray(pcd.points) @ T[:3, :3].T + T[:3, 3]
    keep = np.linalg.norm(p[:, :2], axis=1) < 0.15  # the bunch, not the plate
    merged.append(p[keep])
    colours.append(np.asarray(pcd.colors)[keep])
    normals.append((np.asarray(pcd.normals) @ T[:3, :3].T)[keep])
p, c = np.concatenate(merged), np.concatenate(colours)
W, H, s = 400, 520, 0.30 / 520
img = np.full((H, W, 3), 255.0)
zbuf = np.full((H, W), np.inf)
u = ((p[:, 0] - p[:, 0].mean()) / s + W / 2).astype(int)
v = ((p[:, 2].max() + 0.02 - p[:, 2]) / s).astype(int)
light = 0.55 + 0.45 * np.clip(-np.concatenate(normals)[:, 1], 0, 1)
for k in np.argsort(p[:, 1])[::-1]:
    for du in (0, 1):
        for dv in (0, 1):
            x, y = u[k] + du, v[k] + dv
            if 0 <= x < W and 0 <= y < H and p[k, 1] < zbuf[y, x]:
                zbuf[y, x] = p[k, 1]
                img[y, x] = np.clip(c[k] * 255 * light[k] * 1.6, 0, 255)
save(f"{dst}/kinect_merged.png", img)
print("wrote", dst)
