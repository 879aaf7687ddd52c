"""Every registered filter type of the harness, its docstring from the C++ key table
(help(grapebench.filter.<type>)); the type stub filter.pyi is written at build time."""
from ._registry import populate as _populate

__all__ = _populate(globals(), "filter")
