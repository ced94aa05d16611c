"""The choice of rule engine: adapt's own (:mod:`adapt.engine`) or the Soar kernel (:mod:`adapt.soar`).

Both implement :class:`adapt.engine.interface.RuleEngine`; :func:`make_agent`
builds the one a command line (``--engine``), a scenario (``engine:``) or a
sweep (``--set engine=soar``) names.  The Soar engine is imported only when
it is chosen, and it says which extra to install when soar-sml is missing.

Examples
--------
>>> agent = make_agent("adapt", seed=3)
>>> type(agent).__name__, agent.seed
('Agent', 3)
>>> engine_name("kernel")
Traceback (most recent call last):
...
adapt.errors.AdaptError: unknown engine 'kernel'; expected adapt (adapt's own, the default) or soar (the Soar kernel, soar-sml)
"""

from __future__ import annotations

from importlib import metadata
from typing import Any

from adapt.engine.interface import EngineName, RuleEngine
from adapt.errors import AdaptError

__all__ = ["make_agent", "engine_name", "require_engine", "soar_status", "EngineName"]


def engine_name(value: str | EngineName) -> EngineName:
    """The engine called ``value`` (``"adapt"`` or ``"soar"``).

    Raises
    ------
    AdaptError
        For any other name, listing the two.
    """
    try:
        return EngineName(value)
    except ValueError:
        raise AdaptError(f"unknown engine {value!r}; expected adapt (adapt's own, the default) "
                         "or soar (the Soar kernel, soar-sml)") from None


def require_engine(engine: str | EngineName) -> EngineName:
    """The engine called ``engine``, when it can run here (the kernel is not loaded to
    find out).

    Raises
    ------
    AdaptError
        For an unknown engine, or the Soar engine without soar-sml installed (the
        message names the extra ``adapt[soar]``).
    """
    name = engine_name(engine)
    if name is EngineName.SOAR:
        from adapt.soar.process import require_soar

        require_soar()
    return name


def make_agent(engine: str | EngineName = EngineName.ADAPT, *, seed: int = 1, trace: Any = None,
               trace_level: int = 5, history: int | None = None,
               matcher: str = "rete") -> RuleEngine:
    """An agent of the named engine.

    ``matcher`` chooses the own engine's matcher (``"rete"`` or ``"naive"``);
    the Soar kernel has its own Rete and takes only the default.

    Raises
    ------
    AdaptError
        For an unknown engine, a matcher for the Soar engine, or the Soar
        engine without soar-sml installed (the message says what to install).
    """
    name = engine_name(engine)
    if name is EngineName.SOAR:
        if matcher != "rete":
            raise AdaptError(f"matcher {matcher!r} is a matcher of adapt's own engine; the Soar "
                             "kernel matches with its own Rete")
        from adapt.soar import SoarAgent

        return SoarAgent(seed=seed, trace=trace, trace_level=trace_level, history=history)
    from adapt.engine import Agent

    return Agent(seed=seed, matcher=matcher, trace=trace, trace_level=trace_level,
                 history=history)


def soar_status() -> str:
    """Whether the Soar engine can run here: soar-sml's version, or what to install.

    The kernel is not loaded to find out.
    """
    from adapt.soar.process import INSTALL_HINT, require_soar

    try:
        require_soar()
    except AdaptError:
        return f"not installed: {INSTALL_HINT}"
    try:
        return f"soar-sml {metadata.version('soar-sml')}"
    except metadata.PackageNotFoundError:
        return "soar_sml (version unknown)"
