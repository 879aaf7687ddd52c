"""Every registered rig type of the harness, its docstring from the C++ key table
(help(grapebench.rig.<type>)); the type stub rig.pyi is written at build time."""
from ._registry import populate as _populate

__all__ = _populate(globals(), "rig")
