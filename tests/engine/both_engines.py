"""The engines the semantics tests run on: adapt's own and, where soar-sml is
installed, the Soar kernel (``--engine soar``).

A test about what rules *mean* takes the ``make`` fixture (``conftest.py``)
and runs once per engine: the same rule text must give the same run in both.
Tests of the own engine's internals (matchers, the Rete, the parser) use
``adapt.engine`` directly.
"""

from __future__ import annotations

import re
from typing import Any

import pytest

from adapt.errors import AdaptError
from adapt.soar import require_soar


def soar_available() -> bool:
    """Whether soar-sml can be imported here (the kernel itself runs in a child process)."""
    try:
        require_soar()
    except AdaptError:
        return False
    return True


requires_soar = pytest.mark.skipif(
    not soar_available(), reason="soar-sml (the Soar kernel) is not installed: "
    "the Soar engine's runs are skipped")

#: The engines, as test parameters.
ENGINES = [pytest.param("adapt", id="adapt"),
           pytest.param("soar", id="soar", marks=[pytest.mark.soar, requires_soar])]


def values_of(agent: Any, ident: Any, attr: str) -> list[str]:
    """The values of ``(ident ^attr *)`` as the engine prints them (``print_state``)."""
    text = " ".join(agent.print_state(ident, depth=1).split())
    return re.findall(rf"\^{re.escape(attr)} (\|[^|]*\||[^\s)]+)", text)
