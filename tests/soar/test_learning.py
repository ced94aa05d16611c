"""What the own engine refuses, the Soar engine runs: chunking, reinforcement learning
(``rl``, ``:template``, numeric-indifferent preferences updated by reward), semantic and
episodic memory.  Each agent is also given to the own engine, whose refusal names the
Soar engine."""

from __future__ import annotations

import re

import pytest

from adapt.engine import Agent
from adapt.errors import RuleSemanticError
from adapt.soar import SoarAgent

pytestmark = pytest.mark.soar

CHUNKING = """
chunk always
sp {propose*init (state <s> ^superstate nil -^round) --> (<s> ^operator <o> + !) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^round 1)}
sp {propose*pick (state <s> ^round { <r> < 4 })
   --> (<s> ^operator <a> +) (<s> ^operator <b> +) (<a> ^name a) (<b> ^name b)}
sp {tie*prefer-a (state <s> ^impasse tie ^superstate <ss> ^item <i>) (<i> ^name a)
   --> (<ss> ^operator <i> >)}
sp {apply*pick (state <s> ^operator <o> ^round <r>) (<o> ^name <n>)
   --> (write <n> | |) (<s> ^round <r> - (+ <r> 1))}
sp {done (state <s> ^round 4) --> (halt)}
"""

BANDIT = """
rl --set learning on
rl --set discount-rate 0
rl --set learning-rate 0.3
indifferent-selection --epsilon-greedy
indifferent-selection --epsilon 0.1
sp {propose*init (state <s> ^superstate nil -^round) --> (<s> ^operator <o> + !) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^round 0)}
sp {propose*left (state <s> ^round { <r> < 80 }) --> (<s> ^operator <o> +) (<o> ^name left)}
sp {propose*right (state <s> ^round { <r> < 80 }) --> (<s> ^operator <o> +) (<o> ^name right)}
VALUES
sp {apply*move (state <s> ^operator <o> ^round <r>) (<o> ^name { <n> <> init })
   --> (write <n> | |) (<s> ^round <r> - (+ <r> 1))}
sp {reward (state <s> ^reward-link <rl> ^operator.name right) --> (<rl> ^reward.value 1)}
sp {done (state <s> ^round 80) --> (halt)}
"""
RULES = """
sp {rl*left (state <s> ^operator <o> +) (<o> ^name left) --> (<s> ^operator <o> = 0)}
sp {rl*right (state <s> ^operator <o> +) (<o> ^name right) --> (<s> ^operator <o> = 0)}
"""
TEMPLATE = """
sp {rl*value :template (state <s> ^operator <o> +) (<o> ^name <n>) --> (<s> ^operator <o> = 0)}
"""

SMEM = """
smem --enable
smem --add {(<x> ^name alice ^age 30) (<y> ^name bob ^age 41)}
sp {propose*query (state <s> ^superstate nil ^smem.command <c>) -(<c> ^query)
   --> (<s> ^operator <o> + !) (<o> ^name query)}
sp {apply*query (state <s> ^operator.name query ^smem.command <c>) --> (<c> ^query <q>) (<q> ^name bob)}
sp {found (state <s> ^smem.result.retrieved <r>) (<r> ^age <a>) --> (write |bob is | <a>) (halt)}
"""

EPMEM = """
epmem --set learning on
sp {propose*init (state <s> ^superstate nil -^round) --> (<s> ^operator <o> + !) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^round 1 ^color red)}
sp {propose*step (state <s> ^round { <r> < 4 }) --> (<s> ^operator <o> +) (<o> ^name step)}
sp {apply*step (state <s> ^operator.name step ^round <r> ^color <c>)
   --> (<s> ^round <r> - (+ <r> 1)) (<s> ^color <c> - blue)}
sp {recall (state <s> ^round 4 ^epmem.command <c>) -(<c> ^query) --> (<c> ^query <q>) (<q> ^color red)}
sp {found (state <s> ^epmem.result.retrieved <e>) (<e> ^round <r> ^color red)
   --> (write |red in round | <r>) (halt)}
"""


def soar_run(text: str, seed: int = 3) -> tuple[SoarAgent, object]:
    agent = SoarAgent(seed=seed)
    agent.load_text(text)
    return agent, agent.run(500)


@pytest.mark.parametrize("text, refused", [
    (CHUNKING, "'chunk always' turns chunking on"),
    (BANDIT.replace("VALUES", RULES), "'rl' is a Soar command adapt does not run"),
    (TEMPLATE, "the flag ':template' is not supported"),
    (SMEM, "'smem' is a Soar command adapt does not run"),
    (EPMEM, "'epmem' is a Soar command adapt does not run"),
], ids=["chunking", "rl", "template", "smem", "epmem"])
def test_the_own_engine_refuses_and_names_the_soar_engine(text: str, refused: str) -> None:
    with pytest.raises(RuleSemanticError, match=re.escape(refused)) as caught:
        Agent().load_text(text)
    assert str(caught.value).splitlines()[0].endswith("run it on the Soar engine (--engine soar)")


def test_chunking_learns_from_the_first_tie_and_skips_the_others() -> None:
    agent, learned = soar_run(CHUNKING)
    chunks = agent.command("print --chunks")
    agent.close()
    never, plain = soar_run(CHUNKING.replace("chunk always", "chunk never"))
    never.close()
    assert learned.output == plain.output == "a a a "  # type: ignore[attr-defined]
    assert learned.impasses == [[2, 1, "tie", "operator"]]  # type: ignore[attr-defined]
    assert len(plain.impasses) == 3  # type: ignore[attr-defined]
    assert "chunk" in chunks  # the learned rule


@pytest.mark.parametrize("values", [RULES, TEMPLATE], ids=["rules", "template"])
def test_reinforcement_learning_updates_numeric_preferences_by_reward(values: str) -> None:
    agent, report = soar_run(BANDIT.replace("VALUES", values))
    table = agent.command("print --rl")
    agent.close()
    moves = report.output.split()  # type: ignore[attr-defined]
    assert len(moves) == 80 and moves[-20:].count("right") >= 15  # it learned to go right
    learned = {name: float(value) for name, _updates, value in
               (line.split() for line in table.splitlines() if line.strip())}
    assert len(learned) >= 2 and max(learned.values()) > 0.5


def test_semantic_memory_retrieves_what_was_added() -> None:
    agent, report = soar_run(SMEM)
    agent.close()
    assert report.output == "bob is 41" and report.halted  # type: ignore[attr-defined]


def test_episodic_memory_recalls_an_earlier_episode() -> None:
    agent, report = soar_run(EPMEM)
    agent.close()
    assert report.output == "red in round 1" and report.halted  # type: ignore[attr-defined]
