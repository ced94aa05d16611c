"""``adapt.engines``: choosing the engine by name."""

from __future__ import annotations

import sys
from typing import Any

import pytest

from adapt.engine import Agent
from adapt.engine.interface import EngineName, RuleEngine
from adapt.engines import engine_name, make_agent, soar_status
from adapt.errors import AdaptError


def test_names() -> None:
    assert engine_name("soar") is EngineName.SOAR and engine_name(EngineName.ADAPT) is EngineName.ADAPT
    with pytest.raises(AdaptError, match="unknown engine 'own'; expected adapt"):
        engine_name("own")


def test_the_own_engine_is_the_default() -> None:
    agent = make_agent(seed=4, matcher="naive")
    assert type(agent) is Agent and agent.seed == 4 and isinstance(agent, RuleEngine)


def test_the_soar_engine_has_no_matcher_to_choose() -> None:
    with pytest.raises(AdaptError, match="matcher 'naive' is a matcher of adapt's own engine"):
        make_agent("soar", matcher="naive")


@pytest.mark.soar
def test_the_soar_engine_is_a_rule_engine() -> None:
    agent = make_agent("soar", seed=2)
    try:
        assert isinstance(agent, RuleEngine) and type(agent).__name__ == "SoarAgent"
    finally:
        agent.close()


def test_soar_status_says_what_to_install_when_it_is_missing(monkeypatch: Any) -> None:
    monkeypatch.setitem(sys.modules, "soar_sml", None)
    assert soar_status() == "not installed: pip install 'adapt[soar]' (soar-sml, Soar 9.6)"
