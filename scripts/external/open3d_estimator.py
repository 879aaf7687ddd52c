#!/usr/bin/env python3
"""A grapebench external estimator in Python with Open3D and numpy (Debian:
python3-open3d, python3-numpy).

Protocol (algorithms/README.md; JSON Schema: docs/external-protocol.schema.json):
  per case:    grapebench runs  <command...> <request.json>  and reads the file named
               by the request's "answer";
  persistent:  grapebench runs  <command...>  once (per worker thread) and writes one
               request per line on stdin; the program answers one JSON line each on
               stdout (run this script with --persistent).
A request names the cloud (binary PLY, x y z in metres; in version 2 also nx ny nz,
vx vy vz (the camera centre of each point) and red green blue where the protocol has
them), the quantities wanted and, in version 2, the individual views with their poses
(multi_view) or the frame and its ROI (single_frame). The answer holds one number per
quantity (volume in m3, lengths in m) and optionally "watertight" and "notes".

In-process (a scene's {type: python, module: open3d_estimator, path: [...]}; docs/python.md):
grapebench calls estimate(request) with the same request, arrays in place of files
("cloud" N x 3, "normals", "viewpoints"), and reads the same answer; the request's
"params" ({method, alpha, depth}) choose the method there.

Methods: convex_hull (Open3D's qhull), poisson (depth 8; normals from the sensor,
turned toward each point's camera, where version 2 hands them over, else estimated
and turned away from the centroid), alpha_shape (--alpha, metres). Lengths (height,
length, width, size_major, size_minor) are the extents along the cloud's principal axes.
"""
import argparse
import json
import sys

import numpy as np
import open3d as o3d

PROTOCOLS = ("grapebench-estimator-1", "grapebench-estimator-2")
METHODS = ("convex_hull", "poisson", "alpha_shape")
PLY_TYPES = {"double": "<f8", "float": "<f4", "uchar": "u1", "int": "<i4"}


def read_ply(path):
    """A binary little-endian PLY of one vertex element as a numpy structured array."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError("%s: not a PLY file" % path)
        fields, count = [], 0
        while True:
            line = f.readline().decode("ascii").split()
            if not line:
                continue
            if line[0] == "element":
                count = int(line[2])
            elif line[0] == "property":
                fields.append((line[2], PLY_TYPES[line[1]]))
            elif line[0] == "end_header":
                break
        return np.frombuffer(f.read(), dtype=np.dtype(fields), count=count)


def principal_extents(xyz):
    """Extents along the principal axes, largest first."""
    centred = xyz - xyz.mean(axis=0)
    _, vectors = np.linalg.eigh(centred.T @ centred)
    extent = np.ptp(centred @ vectors, axis=0)
    return np.sort(extent)[::-1]


def volume_of(method, alpha, depth, xyz, normals, viewpoints):
    pcd = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(xyz))
    if method == "convex_hull":
        mesh, _ = pcd.compute_convex_hull()
    elif method == "alpha_shape":
        mesh = o3d.geometry.TriangleMesh.create_from_point_cloud_alpha_shape(pcd, alpha)
    else:
        if normals is not None and viewpoints is not None:
            n = normals.copy()  # the sensor's normals, turned toward each point's camera
            n[np.einsum("ij,ij->i", n, viewpoints - xyz) < 0] *= -1
        else:
            pcd.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(20))
            n = np.asarray(pcd.normals)
            n[np.einsum("ij,ij->i", n, xyz - xyz.mean(axis=0)) < 0] *= -1
        pcd.normals = o3d.utility.Vector3dVector(n)
        mesh, _ = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(pcd, depth=depth)
    # Closed: every edge has two triangles and every vertex one fan. (Open3D's
    # is_watertight() also tests self-intersection, quadratic in the triangles: 15 s
    # on an 80k-triangle hull; get_volume() repeats it.) The volume is the signed
    # tetrahedron sum (seed 000 Eq. 11), exact for a closed mesh, and still defined on
    # an open one, where the answer says so.
    watertight = bool(mesh.is_edge_manifold(allow_boundary_edges=False) and mesh.is_vertex_manifold())
    v = np.asarray(mesh.vertices)
    t = np.asarray(mesh.triangles)
    volume = abs(np.einsum("ij,ij->i", v[t[:, 0]], np.cross(v[t[:, 1]], v[t[:, 2]])).sum() / 6.0)
    return float(volume), watertight, len(t)


def measure(req, xyz, normals, viewpoints, method, alpha, depth):
    """The answer to a request whose cloud is xyz (N x 3, m)."""
    if req.get("protocol") not in PROTOCOLS:
        raise ValueError("unknown protocol %r" % req.get("protocol"))
    out, notes = {}, ["open3d %s" % o3d.__version__, req["protocol"]]
    if req.get("kind"):
        notes.append(req["kind"])
    if req.get("views"):
        notes.append("%d views" % len(req["views"]))
    if req.get("frame"):
        notes.append("frame %d %s" % (req["frame"]["index"], req["frame"]["roi"]))
    if req.get("attributes"):
        notes.append("+".join(req["attributes"]))
    extents = principal_extents(xyz)
    for q in req["quantities"]:
        if q == "volume":
            out["volume"], out["watertight"], triangles = volume_of(method, alpha, depth, xyz, normals, viewpoints)
            notes.append("%s %d triangles" % (method, triangles))
        elif q in ("height", "length", "width"):
            out[q] = float(extents[("height", "length", "width").index(q)])
        elif q in ("size_major", "size_minor"):
            out[q] = float(extents[0 if q == "size_major" else 1])
        else:
            raise ValueError("this example does not measure %r" % q)
    out["notes"] = ", ".join(notes)
    return out


def estimate(request):
    """In-process entry point: the request with arrays (algorithms/external/python_estimator.h)."""
    p = request.get("params", {})
    method = p.get("method", "convex_hull")
    if method not in METHODS:
        raise ValueError("params.method: one of %s, not %r" % (", ".join(METHODS), method))
    return measure(request, request["cloud"], request.get("normals"), request.get("viewpoints"), method,
                   float(p.get("alpha", 0.025)), int(p.get("depth", 8)))


def answer(args, req):
    """Per-case and persistent modes: the request names a PLY file."""
    if req.get("protocol") not in PROTOCOLS:
        raise ValueError("unknown protocol %r" % req.get("protocol"))
    ply = read_ply(req["cloud"])
    if len(ply) != req["points"]:
        raise ValueError("read %d points, the request says %d" % (len(ply), req["points"]))
    names = ply.dtype.names
    xyz = np.stack([ply["x"], ply["y"], ply["z"]], axis=1).astype(float)
    normals = np.stack([ply["nx"], ply["ny"], ply["nz"]], axis=1) if "nx" in names else None
    viewpoints = np.stack([ply["vx"], ply["vy"], ply["vz"]], axis=1) if "vx" in names else None
    return measure(req, xyz, normals, viewpoints, args.method, args.alpha, args.depth)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--method", choices=METHODS, default="convex_hull")
    ap.add_argument("--alpha", type=float, default=0.025, help="alpha shape radius, m")
    ap.add_argument("--depth", type=int, default=8, help="Poisson octree depth")
    ap.add_argument("--persistent", action="store_true", help="answer JSON lines on stdin, one line each on stdout")
    ap.add_argument("request", nargs="?", help="the request file (per-case mode)")
    args = ap.parse_args()
    if args.persistent:
        for line in sys.stdin:
            # An error answers the request with its message: the harness fails that
            # row, naming it, and the process serves the next.
            try:
                reply = answer(args, json.loads(line))
            except Exception as e:  # noqa: BLE001 - reported to the harness, not swallowed
                reply = {"error": str(e)}
            sys.stdout.write(json.dumps(reply) + "\n")
            sys.stdout.flush()
        return
    if not args.request:
        ap.error("a request file, or --persistent")
    with open(args.request) as f:
        req = json.load(f)
    try:
        reply = answer(args, req)
    except ValueError as e:
        sys.exit(str(e))
    with open(req["answer"], "w") as f:
        json.dump(reply, f)


if __name__ == "__main__":
    main()
