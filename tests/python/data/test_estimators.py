"""In-process estimators for tests/python/test_python_estimator.py (and the C++ unit
tests): each takes the request of algorithms/external/python_estimator.h."""
import numpy as np


def principal_sizes(request):
    """Extents along the principal axes, times params.scale: checks the request's arrays."""
    xyz = request["cloud"]
    assert xyz.dtype == np.float64 and xyz.shape == (request["points"], 3), (xyz.dtype, xyz.shape)
    assert request["protocol"] == "grapebench-estimator-2" and request["units"] == "m"
    c = xyz - xyz.mean(axis=0)
    _, vectors = np.linalg.eigh(c.T @ c)
    extents = np.sort(np.ptp(c @ vectors, axis=0))[::-1] * request["params"]["scale"]
    return {"height": extents[0], "length": extents[1], "width": extents[2],  # numpy scalars are fine
            "notes": "%d points, %s" % (len(xyz), "+".join(request["attributes"]))}


def raises(request):
    def deeper(n):
        raise ValueError("no volume for %d points" % n)
    deeper(request["points"])


def not_json(request):
    return {"volume": object()}


def wrong_range(request):
    return {"volume": -1.0}


def echo_params(request):
    return {"volume": 1e-4, "notes": repr(request["params"])}


def keeps_the_cloud(request):
    keeps_the_cloud.kept.append(request["cloud"])  # a copy it may keep
    return {"volume": float(len(keeps_the_cloud.kept))}


keeps_the_cloud.kept = []


def spins(request):
    """Never returns on its own: the run's time budget must stop it."""
    n = 0
    while True:
        n += 1
