"""The harness's registries (estimators, sensors, rigs, registration methods, pipeline
filters, protocols) as Python objects whose docstrings, help() and type stubs (.pyi,
written by python/make_stubs.py at build time) come from the C++ key tables: each key
with its unit, default, allowed range and meaning, written once in C++."""
import json

from . import _grapebench

SECTION = {  # where a scene names an entry of each kind
    "estimator": "estimators: [{type: %s, ...}]",
    "sensor": "sensor: {type: %s, ...}",
    "rig": "rig: {type: %s, ...}",
    "registration": "pipeline: {registration: {type: %s, ...}}",
    "filter": "pipeline: {cloud_filters: [{type: %s, ...}]}",
    "protocol": "protocol: %s (its keys are under pipeline:)",
}
PYTHON_TYPES = {bool: "bool", int: "int", float: "float", str: "str", list: "list", dict: "dict"}


def tables():
    """{kind: [{type, summary, keys: [{key, unit, range, default, doc, when, required}], defaults}]}"""
    if tables.cache is None:
        tables.cache = json.loads(_grapebench.registries_json())
    return tables.cache


tables.cache = None


def python_type(value):
    """The Python type a key takes, from its typed default (floats accept ints)."""
    return PYTHON_TYPES.get(type(value), "object")


def docstring(kind, entry):
    lines = ["%s: %s" % (entry["type"], entry["summary"]), "", "Scene entry: " + SECTION[kind] % entry["type"]]
    if not entry["keys"]:
        lines += ["", "No keys."]
        return "\n".join(lines)
    lines += ["", "Keys (key : type, unit, default, allowed range):"]
    for k in entry["keys"]:
        top = k["key"].split(".")[0]
        t = "" if "." in k["key"] else python_type(entry["defaults"].get(top)) if top in entry["defaults"] else ""
        head = "    %s : %s" % (k["key"], ", ".join(x for x in (t, k["unit"] if k["unit"] != "-" else "",
                                                              "required" if k["required"] else "default " + k["default"],
                                                              k["range"]) if x))
        lines.append(head)
        lines.append("        " + k["doc"])
        if k["when"]:
            lines.append("        (only with %s)" % k["when"])
    return "\n".join(lines)


class Entry:
    """One registered type: `keys` (its key table), `defaults` (typed), `spec(**keys)`
    (the scene entry as a dict, key names checked)."""

    def __init__(self, kind, entry):
        self.kind, self.type, self.summary = kind, entry["type"], entry["summary"]
        self.keys = entry["keys"]
        self.defaults = {k: v for k, v in entry["defaults"].items()
                         if not any(x["key"] == k and x["required"] for x in self.keys)}
        self.__doc__ = docstring(kind, entry)
        self.__name__ = self.__qualname__ = self.type

    def spec(self, **keys):
        known = {k["key"].split(".")[0] for k in self.keys}
        unknown = sorted(set(keys) - known - {"name"})
        if unknown:
            raise _grapebench.InputError("%s %s: unknown key%s %s; its keys: %s" % (
                self.kind, self.type, "s" if len(unknown) > 1 else "", ", ".join(unknown),
                ", ".join(sorted(known)) or "none"))
        return {"type": self.type, **keys}

    def __repr__(self):
        return "<grapebench %s %r>" % (self.kind, self.type)


class Estimator(Entry):
    """A registered estimator: call it on its input with its keys, as
    grapebench.estimate(type, points, **keys) (images, stereo pairs and labelled clouds
    by keyword: see grapebench.estimate)."""

    def __call__(self, points=None, **keys):
        from . import estimate
        return estimate(self.type, points, **keys)


def populate(namespace, kind):
    """Puts one object per registered type of `kind` into a module's namespace."""
    names = []
    for entry in tables()[kind]:
        cls = Estimator if kind == "estimator" else Entry
        # Per type a class, so that help() shows the type's own docstring.
        obj = type(entry["type"], (cls,), {"__doc__": docstring(kind, entry)})(kind, entry)
        namespace[entry["type"]] = obj
        names.append(entry["type"])
    return names
