"""The production-rule engine: a faithful subset of Soar in pure Python.

Imports only the standard library and :mod:`adapt.errors`.

Examples
--------
>>> from adapt.engine import Agent
>>> agent = Agent()
>>> _ = agent.load_text("sp {hello (state <s> ^superstate nil) --> (write |hello|) (halt)}")
>>> agent.run().output
'hello'
"""

from adapt.engine.compiled import engine_build, prefer_source

prefer_source()  # before any other engine module is imported

from adapt.engine.agent import Agent
from adapt.engine.io import InputWriter, OutputView
from adapt.engine.memory import WorkingMemory
from adapt.engine.report import REPORT_KEYS, RunReport
from adapt.engine.symbols import Float, Identifier, format_symbol, to_symbol
from adapt.engine.trace import TraceWriter
from adapt.engine.wme import WME

__all__ = [
    "Agent",
    "RunReport",
    "REPORT_KEYS",
    "WME",
    "Identifier",
    "Float",
    "to_symbol",
    "format_symbol",
    "WorkingMemory",
    "InputWriter",
    "OutputView",
    "TraceWriter",
    "engine_build",
]
