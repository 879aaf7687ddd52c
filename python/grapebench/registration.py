"""Every registered registration type of the harness, its docstring from the C++ key table
(help(grapebench.registration.<type>)); the type stub registration.pyi is written at build time."""
from ._registry import populate as _populate

__all__ = _populate(globals(), "registration")
