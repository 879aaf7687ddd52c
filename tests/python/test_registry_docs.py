"""Docstrings, help() and type stubs of every registered type, generated from the C++ key
tables (python/grapebench/_registry.py, python/make_stubs.py)."""
import ast
import math
import pydoc
from pathlib import Path

import numpy as np
import pytest

import grapebench as gb
from grapebench import _registry

KINDS = ["estimator", "sensor", "rig", "registration", "filter", "protocol"]


@pytest.mark.parametrize("kind", KINDS)
def test_every_type_has_its_key_table_as_docstring(kind):
    module = getattr(gb, kind)
    entries = _registry.tables()[kind]
    assert len(entries) >= 1 and sorted(module.__all__) == sorted(e["type"] for e in entries)
    for e in entries:
        obj = getattr(module, e["type"])
        text = pydoc.render_doc(obj, renderer=pydoc.plaintext)
        assert e["summary"][:40] in text, (kind, e["type"])
        for k in e["keys"]:
            assert k["key"] in obj.__doc__ and k["doc"][:30] in obj.__doc__, (kind, e["type"], k["key"])
            assert k["range"] in obj.__doc__


def test_the_docstring_gives_unit_default_and_range():
    doc = gb.estimator.alpha_shape.__doc__
    alpha = next(k for k in _registry.tables()["estimator"] if k["type"] == "alpha_shape")["keys"][0]
    line = next(l for l in doc.splitlines() if l.strip().startswith(alpha["key"] + " :"))
    assert "float" in line and alpha["unit"] in line and "default " + alpha["default"] in line and alpha["range"] in line
    assert "gb.estimator" not in doc  # the scene's words, not Python's
    # A required key has no default: absent from defaults, "required" in its docstring line.
    assert "module" not in gb.estimator.python.defaults and "function" in gb.estimator.python.defaults
    module_line = next(l for l in gb.estimator.python.__doc__.splitlines() if l.strip().startswith("module :"))
    assert "required" in module_line and "default" not in module_line


@pytest.mark.parametrize("kind", KINDS)
def test_the_stubs_declare_every_type_with_its_defaults(kind):
    path = Path(gb.__file__).parent / (kind + ".pyi")
    tree = ast.parse(path.read_text())
    declared = {n.target.id for n in tree.body if isinstance(n, ast.AnnAssign)}
    entries = _registry.tables()[kind]
    assert declared == {e["type"] for e in entries}
    classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    for e in entries:
        spec = next(f for f in classes["_" + e["type"]].body if isinstance(f, ast.FunctionDef) and f.name == "spec")
        stub_defaults = {a.arg: ast.literal_eval(d) for a, d in zip(spec.args.kwonlyargs, spec.args.kw_defaults)
                         if d is not None and not (isinstance(d, ast.Constant) and d.value is Ellipsis)}
        for key, value in stub_defaults.items():
            assert e["defaults"][key] == value, (kind, e["type"], key)
        flat = [k["key"] for k in e["keys"] if "." not in k["key"] and k["key"].isidentifier()]
        assert set(flat) <= {a.arg for a in spec.args.kwonlyargs}, (kind, e["type"])


def test_an_estimator_object_runs_as_estimate_does():
    rng = np.random.default_rng(3)
    pts = rng.normal(size=(2000, 3))
    pts = 0.05 * pts / np.linalg.norm(pts, axis=1, keepdims=True)
    a = gb.estimator.convex_hull(pts)["values"]["volume"]
    assert a == gb.estimate("convex_hull", pts)["values"]["volume"]
    assert a == pytest.approx(4 / 3 * math.pi * 0.05 ** 3, rel=0.02)


def test_spec_checks_key_names_and_builds_a_scene():
    with pytest.raises(gb.InputError, match="unknown key views_typo"):
        gb.rig.turntable.spec(views_typo=3)
    scene = gb.Scene({"name": "spec", "seed": 1, "bunches": [{"preset": "table-red", "count": 1}],
                      "sensor": gb.sensor.ideal.spec(width=160, height=120),
                      "rig": gb.rig.turntable.spec(views=4, step_deg=90, distance=0.6),
                      "estimators": [gb.estimator.convex_hull.spec(name="CH")]})
    d = scene.to_dict()
    assert d["sensor"]["width"] == 160 and d["rig"]["views"] == 4
