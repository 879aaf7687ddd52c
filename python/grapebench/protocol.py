"""Every registered protocol type of the harness, its docstring from the C++ key table
(help(grapebench.protocol.<type>)); the type stub protocol.pyi is written at build time."""
from ._registry import populate as _populate

__all__ = _populate(globals(), "protocol")
