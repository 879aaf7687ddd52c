"""bench/perf/python_perf.cpp: an estimator that does no work, so its per-call time is
the hand-over alone (in-process, or through serve_python.py as an external program)."""


def constant(request):
    return {"volume": 1e-4, "watertight": True, "notes": "%d points" % request["points"]}
