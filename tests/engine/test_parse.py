"""The parser's normalised output, construct by construct.

Lexing and negation facts marked "Soar 9.6.5" were checked by running the
real kernel (soar-sml 9.6.5) on small agents.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from adapt.engine.lexer import tokenize
from adapt.engine.parse import RuleFile, load_rule_file, parse_rules
from adapt.engine.production import (
    CallAction,
    Condition,
    ConjunctiveNegation,
    ConjunctiveTest,
    DisjunctionTest,
    EqualityTest,
    FunctionCall,
    MakeAction,
    RelationalTest,
    Variable,
)
from adapt.engine.production import (
    PreferenceKind as K,
)
from adapt.engine.symbols import Float

S, X, Y, O, O1, O2 = (Variable(n) for n in ("<s>", "<x>", "<y>", "<o>", "<o1>", "<o2>"))
H1, H2, H3 = Variable("<#1>"), Variable("<#2>"), Variable("<#3>")


def eq(term: object) -> EqualityTest:
    return EqualityTest(term)  # type: ignore[arg-type]


def cond(id_: Variable, attr: object, value: object = None, acceptable: bool = False,
         negated: bool = False) -> Condition:
    a = attr if attr is None or not isinstance(attr, (str, int, Float, Variable)) else eq(attr)
    v = value if value is None or not isinstance(value, (str, int, Float, Variable)) else eq(value)
    return Condition(id_, a, v, acceptable, negated)  # type: ignore[arg-type]


def goal(c: Condition) -> Condition:
    """``c`` with the goal test of ``(state <s> ...)``."""
    return dataclasses.replace(c, goal=True)


#: ``(<s> ^type state)`` with the goal test: what ``(state <s>)`` alone reads as
STATE = goal(cond(S, "type", "state"))


def lhs(text: str) -> tuple:
    """Conditions of ``sp {t <text> --> }``."""
    return parse_rules(f"sp {{t {text} -->}}").productions[0].conditions


def rhs(text: str, conditions: str = "(state <s> ^x <x> ^y <y>)") -> tuple:
    return parse_rules(f"sp {{t {conditions} --> {text}}}").productions[0].actions


LHS_CASES = [
    ("(state <s>)", (STATE,)),
    ("(state <s> ^a 1)", (goal(cond(S, "a", 1)),)),
    ("(state <s> ^a)", (goal(cond(S, "a")),)),
    ("(state <s> ^a <x> ^b |two words|)", (goal(cond(S, "a", X)), goal(cond(S, "b", "two words")))),
    ("(state <s> ^a 1 2.5)", (goal(cond(S, "a", 1)), goal(cond(S, "a", Float(2.5))))),
    ("(state <s> ^a.b.c 3)",
     (goal(cond(S, "a", H1)), cond(H1, "b", H2), cond(H2, "c", 3))),
    ("(state <s> ^a.b 1 2)", (goal(cond(S, "a", H1)), cond(H1, "b", 1), cond(H1, "b", 2))),
    # Soar refuses a state test with no positive attribute test; adapt adds ^type state
    ("(state <s> -^a)", (STATE, goal(cond(S, "a", negated=True)))),
    ("(state <s> -^a 1)", (STATE, goal(cond(S, "a", 1, negated=True)))),
    ("(state <s> -^a 1 ^b 2)", (goal(cond(S, "a", 1, negated=True)), goal(cond(S, "b", 2)))),
    # Soar 9.6.5: -^a 1 2 and -^a.b c are conjunctive negations (not each).
    ("(state <s> -^a 1 2)",
     (STATE, ConjunctiveNegation((cond(S, "a", 1), cond(S, "a", 2))))),
    ("(state <s> -^a.b c)",
     (STATE, ConjunctiveNegation((cond(S, "a", H1), cond(H1, "b", "c"))))),
    ("(state <s>) -(<s> ^a 1)", (STATE, cond(S, "a", 1, negated=True))),
    ("(state <s>) -(<s> ^a 1 ^b 2)",
     (STATE, ConjunctiveNegation((cond(S, "a", 1), cond(S, "b", 2))))),
    ("(state <s>) -{(<s> ^a <x>) (<x> ^b 2)}",
     (STATE, ConjunctiveNegation((cond(S, "a", X), cond(X, "b", 2))))),
    ("(state <s>) -{(<s> ^a <x>) -{(<x> ^b <y>) (<y> ^c 1)}}",
     (STATE, ConjunctiveNegation((
         cond(S, "a", X),
         ConjunctiveNegation((cond(X, "b", Y), cond(Y, "c", 1))))))),
    # Soar 9.6.5: negating a single negated condition makes it positive again.
    ("(state <s>) -{-(<s> ^a 1)}", (STATE, cond(S, "a", 1))),
    ("(state <s>) -{(<s> ^a 1)}", (STATE, cond(S, "a", 1, negated=True))),
    ("(state <s>) {(<s> ^a <x>) (<x> ^b 1)}", (STATE, cond(S, "a", X), cond(X, "b", 1))),
    ("(state <s> ^a << x 1 |y z| >>)", (goal(cond(S, "a", DisjunctionTest(("x", 1, "y z")))),)),
    ("(state <s> ^a <> 1)", (goal(cond(S, "a", RelationalTest("<>", 1))),)),
    ("(state <s> ^a <=> <x> ^x <x>)",
     (goal(cond(S, "a", RelationalTest("<=>", X))), goal(cond(S, "x", X)))),
    ("(state <s> ^a = 5)", (goal(cond(S, "a", 5)),)),
    ("(state <s> ^a { <x> > 3 <= 10 })",
     (goal(cond(S, "a", ConjunctiveTest((eq(X), RelationalTest(">", 3),
                                         RelationalTest("<=", 10))))),)),
    ("(state <s> ^a { < 5 })", (goal(cond(S, "a", RelationalTest("<", 5))),)),
    ("(state <s> ^<x> 1)", (goal(cond(S, X, 1)),)),
    ("(state <s> ^{<x> <> type} 1)",
     (goal(cond(S, ConjunctiveTest((eq(X), RelationalTest("<>", "type"))), 1)),)),
    ("(state <s> ^<< a b >> 1)", (goal(cond(S, DisjunctionTest(("a", "b")), 1)),)),
    ("(state <s> ^operator <o> +)", (goal(cond(S, "operator", O, acceptable=True)),)),
    ("(state <s> ^operator +)", (goal(cond(S, "operator", None, acceptable=True)),)),
    ("(state <s> ^operator <o>) (<o> ^name go)",
     (goal(cond(S, "operator", O)), cond(O, "name", "go"))),
    # Soar keeps the goal test only on roots: <x> is the value of ^superstate
    ("(state <s> ^superstate <x>) (state <x>)", (goal(cond(S, "superstate", X)),
                                                 cond(X, "type", "state"))),
    ("(state <s> ^superstate <x>) (state <x> ^name a)", (goal(cond(S, "superstate", X)),
                                                         cond(X, "name", "a"))),
    ("(state <s> ^superstate nil) (state <x> ^superstate nil)",
     (goal(cond(S, "superstate", "nil")), goal(cond(X, "superstate", "nil")))),
    ("(state <s> ^a <x>) (<x>)", (goal(cond(S, "a", X)), Condition(X, None, None))),
    # Soar 9.6.5: identifier-shaped tokens are strings, upper-cased; 1e5 is a string.
    ("(state <s> ^a p1 q01 1e5 1.5e3)",
     (goal(cond(S, "a", "P1")), goal(cond(S, "a", "Q1")), goal(cond(S, "a", "1e5")),
      goal(cond(S, "a", Float(1500.0))))),
]


@pytest.mark.parametrize("text, expected", LHS_CASES, ids=[c[0] for c in LHS_CASES])
def test_conditions_are_normalised(text: str, expected: tuple) -> None:
    assert lhs(text) == expected


RHS_CASES = [
    ("(<s> ^a 1)", (MakeAction(S, "a", 1),)),
    ("(<s> ^a 1 2)", (MakeAction(S, "a", 1), MakeAction(S, "a", 2))),
    ("(<s> ^a <x> -)", (MakeAction(S, "a", X, K.REJECT),)),
    ("(<s> ^a <n>) (<n> ^b 2)",
     (MakeAction(S, "a", Variable("<n>")), MakeAction(Variable("<n>"), "b", 2))),
    # Soar 9.6.5 accepts a new identifier used before the action that links it.
    ("(<n> ^b 2) (<s> ^a <n>)",
     (MakeAction(Variable("<n>"), "b", 2), MakeAction(S, "a", Variable("<n>")))),
    ("(<s> ^a.b.c 1)",
     (MakeAction(S, "a", H1), MakeAction(H1, "b", H2), MakeAction(H2, "c", 1))),
    ("(<s> ^<x> <y>)", (MakeAction(S, X, Y),)),
    ("(<s> ^(concat a <x>) 1)", (MakeAction(S, FunctionCall("concat", ("a", X)), 1),)),
    ("(<s> ^a (+ <x> (* 2 <y>)))",
     (MakeAction(S, "a", FunctionCall("+", (X, FunctionCall("*", (2, Y))))),)),
    ("(<s> ^operator <o> +)", (MakeAction(S, "operator", O),)),
    ("(<s> ^operator <o> !)", (MakeAction(S, "operator", O, K.REQUIRE),)),
    ("(<s> ^operator <o> ~)", (MakeAction(S, "operator", O, K.PROHIBIT),)),
    ("(<s> ^operator <o> -)", (MakeAction(S, "operator", O, K.REJECT),)),
    ("(<s> ^operator <o> >)", (MakeAction(S, "operator", O, K.BEST),)),
    ("(<s> ^operator <o> <)", (MakeAction(S, "operator", O, K.WORST),)),
    ("(<s> ^operator <o> =)", (MakeAction(S, "operator", O, K.UNARY_INDIFFERENT),)),
    ("(<s> ^operator <o> + =)",
     (MakeAction(S, "operator", O), MakeAction(S, "operator", O, K.UNARY_INDIFFERENT))),
    ("(<s> ^operator <o> +, =, >)",
     (MakeAction(S, "operator", O), MakeAction(S, "operator", O, K.UNARY_INDIFFERENT),
      MakeAction(S, "operator", O, K.BEST))),
    ("(<s> ^operator <o> = 0.5)",
     (MakeAction(S, "operator", O, K.NUMERIC_INDIFFERENT, Float(0.5)),)),
    ("(<s> ^operator <o> = 3)", (MakeAction(S, "operator", O, K.NUMERIC_INDIFFERENT, 3),)),
    ("(<s> ^operator <o> = <x>)", (MakeAction(S, "operator", O, K.BINARY_INDIFFERENT, X),)),
    # Soar 9.6.5: the value after a binary preference is its referent, not a new value:
    # in `<o1> > <o2> +` only <o1> gets the acceptable preference.
    ("(<s> ^operator <x> > <y> +)",
     (MakeAction(S, "operator", X, K.BETTER, Y), MakeAction(S, "operator", X))),
    ("(<s> ^operator <x> < <y>)", (MakeAction(S, "operator", X, K.WORSE, Y),)),
    ("(<s> ^operator <x> + <y> +)", (MakeAction(S, "operator", X), MakeAction(S, "operator", Y))),
    ("(<s> ^operator <x> + <y> + = 0.3)",
     (MakeAction(S, "operator", X), MakeAction(S, "operator", Y),
      MakeAction(S, "operator", Y, K.NUMERIC_INDIFFERENT, Float(0.3)))),
    ("(write |a b| <x> (crlf))",
     (CallAction(FunctionCall("write", ("a b", X, FunctionCall("crlf", ())))),)),
    ("(halt)", (CallAction(FunctionCall("halt", ())),)),
    ("(<s> ^a -5 +5 -.5 5.)", (MakeAction(S, "a", -5), MakeAction(S, "a", 5),
                               MakeAction(S, "a", Float(-0.5)), MakeAction(S, "a", Float(5.0)))),
]


@pytest.mark.parametrize("text, expected", RHS_CASES, ids=[c[0] for c in RHS_CASES])
def test_actions_are_normalised(text: str, expected: tuple) -> None:
    assert rhs(text) == expected


def test_rhs_hidden_variables_continue_the_lhs_numbering() -> None:
    p = parse_rules("sp {t (state <s> ^a.b <x>) --> (<s> ^c.d <x>)}").productions[0]
    assert p.actions == (MakeAction(S, "c", H2), MakeAction(H2, "d", X))


def test_production_header() -> None:
    text = 'sp {my*rule "says \\"hi\\"" :o-support :default (state <s>) --> (halt)}'
    p = parse_rules(text).productions[0]
    assert (p.name, p.documentation, p.flags) == (
        "my*rule", 'says "hi"', frozenset({"o-support", "default"}))
    assert parse_rules("sp {|quoted name| (state <s>) -->}").productions[0].name == "quoted name"


def test_locations_point_at_source() -> None:
    text = "# comment\nsp {t\n  (state <s>)\n-->\n  (<s> ^a 1)}"
    p = parse_rules(text, file="f.soar").productions[0]
    assert str(p.location) == "f.soar:2:1"
    assert str(p.conditions[0].location) == "f.soar:3:3"
    assert str(p.actions[0].location) == "f.soar:5:8"


def test_comments_and_several_rules() -> None:
    text = """
    # a comment with sp {fake (state <s>) -->}
    sp {one (state <s>) --> (<s> ^a 1)} ;# trailing comment
    sp {two   # comment inside
        (state <s>)  ;# another
    -->
        (<s> ^b |#not a comment|)}
    """
    rf = parse_rules(text)
    assert [p.name for p in rf.productions] == ["one", "two"]
    assert rf.productions[1].actions == (MakeAction(S, "b", "#not a comment"),)
    assert rf.warnings == ()


def test_a_later_production_replaces_an_earlier_one_with_a_warning() -> None:
    text = ("sp {a (state <s>) --> (<s> ^v 1)}\n"
            "sp {b (state <s>) --> (<s> ^v 2)}\n"
            "  sp {a (state <s>) --> (<s> ^v 3)}\n")
    rf = parse_rules(text, file="r.soar")
    assert [(p.name, p.actions[0].value) for p in rf.productions] == [("b", 2), ("a", 3)]
    assert rf.warnings == ("r.soar:3:3: warning: production 'a' replaces an earlier one",)


def test_empty_text_gives_no_productions() -> None:
    assert parse_rules("  # nothing\n") == RuleFile((), ())


def test_quoted_string_escapes_as_soar() -> None:
    # Soar 9.6.5: a backslash takes the next character literally (|a\|b\\c\nd| is a|b\cnd).
    assert rhs(r"(<s> ^a |a\|b\\c\nd|)")[0].value == "a|b\\cnd"


@pytest.mark.parametrize("text, values", [
    # Soar 9.6.5 splits these exactly so.
    ("1.2.3", [Float(1.2), Float(0.3)]),
    ("1..2", [Float(1.0), Float(0.2)]),
    ("-5.5.5", [Float(-5.5), Float(0.5)]),
    ("5a a5 e5 1e 5e-3 0x10 007 -0 +.5", ["5a", "A5", "E5", "1e", "5e-3", "0x10", 7, 0,
                                          Float(0.5)]),
    ("a:b -x <a a> <a>b &*? x,y", ["a:b", "-x", "<a", "a>", "<a>b", "&*?", "x", ",", "y"]),
])
def test_lexing_matches_soar(text: str, values: list) -> None:
    assert [t.value for t in tokenize(text)][:-1] == values


def test_user_functions_are_checked_against_the_given_table() -> None:
    from adapt.engine.functions import default_functions
    table = default_functions()
    table.register("distance", lambda a, b: abs(a - b), min_args=2, max_args=2)
    p = parse_rules("sp {t (state <s> ^x <x>) --> (<s> ^d (distance <x> 3))}",
                    functions=table).productions[0]
    assert p.actions[0].value == FunctionCall("distance", (X, 3))


def test_load_rule_file(tmp_path: Path) -> None:
    path = tmp_path / "r.soar"
    path.write_text("sp {t (state <s>) --> (halt)}\n", encoding="utf-8")
    rf = load_rule_file(path)
    assert rf.productions[0].name == "t"
    assert rf.productions[0].location is not None
    assert rf.productions[0].location.file == str(path)


def test_binding_sites_of_a_parsed_production() -> None:
    p = parse_rules("sp {t (state <s> ^a.b <x>) -(<x> ^c <y>) --> (<s> ^d <x>)}").productions[0]
    assert p.binding_sites == {S: (0, 0), H1: (0, 2), X: (1, 2)}


def test_conjunctive_negation_members_are_ordered_binders_first() -> None:
    # The relational test on <x> needs <x> bound first inside the negation.
    assert lhs("(state <s>) -{(<s> ^b < <x>) (<s> ^a <x>)}") == (
        STATE, ConjunctiveNegation((cond(S, "a", X), cond(S, "b", RelationalTest("<", X)))))
    assert lhs("(state <s>) -{(<s> ^a <x>) (<s> ^b < <x>)}") == (
        STATE, ConjunctiveNegation((cond(S, "a", X), cond(S, "b", RelationalTest("<", X)))))
