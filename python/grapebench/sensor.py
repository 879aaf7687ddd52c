"""Every registered sensor type of the harness, its docstring from the C++ key table
(help(grapebench.sensor.<type>)); the type stub sensor.pyi is written at build time."""
from ._registry import populate as _populate

__all__ = _populate(globals(), "sensor")
