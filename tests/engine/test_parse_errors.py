"""Every kind of rule-text error: its class, exact ``file:line:col`` and message.

Where Soar 9.6.5 behaves differently (it accepts some of these), the comment
says so; those were checked by loading the rule into the real kernel.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from adapt.engine.parse import load_rule_file, parse_rules
from adapt.errors import RuleError, RuleSemanticError, RuleSyntaxError

SYN, SEM = RuleSyntaxError, RuleSemanticError

CASES = [
    # --- file level
    ("hello world", SYN, "1:1",
     "expected 'sp {' to begin a production, or an agent-file command, found 'hello'"),
    ("sp t", SYN, "1:4", "expected '{' after 'sp', found 't'"),
    ("sp {t (state <s>) --> (<s> ^a 1)} }", SYN, "1:35",
     "expected 'sp {' to begin a production, or an agent-file command, found '}'"),
    ("sp {t (state <s>) --> (<s> ^a 1)\nsp {u (state <s>) --> }", SYN, "2:1",
     "expected '(' to begin an action, or '}', found 'sp' "
     "(is the '}' that ends production 't' missing?)"),
    ("sp {t (state <s>) -->", SYN, "1:22",
     "expected '(' to begin an action, or '}', found the end of the file "
     "(is the '}' that ends production 't' missing?)"),
    # --- agent-file commands that ask for what adapt lacks
    ("chunk always", SEM, "1:1",
     "'chunk always' turns chunking on, which adapt does not implement; remove the line, "
     "write 'chunk never', or run it on the Soar engine (--engine soar)"),
    ("learn --on", SEM, "1:1",
     "'learn --on' turns chunking on, which adapt does not implement; remove the line, "
     "write 'chunk never', or run it on the Soar engine (--engine soar)"),
    ("chunk never\nchunk add-osk on", SEM, "2:1",
     "'chunk add-osk on' configures chunking, which adapt does not implement; remove the "
     "line, write 'chunk never', or run it on the Soar engine (--engine soar)"),
    ("rl --set learning on", SEM, "1:1",
     "'rl' is a Soar command adapt does not run (reinforcement learning is not implemented); "
     "run it on the Soar engine (--engine soar)"),
    ("smem --enable", SEM, "1:1",
     "'smem' is a Soar command adapt does not run (semantic memory is not implemented); "
     "run it on the Soar engine (--engine soar)"),
    ("epmem --enable", SEM, "1:1",
     "'epmem' is a Soar command adapt does not run (episodic memory is not implemented); "
     "run it on the Soar engine (--engine soar)"),
    ("# ok\n  gp {t (state <s> ^a [1 2]) -->}", SEM, "2:3",
     "'gp' is a Soar command adapt does not run (generated productions are not supported; "
     "write each production with sp); run it on the Soar engine (--engine soar)"),
    ("indifferent-selection --epsilon-greedy", SEM, "1:1",
     "'indifferent-selection' is a Soar command adapt does not run (only Soar's default "
     "selection policy (softmax) is implemented); run it on the Soar engine (--engine soar)"),
    ("  excise foo", SEM, "1:3",
     "'excise foo' is a Soar command adapt does not run in agent files (besides 'sp' "
     "productions they may hold source, pushd, popd, srand, multi-attributes, chunk never, "
     "watch, echo, max-elaborations, max-goal-depth and output agent-writes); "
     "run it on the Soar engine (--engine soar)"),
    # --- agent-file commands adapt accepts, used wrongly
    ("source other.soar", SEM, "1:8", "cannot source other.soar: no file other.soar"),
    ("source", SEM, "1:1",
     "'source' takes one file name (put quotes around a name with spaces)"),
    ("popd", SEM, "1:1", "popd: the directory stack is empty (no pushd before it)"),
    ("pushd no-such-folder", SEM, "1:7", "pushd: no directory no-such-folder"),
    ("srand", SEM, "1:1",
     "'srand' without a seed seeds Soar from the clock, which would make the run "
     "irreproducible; give a seed ('srand 1')"),
    ("srand x", SEM, "1:7", "the seed must be an integer, not 'x'"),
    ("multi-attributes foo 0", SEM, "1:22", "the number of values must be at least 1, not 0"),
    ("max-elaborations", SEM, "1:1", "'max-elaborations' needs the max-elaborations limit"),
    ("output agent-writes maybe", SEM, "1:21", "'output agent-writes' takes 'on' or 'off'"),
    ("echo {unterminated", SYN, "1:6", "unterminated '{': no matching '}'"),
    ('sp "a (state <s>) --> (write x)', SYN, "1:4", "unterminated quoted word: no closing '\"'"),
    # --- header
    ("sp {p1 (state <s>) -->}", SEM, "1:5",
     "production name 'p1' is shaped like an identifier (a letter followed by digits), "
     "which Soar does not accept as a name"),
    ("sp {<x> (state <s>) -->}", SYN, "1:5", "expected a production name, found '<x>'"),
    ("sp {t :chunk (state <s>) -->}", SEM, "1:7",
     "the flag ':chunk' is not supported: chunking is not implemented; "
     "run it on the Soar engine (--engine soar)"),
    ("sp {t :template (state <s>) -->}", SEM, "1:7",
     "the flag ':template' is not supported: Soar-RL templates need reinforcement learning, "
     "which is not implemented; run it on the Soar engine (--engine soar)"),
    ("sp {t :foo (state <s>) -->}", SYN, "1:7",
     "unknown production flag ':foo' (expected :o-support, :i-support, :default or "
     ":interrupt)"),
    ("sp {t :o-support :i-support (state <s>) -->}", SEM, "1:18",
     "a production cannot be both :o-support and :i-support"),
    # --- lexing
    ("sp {t (state <s> ^a [1]) -->}", SYN, "1:21", "unexpected character '[' in rule text"),
    ("sp {t (state <s> ^a) -->\n (<s> ^a |unterminated)}", SYN, "2:10",
     "unterminated quoted string '|': no closing |"),
    ('sp {t "unterminated doc (state <s>) -->}', SYN, "1:7",
     "unterminated documentation string '\"': no closing \""),
    ("sp {t (state <s> ^a 99999999999999999999) -->}", SYN, "1:21",
     "integer 99999999999999999999 does not fit in 64 bits"),
    # --- conditions: syntax
    ("sp {t (state <s>) (halt)}", SYN, "1:20",
     "expected a variable for the condition's identifier, found 'halt' "
     "(is '-->' missing before the actions?)"),
    ("sp {t (state <s> a) -->}", SYN, "1:18",
     "expected '^attribute' or ')' in the condition opened at 1:7, found 'a'"),
    ("sp {t (state) -->}", SYN, "1:13",
     "expected a variable for the condition's identifier, found ')'"),
    ("sp {t (state {<s> <> <t>}) -->}", SEM, "1:14",
     "a condition's identifier must be tested by a plain variable such as <s>"),
    ("sp {t {} -->}", SYN, "1:7", "empty '{ }': a conjunction needs at least one condition"),
    ("sp {t (state <s>) - ^a -->}", SYN, "1:21", "expected '(' or '{' after '-', found '^'"),
    ("sp {t (state <s> ^a << <x> >>) -->}", SYN, "1:24",
     "expected a constant or '>>' in a disjunction, found '<x>'"),
    ("sp {t (state <s> ^a {}) -->}", SYN, "1:21", "empty conjunctive test '{ }'"),
    ("sp {t (state <s> ^a > ) -->}", SYN, "1:23",
     "expected a variable or a constant after '>', found ')'"),
    # --- conditions: meaning
    # Soar 9.6.5 accepts (and matches) a first condition without `state`.
    ("sp {t (<s> ^a 1) -->}", SEM, "1:7",
     "the first condition must test a state: '(state <s> ...)'"),
    ("sp {t -(state <s>) -->}", SEM, "1:8",
     "the first condition must test a state: '(state <s> ...)'"),
    ("sp {t --> (halt)}", SEM, "1:7", "the first condition must test a state: '(state <s> ...)'"),
    # Soar 9.6.5 accepts conditions that are not linked to a state.  (A negation
    # linked through its value, -(<x> ^on <b>), is accepted: test_agent_files.py.)
    ("sp {t (state <s>)\n   (<x> ^a 1) -->}", SEM, "2:4",
     "condition on <x> is not linked to a state: <x> is not the value of any condition "
     "reachable from a state variable"),
    ("sp {t (state <s>) -(<x> ^a 1) -->}", SEM, "1:20",
     "condition on <x> is not linked to a state: <x> is not the value of any condition "
     "reachable from a state variable"),
    ("sp {t (state <s>) -{(<s> ^a <x>) (<y> ^b 1)} -->}", SEM, "1:34",
     "condition on <y> is not linked to a state: <y> is not the value of any condition "
     "reachable from a state variable"),
    # Soar 9.6.5 loads (impasse <i>) but it never matches: there are no impasse objects.
    ("sp {t (impasse <i>) -->}", SEM, "1:8",
     "'impasse' conditions are not supported: Soar 9 has no impasse objects; test the "
     "substate's ^impasse attribute instead"),
    # Soar 9.6.5 accepts two variables in one {} (and rejects a constant and a variable).
    ("sp {t (state <s> ^a {<x> <y>}) -->}", SEM, "1:26",
     "a conjunctive test may hold only one equality test; '<x>' is already one"),
    ("sp {t (state <s> ^a {3.0 <m>}) -->}", SEM, "1:26",
     "a conjunctive test may hold only one equality test; '3.0' is already one"),
    # Soar 9.6.5 accepts this and treats the test as true.
    ("sp {t (state <s> ^a > <x>) -->}", SEM, "1:23",
     "variable <x> is used in a relational test but never bound by an equality test in a "
     "positive condition, so the test cannot be evaluated"),
    ("sp {t (state <s>) -(<s> ^a <x>) (<s> ^b < <x>) -->}", SEM, "1:43",
     "variable <x> is used in a relational test but never bound by an equality test in a "
     "positive condition, so the test cannot be evaluated"),
    # Soar refuses it: "unbound referent in negated relational test" (a negated
    # condition's own equality tests do not bind for its relational tests)
    ("sp {t (state <s>) -(<s> ^{a <= <y>} <y>) -->}", SEM, "1:32",
     "variable <y> is used in a relational test but never bound by an equality test in a "
     "positive condition, so the test cannot be evaluated"),
    ("sp {t (state <s>) -{(<s> ^{a <= <y>} <y>)} -->}", SEM, "1:33",
     "variable <y> is used in a relational test but never bound by an equality test in a "
     "positive condition, so the test cannot be evaluated"),
    # --- actions: syntax
    ("sp {t (state <s>) --> (<s> ^a)}", SYN, "1:30",
     "expected a value after the attribute, found ')'"),
    ("sp {t (state <s>) --> (<s>)}", SYN, "1:27", "expected '^attribute' after <s>, found ')'"),
    ("sp {t (state <s>) --> (<s> ^a 1 <=)}", SYN, "1:33",
     "expected a value, a preference, '^attribute' or ')', found '<='"),
    ("sp {t (state <s>) --> (<s> ^a a.b)}", SYN, "1:32",
     "expected a value, a preference, '^attribute' or ')', found '.'"),
    ("sp {t (state <s>) --> (<s> ^a 1 , 2)}", SYN, "1:33",
     "expected a value, a preference, '^attribute' or ')', found ','"),
    ("sp {t (state <s>) --> (1 2)}", SYN, "1:24",
     "expected a variable or a function name after '(', found '1'"),
    # --- actions: meaning
    ("sp {t (state <s>) --> (<y> ^a 1)}", SEM, "1:24",
     "variable <y> is used as an action's identifier but is neither bound by a positive "
     "condition nor created as a value by an action"),
    ("sp {t (state <s>) -(<s> ^a <x>) --> (<x> ^a 1)}", SEM, "1:38",
     "variable <x> is used as an action's identifier but is neither bound by a positive "
     "condition nor created as a value by an action"),
    ("sp {t (state <s>) --> (write <y>)}", SEM, "1:30",
     "variable <y> is used in a function call but is neither bound by a positive condition "
     "nor created as a value by an action"),
    ("sp {t (state <s>) --> (<s> ^operator <o> > <p>)}", SEM, "1:44",
     "variable <p> is used in a preference's referent but is neither bound by a positive "
     "condition nor created as a value by an action"),
    # Soar 9.6.5 loads a call to an unknown function (and ignores it at run time).
    ("sp {t (state <s>) --> (foo 1)}", SEM, "1:24", "unknown RHS function 'foo'"),
    ("sp {t (state <s>) --> (<s> ^a (foo 1))}", SEM, "1:32", "unknown RHS function 'foo'"),
    ("sp {t (state <s>) --> (<s> ^a (ifeq 1 2))}", SEM, "1:32",
     "wrong number of arguments to function 'ifeq' (expected 4, got 2)"),
    ("sp {t (state <s>) --> (halt 1)}", SEM, "1:24",
     "wrong number of arguments to function 'halt' (expected 0, got 1)"),
    ("sp {t (state <s>) --> (<s> ^a (div 1))}", SEM, "1:32",
     "wrong number of arguments to function 'div' (expected 2, got 1)"),
    ("sp {t (state <s>) --> (crlf)}", SEM, "1:24",
     "function 'crlf' cannot be used as a stand-alone action"),
    ("sp {t (state <s>) --> (<s> ^a (write x))}", SEM, "1:32",
     "function 'write' can only be used as a stand-alone action"),
]


@pytest.mark.parametrize("text, kind, where, message", CASES, ids=[c[0][:40] for c in CASES])
def test_error_position_and_message(text: str, kind: type, where: str, message: str) -> None:
    with pytest.raises(RuleError) as info:
        parse_rules(text, file="e.soar")
    err = info.value
    assert type(err) is kind
    assert (f"{err.line}:{err.col}", err.message) == (where, message)
    assert str(err).startswith(f"e.soar:{where}: {message}\n")


def test_error_shows_the_line_and_a_caret() -> None:
    text = "sp {t\n  (state <s>)\n-->\n  (<y> ^a 1)}"
    with pytest.raises(RuleSemanticError) as info:
        parse_rules(text, file="r.soar")
    assert str(info.value).splitlines() == [
        "r.soar:4:4: variable <y> is used as an action's identifier but is neither bound by a "
        "positive condition nor created as a value by an action",
        "      (<y> ^a 1)}",
        "       ^",
    ]


def test_an_error_anywhere_loads_nothing(tmp_path: Path) -> None:
    path = tmp_path / "bad.soar"
    path.write_text("sp {good (state <s>) --> (halt)}\nsp {bad (state <s>) --> (<x> ^a 1)}\n")
    with pytest.raises(RuleSemanticError) as info:
        load_rule_file(path)
    assert info.value.location == f"{path}:2:26"


def test_unreadable_files(tmp_path: Path) -> None:
    with pytest.raises(RuleError) as info:
        load_rule_file(tmp_path / "missing.soar")
    assert info.value.message.startswith("cannot read rule file: ")
    path = tmp_path / "latin1.soar"
    path.write_bytes(b"# caf\xe9\nsp {t (state <s>) -->}")
    with pytest.raises(RuleSyntaxError) as info2:
        load_rule_file(path)
    assert (info2.value.line, info2.value.col, info2.value.message) == (
        1, 6, "the file is not UTF-8 text")


def test_deep_nesting_is_an_error_not_a_crash() -> None:
    text = "sp {t (state <s>) " + "-{" * 3000 + "(<s> ^a 1)" + "}" * 3000 + " -->}"
    with pytest.raises(RuleSyntaxError):
        parse_rules(text)


# ---------------------------------------------------------------- fuzzing

VALID = [
    "sp {a*b \"doc\" :o-support (state <s> ^superstate nil ^io.input-link <il> -^done ^p <p>)\n"
    "  (<il> ^x { <x> > 3 <= 10 } ^y << a |b c| 2.5 >>)\n"
    "  -{(<s> ^z <z>) -(<z> ^w <> <x>)}\n-->\n"
    "  (<s> ^operator <o> + = 0.5, > <p>) (<o> ^name go ^v (+ <x> 1))\n"
    "  (<s> ^done <x> -) (write |x=| <x> (crlf)) (halt)}\n",
    "# comment\nsp {c (state <s> ^operator <o> +) (<o> ^name <n>) --> "
    "(<s> ^out.deep.er (concat <n> 1e5 p1)) (<s> ^operator <o> !, ~ <)} ;# end\n",
]
ALPHABET = "sp{}()^<>-+=!~.,|\"#;:abcxyz0123456789 \n\t<<>>{}[]é"
TOKENS = ["sp", "{", "}", "(", ")", "^", "<s>", "<x>", "-", "+", "-->", "state", "<<", ">>",
          "|", "\"", "1.5", "-.5", "1e5", "p1", ":o-support", "(halt)", "(write", "#", ";#",
          "\n", ".", ",", "=", "<=>", "impasse", "gp", "chunk"]


@st.composite
def mutated_rules(draw: st.DrawFn) -> str:
    text = draw(st.sampled_from(VALID))
    for _ in range(draw(st.integers(1, 4))):
        i = draw(st.integers(0, len(text)))
        j = draw(st.integers(i, min(len(text), i + 12)))
        op = draw(st.sampled_from(["delete", "insert", "token", "duplicate"]))
        if op == "delete":
            text = text[:i] + text[j:]
        elif op == "insert":
            text = text[:i] + draw(st.text(ALPHABET, max_size=4)) + text[i:]
        elif op == "token":
            text = text[:i] + " " + draw(st.sampled_from(TOKENS)) + " " + text[i:]
        else:
            text = text[:j] + text[i:j] + text[j:]
    return text


def _parses_or_rule_error(text: str) -> None:
    try:
        parse_rules(text)
    except RuleError as err:
        assert err.line >= 1 and err.col >= 1
        str(err)


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_rules())
def test_garbled_rules_give_a_rule_error_or_a_result(text: str) -> None:
    _parses_or_rule_error(text)


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=60) | st.lists(st.sampled_from(TOKENS), max_size=30).map(" ".join))
def test_random_text_gives_a_rule_error_or_a_result(text: str) -> None:
    _parses_or_rule_error(text)


def test_the_valid_fuzz_seeds_parse() -> None:
    for text in VALID:
        assert parse_rules(text).productions
