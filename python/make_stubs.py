"""Writes the type stubs (<kind>.pyi) of grapebench's registry modules from the C++ key
tables, beside the built package (run by CMake after the extension is linked):
    PYTHONPATH=build/python python3 -P python/make_stubs.py build/python/grapebench
(-P: the package is the build's, not python/grapebench beside this script)
Each registered type gets its keyword arguments with their types and defaults, and its
docstring, so editors complete and check `grapebench.estimator.alpha_shape(pts, alpha=...)`."""
import keyword
import sys
from pathlib import Path

from grapebench import _registry

HEAD = '''"""Type stub written by python/make_stubs.py from the C++ key tables: do not edit."""
from typing import Any

import numpy.typing as npt

from ._registry import Entry, Estimator
'''


def arguments(entry):
    args, rest, seen = [], False, set()
    for k in entry["keys"]:
        key = k["key"]
        if key in seen:  # one key in two rows, each under its own condition
            continue
        seen.add(key)
        if "." in key or keyword.iskeyword(key) or not key.isidentifier():
            rest = rest or "." not in key  # nested keys travel inside their section's dict
            continue
        if k["required"]:
            args.insert(0, "%s: %s" % (key, _registry.python_type(entry["defaults"].get(key, ""))))
        elif key in entry["defaults"]:
            value = entry["defaults"][key]
            args.append("%s: %s = %r" % (key, _registry.python_type(value), value))
        else:  # read only under a condition the defaults do not meet (its docstring says which)
            args.append("%s: Any = ..." % key)
    args.append("name: str = ...")
    if rest:
        args.append("**keys: Any")
    return args


def stub(kind):
    out = [HEAD]
    for entry in _registry.tables()[kind]:
        t = entry["type"]
        doc = _registry.docstring(kind, entry).replace("\\", "\\\\").replace('"""', '\\"\\"\\"')
        base = "Estimator" if kind == "estimator" else "Entry"
        out.append("class _%s(%s):" % (t, base))
        out.append('    """%s"""' % doc.replace("\n", "\n    "))
        args = ", ".join(["*"] + arguments(entry))
        if kind == "estimator":
            extra = "" if "**keys" in args else ", **inputs: Any"  # left, camera, colours, ...
            out.append("    def __call__(self, points: npt.ArrayLike | None = None, %s%s) -> dict[str, Any]: ..."
                       % (args, extra))
        out.append("    def spec(self, %s) -> dict[str, Any]: ..." % args)
        out.append("")
        out.append("%s: _%s" % (t, t))
        out.append("")
    return "\n".join(out)


def main():
    folder = Path(sys.argv[1])
    for kind in _registry.SECTION:
        text = stub(kind)
        compile(text, "%s.pyi" % kind, "exec")  # a stub that does not parse fails the build
        (folder / ("%s.pyi" % kind)).write_text(text)


if __name__ == "__main__":
    main()
