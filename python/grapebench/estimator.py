"""Every registered estimator type of the harness, its docstring from the C++ key table
(help(grapebench.estimator.<type>)); the type stub estimator.pyi is written at build time."""
from ._registry import populate as _populate

__all__ = _populate(globals(), "estimator")
