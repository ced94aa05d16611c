"""adapt: the ADAPT architecture's mirror system.

A production-rule engine in the spirit of Soar (``adapt.engine``), match-mediated
difference image comparison (``adapt.vision``), a pymunk imagination with a
rasterized renderer (``adapt.imagination``) and the tools to inspect traces
(``adapt.traceview``).  Importing ``adapt`` imports nothing heavy.
"""

__version__ = "0.1.0"
__all__ = ["__version__"]
