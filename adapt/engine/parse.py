"""Soar ``sp {...}`` rule text -> normalised :class:`~adapt.engine.production.Production` records.

:func:`parse_rules` parses a whole rule file (several productions and
comments); :func:`load_rule_file` reads one from disk.  The grammar and the
normalisation are documented in ``docs/rule-language.md`` and in the module
docstring of :mod:`adapt.engine.production`.  Loading is all or nothing: the
first syntax or semantic error raises a :class:`~adapt.errors.RuleSyntaxError`
or :class:`~adapt.errors.RuleSemanticError` that points at the offending
token (``file:line:col``, the line and a caret), and nothing from the file is
returned.

Examples
--------
>>> rules = parse_rules('''
... sp {count*propose
...    (state <s> ^count < 3)
... -->
...    (<s> ^operator <o> + =)
...    (<o> ^name count)}
... ''')
>>> p, = rules.productions
>>> p.name, len(p.conditions), [a.preference.name for a in p.actions]
('count*propose', 1, ['ACCEPTABLE', 'UNARY_INDIFFERENT', 'ACCEPTABLE'])
>>> p.conditions[0]  # doctest: +NORMALIZE_WHITESPACE
Condition(id=<s>, attr=EqualityTest(term='count'), value=RelationalTest(relation='<', term=3),
          acceptable=False, negated=False, location=SourceLocation(file='<string>', line=3, col=4),
          goal=True)
>>> parse_rules("sp {p1 (state <s>) --> (halt)}")
Traceback (most recent call last):
  ...
adapt.errors.RuleSemanticError: <string>:1:5: production name 'p1' is shaped like an identifier (a letter followed by digits), which Soar does not accept as a name
    sp {p1 (state <s>) --> (halt)}
        ^
"""

from __future__ import annotations

import dataclasses
import os
import stat
from dataclasses import dataclass
from typing import Union

from adapt.engine.commands import (
    ON_SOAR,
    Chunking,
    Command,
    CommandSyntaxError,
    Popd,
    Pushd,
    Refusal,
    Setting,
    Source,
    interpret,
    read_command,
    skip_blank,
)
from adapt.engine.functions import FunctionTable, default_functions
from adapt.engine.lexer import CONSTANT_KINDS, Token, token_batches
from adapt.engine.production import (
    Action,
    CallAction,
    Condition,
    ConditionElement,
    ConjunctiveNegation,
    ConjunctiveTest,
    DisjunctionTest,
    EqualityTest,
    FunctionCall,
    MakeAction,
    PreferenceKind,
    Production,
    RelationalTest,
    RhsValue,
    SourceLocation,
    Test,
    Variable,
    condition_equality_variables,
    equality_variable,
    relational_variables,
)
from adapt.engine.symbols import Constant, Float
from adapt.errors import RuleError, RuleSemanticError, RuleSyntaxError

__all__ = ["RuleFile", "parse_rules", "load_rule_file"]


@dataclass(frozen=True)
class RuleFile:
    """The productions an agent file (and the files it sources) adds, in order.

    A later ``sp`` with the name of an earlier one replaces it (the earlier
    one is dropped, the later one keeps its own position, as if Soar excised
    the first and added the second) and adds a warning
    ``file:line:col: warning: production 'x' replaces an earlier one``.

    ``settings`` are the accepted commands that set something on the agent
    (:class:`~adapt.engine.commands.Setting`), each with the number of
    productions read before it (so that a ``multi-attributes`` hint applies
    to the productions after it, as in Soar); ``files`` every file read, the
    top one first.
    """

    productions: tuple[Production, ...]
    warnings: tuple[str, ...] = ()
    settings: tuple[tuple[int, Setting], ...] = ()
    files: tuple[str, ...] = ()


#: How deeply ``source`` may nest (Soar's limit).
MAX_SOURCE_DEPTH = 100

#: The largest rule file read, in bytes (64 MiB: a large agent is a few MB); no more is read.
MAX_FILE_BYTES = 64 * 1024 * 1024

_FLAGS = {":o-support": "o-support", ":i-support": "i-support", ":default": "default",
          ":interrupt": "interrupt"}
#: With learning off, a production Soar flags as a chunk is an ordinary production.
_FLAGS_CHUNKING_OFF = dict(_FLAGS, **{":chunk": ""})
_UNSUPPORTED_FLAGS = {
    ":chunk": "chunking is not implemented",
    ":template": "Soar-RL templates need reinforcement learning, which is not implemented",
}
_UNARY_PREFS = {
    "+": PreferenceKind.ACCEPTABLE,
    "-": PreferenceKind.REJECT,
    "!": PreferenceKind.REQUIRE,
    "~": PreferenceKind.PROHIBIT,
}
_BINARY_PREFS = {
    ">": (PreferenceKind.BEST, PreferenceKind.BETTER),
    "<": (PreferenceKind.WORST, PreferenceKind.WORSE),
    "=": (PreferenceKind.UNARY_INDIFFERENT, PreferenceKind.BINARY_INDIFFERENT),
}
_VALUE_TEST_START = CONSTANT_KINDS | {"variable", "relation", "<<", "{", "+"}
_RHS_VALUE_START = CONSTANT_KINDS | {"variable", "("}
_TYPE_STATE = (EqualityTest("type"), EqualityTest("state"))

_Located = Union[Token, SourceLocation]


def _describe(tok: Token) -> str:
    if tok.kind == "eof":
        return "the end of the file"
    return repr(tok.text)


def _is_state_test(c: ConditionElement) -> bool:
    """A positive condition with Soar's goal test (written in ``(state <s> ...)``)."""
    return isinstance(c, Condition) and not c.negated and c.goal


def _goal_tests_on_roots(conditions: list[ConditionElement]) -> list[ConditionElement]:
    """Soar keeps the goal test of ``(state <x> ...)`` only where ``<x>`` is a
    *root*: a variable no positive condition has as its value
    (``remove_isa_state_tests_for_non_roots``).  ``(state <s> ^fake <f>)
    (state <f> ^name fake)`` tests ``<f>`` as a plain identifier.  When every
    identifier is a value (``(state <s> ^self <s>)``), the first state test's
    identifier is the root."""
    values = {equality_variable(c.value) for c in conditions
              if isinstance(c, Condition) and not c.negated}
    roots = {c.id for c in conditions
             if isinstance(c, Condition) and not c.negated and c.id not in values}
    if not roots:
        # every identifier is some condition's value (``(state <s> ^self <s>)``):
        # Soar takes the first state test's identifier as the root (``reorder_lhs``)
        first = next((c.id for c in conditions
                      if isinstance(c, Condition) and _is_state_test(c)), None)
        roots = {first} if first is not None else set()
    return [dataclasses.replace(c, goal=False)
            if isinstance(c, Condition) and c.goal and not c.negated and c.id not in roots
            else c
            for c in conditions]


def _goal_tests(ident: Variable, conds: list[ConditionElement],
                loc: SourceLocation) -> list[ConditionElement]:
    """The conditions of ``(state <ident> ...)``: those on ``ident`` get the goal
    test; with no positive one among them (``(state <s>)``, ``(state <s> -^a)``,
    which Soar refuses), ``(<ident> ^type state)`` with the goal test comes first."""
    out: list[ConditionElement] = [
        dataclasses.replace(c, goal=True) if isinstance(c, Condition) and c.id == ident else c
        for c in conds]
    if not any(_is_state_test(c) for c in out):
        out.insert(0, Condition(ident, *_TYPE_STATE, location=loc, goal=True))
    return out


def _relational_vars_deep(c: ConditionElement) -> set[Variable]:
    if isinstance(c, Condition):
        return set(relational_variables(c.attr) + relational_variables(c.value))
    out: set[Variable] = set()
    for inner in c.conditions:
        out |= _relational_vars_deep(inner)
    return out


def _binders_first(conds: list[ConditionElement]) -> tuple[ConditionElement, ...]:
    """Order a conjunctive negation's members so that a relational test on a
    variable bound by another member comes after that member (the matcher
    evaluates members in order).  Stable; the order only changes when needed.
    A cycle (two members each binding what the other tests, which Soar
    accepts) is left as written."""
    binders: dict[Variable, set[int]] = {}
    for k, c in enumerate(conds):
        if isinstance(c, Condition) and not c.negated:
            for v in condition_equality_variables(c):
                binders.setdefault(v, set()).add(k)
    needs = [
        {k2 for v in _relational_vars_deep(c) for k2 in binders.get(v, ()) if k2 != k}
        for k, c in enumerate(conds)
    ]
    placed: list[int] = []
    remaining = list(range(len(conds)))
    while remaining:
        ready = next((k for k in remaining if needs[k] <= set(placed)), None)
        if ready is None:
            placed.extend(remaining)
            break
        placed.append(ready)
        remaining.remove(ready)
    return tuple(conds[k] for k in placed)


#: Deepest nesting of ``{ }`` (conjunctive negations) and of function calls
#: in one production: a limit, so that the (possibly compiled) recursive
#: parser and matcher never run out of stack.
MAX_NESTING = 200


class _Parser:
    def __init__(self, text: str, file: str, table: FunctionTable, start: int = 0,
                 flags: dict[str, str] | None = None) -> None:
        self.text = text
        self.file = file
        self.table = table
        self.flags = _FLAGS if flags is None else flags
        self._lines: list[str] | None = None
        self._batches = token_batches(text, file, start=start)
        self.toks: list[Token] = []
        self.i = 0
        #: nesting of ``{`` and of function calls (bounded by MAX_NESTING)
        self.depth = 0
        self._reset_production()

    def _reset_production(self) -> None:
        if self.i:  # the tokens read so far are done with
            del self.toks[:self.i]
            self.i = 0
        self.hidden = 0
        self.rel_tokens: dict[tuple[str, int, int], Token] = {}
        self.rhs_uses: list[tuple[str, Variable, Token]] = []

    # ------------------------------------------------------------ helpers
    def peek(self, k: int = 0) -> Token:
        j = self.i + k
        toks = self.toks
        if j < len(toks):
            return toks[j]
        return self._pull(j)

    def _pull(self, j: int) -> Token:
        """Read tokens until the ``j``-th (or the end of the text)."""
        toks = self.toks
        while len(toks) <= j and (not toks or toks[-1].kind != "eof"):
            toks.extend(next(self._batches))
        return toks[min(j, len(toks) - 1)]

    def advance(self) -> Token:
        tok = self.peek()
        if tok.kind != "eof":
            self.i += 1
        return tok

    def loc(self, tok: Token) -> SourceLocation:
        return SourceLocation(self.file, tok.line, tok.col)

    def _source(self, line: int) -> str | None:
        if self._lines is None:
            self._lines = self.text.splitlines()
        lines = self._lines
        return lines[line - 1] if 0 < line <= len(lines) else None

    def syntax(self, message: str, at: _Located) -> RuleSyntaxError:
        return RuleSyntaxError(
            message, file=self.file, line=at.line, col=at.col, source_line=self._source(at.line)
        )

    def semantic(self, message: str, at: _Located) -> RuleSemanticError:
        return RuleSemanticError(
            message, file=self.file, line=at.line, col=at.col, source_line=self._source(at.line)
        )

    def expect(self, kind: str, what: str) -> Token:
        tok = self.peek()
        if tok.kind != kind:
            raise self.syntax(f"expected {what}, found {_describe(tok)}", tok)
        return self.advance()

    def new_hidden(self) -> Variable:
        self.hidden += 1
        return Variable(f"<#{self.hidden}>")

    @staticmethod
    def constant(tok: Token) -> Constant:
        assert tok.value is not None
        return tok.value

    # ------------------------------------------------------------ file level
    def parse_run(self) -> tuple[list[Production], int]:
        """Parse ``sp {...}`` productions until something else comes.

        Returns the productions in order and the offset of the first token
        that does not begin an ``sp {`` production (the length of the text at
        its end): an agent-file command, or ``sp "..."``, which the caller
        reads (:mod:`adapt.engine.agentfile`).
        """
        productions: list[Production] = []
        while True:
            tok = self.peek()
            if tok.kind == "eof":
                return productions, len(self.text)
            if not (tok.kind == "symbol" and tok.value == "sp") or self.peek(1).kind == "doc":
                return productions, tok.offset
            productions.append(self.parse_production())

    # ------------------------------------------------------------ production
    def parse_production(self) -> Production:
        self._reset_production()
        sp = self.advance()
        self.expect("{", "'{' after 'sp'")
        name_tok = self.peek()
        if name_tok.kind == "idshaped":
            raise self.semantic(
                f"production name '{name_tok.text}' is shaped like an identifier (a letter "
                "followed by digits), which Soar does not accept as a name",
                name_tok,
            )
        if name_tok.kind not in ("symbol", "quoted"):
            raise self.syntax(f"expected a production name, found {_describe(name_tok)}", name_tok)
        self.advance()
        name = str(name_tok.value)
        documentation = None
        if self.peek().kind == "doc":
            documentation = str(self.advance().value)
        flags: set[str] = set()
        while self.peek().kind == "symbol" and str(self.peek().value).startswith(":"):
            flag = self.advance()
            if flag.text in _UNSUPPORTED_FLAGS and flag.text not in self.flags:
                raise self.semantic(
                    f"the flag '{flag.text}' is not supported: {_UNSUPPORTED_FLAGS[flag.text]}; "
                    f"{ON_SOAR}",
                    flag,
                )
            known = self.flags.get(flag.text)
            if known is None:
                raise self.syntax(
                    f"unknown production flag '{flag.text}' (expected :o-support, :i-support, "
                    ":default or :interrupt)",
                    flag,
                )
            if known:
                flags.add(known)
            if {"o-support", "i-support"} <= flags:
                raise self.semantic("a production cannot be both :o-support and :i-support", flag)
        conditions: list[ConditionElement] = []
        while self.peek().kind != "-->":
            tok = self.peek()
            if tok.kind not in ("(", "-", "{"):
                raise self.syntax(
                    f"expected a condition ('(', '-' or '{{') or '-->', found {_describe(tok)}",
                    tok,
                )
            conditions.extend(self.parse_cond())
        arrow = self.advance()
        lhs_bound = self.check_conditions(conditions, arrow)
        conditions = _goal_tests_on_roots(conditions)
        actions: list[Action] = []
        while self.peek().kind != "}":
            tok = self.peek()
            if tok.kind != "(":
                hint = ""
                if tok.kind == "eof" or (tok.kind == "symbol" and tok.value == "sp"):
                    hint = f" (is the '}}' that ends production '{name}' missing?)"
                raise self.syntax(
                    f"expected '(' to begin an action, or '}}', found {_describe(tok)}{hint}", tok
                )
            actions.extend(self.parse_action())
        self.advance()
        self.check_actions(lhs_bound)
        return Production(
            name,
            tuple(conditions),
            tuple(actions),
            documentation=documentation,
            flags=frozenset(flags),
            location=self.loc(sp),
        )

    # ------------------------------------------------------------ conditions
    def negate(self, conds: list[ConditionElement], tok: Token) -> list[ConditionElement]:
        """Soar's negate_condition_list: one condition toggles, several form a -{...}."""
        if len(conds) == 1:
            c = conds[0]
            if isinstance(c, Condition):
                return [dataclasses.replace(c, negated=not c.negated)]
            return list(c.conditions)
        return [ConjunctiveNegation(_binders_first(conds), location=self.loc(tok))]

    def parse_cond(self) -> list[ConditionElement]:
        if self.peek().kind == "-":
            minus = self.advance()
            if self.peek().kind not in ("(", "{"):
                raise self.syntax(
                    f"expected '(' or '{{' after '-', found {_describe(self.peek())}", self.peek()
                )
            return self.negate(self.parse_cond_plus(), minus)
        return self.parse_cond_plus()

    def parse_cond_plus(self) -> list[ConditionElement]:
        tok = self.peek()
        if tok.kind == "(":
            return self.parse_condition()
        if tok.kind == "{":
            self.advance()
            self.enter(tok)
            out: list[ConditionElement] = []
            while self.peek().kind != "}":
                if self.peek().kind not in ("(", "-", "{"):
                    raise self.syntax(
                        f"expected a condition or '}}', found {_describe(self.peek())}", self.peek()
                    )
                out.extend(self.parse_cond())
            self.advance()
            self.depth -= 1
            if not out:
                raise self.syntax("empty '{ }': a conjunction needs at least one condition", tok)
            return out
        raise self.syntax(f"expected '(' to begin a condition, found {_describe(tok)}", tok)

    def parse_condition(self) -> list[ConditionElement]:
        opening = self.advance()
        loc = self.loc(opening)
        is_state = False
        head = self.peek()
        if head.kind == "symbol" and head.value == "state":
            self.advance()
            is_state = True
        elif head.kind == "symbol" and head.value == "impasse":
            raise self.semantic(
                "'impasse' conditions are not supported: Soar 9 has no impasse objects; "
                "test the substate's ^impasse attribute instead",
                head,
            )
        id_tok = self.peek()
        if id_tok.kind != "variable":
            if id_tok.kind == "symbol" and id_tok.value in self.table:
                raise self.syntax(
                    f"expected a variable for the condition's identifier, found "
                    f"{_describe(id_tok)} (is '-->' missing before the actions?)",
                    id_tok,
                )
            if id_tok.kind in ("{", "<<", "relation") or id_tok.kind in CONSTANT_KINDS:
                raise self.semantic(
                    "a condition's identifier must be tested by a plain variable such as <s>",
                    id_tok,
                )
            raise self.syntax(
                f"expected a variable for the condition's identifier, found {_describe(id_tok)}",
                id_tok,
            )
        self.advance()
        ident = Variable(str(id_tok.value))
        out: list[ConditionElement] = []
        while self.peek().kind != ")":
            tok = self.peek()
            if tok.kind not in ("^", "-"):
                raise self.syntax(
                    f"expected '^attribute' or ')' in the condition opened at "
                    f"{opening.line}:{opening.col}, found {_describe(tok)}",
                    tok,
                )
            out.extend(self.parse_attr_value_tests(ident, loc))
        self.advance()
        if is_state:
            return _goal_tests(ident, out, loc)
        if not out:
            out.append(Condition(ident, None, None, location=loc))
        return out

    def parse_attr_value_tests(self, ident: Variable, loc: SourceLocation) -> list[ConditionElement]:
        minus = None
        if self.peek().kind == "-":
            minus = self.advance()
        self.expect("^", "'^' before an attribute")
        attrs = [self.parse_test(loc)]
        while self.peek().kind == ".":
            self.advance()
            attrs.append(self.parse_test(loc))
        values: list[tuple[Test | None, bool]] = []
        while self.peek().kind in _VALUE_TEST_START:
            if self.peek().kind == "+":
                self.advance()
                values.append((None, True))
                continue
            test = self.parse_test(loc)
            acceptable = False
            if self.peek().kind == "+":
                self.advance()
                acceptable = True
            values.append((test, acceptable))
        if not values:
            values.append((None, False))
        conds: list[ConditionElement] = []
        current = ident
        for attr in attrs[:-1]:
            hidden = self.new_hidden()
            conds.append(Condition(current, attr, EqualityTest(hidden), location=loc))
            current = hidden
        for value, acceptable in values:
            conds.append(Condition(current, attrs[-1], value, acceptable, location=loc))
        return self.negate(conds, minus) if minus is not None else conds

    def parse_test(self, loc: SourceLocation) -> Test:
        tok = self.peek()
        if tok.kind != "{":
            return self.parse_simple_test(loc)[0]
        self.advance()
        tests: list[Test] = []
        first_equality: Token | None = None
        while self.peek().kind != "}":
            test, at = self.parse_simple_test(loc)
            if isinstance(test, EqualityTest):
                if first_equality is not None:
                    raise self.semantic(
                        f"a conjunctive test may hold only one equality test; "
                        f"'{first_equality.text}' is already one",
                        at,
                    )
                first_equality = at
            tests.append(test)
        self.advance()
        if not tests:
            raise self.syntax("empty conjunctive test '{ }'", tok)
        return tests[0] if len(tests) == 1 else ConjunctiveTest(tuple(tests))

    def parse_simple_test(self, loc: SourceLocation) -> tuple[Test, Token]:
        tok = self.peek()
        if tok.kind == "<<":
            self.advance()
            values: list[Constant] = []
            while self.peek().kind != ">>":
                v = self.peek()
                if v.kind not in CONSTANT_KINDS:
                    raise self.syntax(
                        f"expected a constant or '>>' in a disjunction, found {_describe(v)}", v
                    )
                values.append(self.constant(self.advance()))
            self.advance()
            if not values:
                raise self.syntax("empty disjunction '<< >>'", tok)
            return DisjunctionTest(tuple(values)), tok
        relation = None
        if tok.kind == "relation":
            relation = str(self.advance().value)
        term_tok = self.peek()
        if term_tok.kind == "variable":
            term: Variable | Constant = Variable(str(term_tok.value))
        elif term_tok.kind in CONSTANT_KINDS:
            term = self.constant(term_tok)
        elif relation is not None:
            raise self.syntax(
                f"expected a variable or a constant after '{relation}', found {_describe(term_tok)}",
                term_tok,
            )
        else:
            raise self.syntax(
                f"expected a test (a variable, a constant, '<<', '{{' or a relation), "
                f"found {_describe(term_tok)}",
                term_tok,
            )
        self.advance()
        if relation is None or relation == "=":
            return EqualityTest(term), (tok if relation else term_tok)
        if isinstance(term, Variable):
            self.rel_tokens.setdefault((term.name, loc.line, loc.col), term_tok)
        return RelationalTest(relation, term), tok

    def check_conditions(self, conditions: list[ConditionElement], arrow: Token) -> set[Variable]:
        """First condition a state, every condition linked, relational variables bound."""
        head: ConditionElement | None = conditions[0] if conditions else None
        while isinstance(head, ConjunctiveNegation):  # (state <s> -^a.b c ...)
            head = head.conditions[0] if head.conditions else None
        if head is None or not any(isinstance(c, Condition) and _is_state_test(c)
                                   and c.id == head.id for c in conditions):
            at: _Located = arrow
            first = conditions[0].location if conditions else None
            if first is not None:
                at = first
            raise self.semantic(
                "the first condition must test a state: '(state <s> ...)'", at
            )
        self.check_links(conditions, set())
        self.check_relations(conditions, set())
        bound: set[Variable] = set()
        for c in conditions:
            if isinstance(c, Condition) and not c.negated:
                bound |= condition_equality_variables(c)
        return bound

    def check_links(self, elements: tuple[ConditionElement, ...] | list[ConditionElement],
                    reach_in: set[Variable], negated: bool = False) -> None:
        """Every positive condition's identifier reachable from a state; inside a
        negation (``negated``) a condition may instead reach the bound variables
        through its attribute or value (``-(<x> ^on <block>)``: no WME on any
        identifier is on the block -- Soar's own agents write this)."""
        reach = set(reach_in)
        positives = [c for c in elements if isinstance(c, Condition) and not c.negated]
        reach |= {c.id for c in positives if _is_state_test(c)}
        pending = list(positives)
        changed = True
        while changed:
            changed = False
            for p in list(pending):
                if p.id in reach or (negated and not reach.isdisjoint(
                        condition_equality_variables(p))):
                    reach |= condition_equality_variables(p)
                    pending.remove(p)
                    changed = True
        for c in elements:
            if isinstance(c, ConjunctiveNegation):
                self.check_links(c.conditions, reach, negated=True)
            elif c in pending or (c.negated and c.id not in reach and reach.isdisjoint(
                    condition_equality_variables(c))):
                assert c.location is not None
                raise self.semantic(
                    f"condition on {c.id} is not linked to a state: {c.id} is not the value "
                    "of any condition reachable from a state variable",
                    c.location,
                )

    def check_relations(self, elements: tuple[ConditionElement, ...] | list[ConditionElement],
                        outer: set[Variable]) -> None:
        local = set(outer)
        for c in elements:
            if isinstance(c, Condition) and not c.negated:
                local |= condition_equality_variables(c)
        for c in elements:
            if isinstance(c, ConjunctiveNegation):
                self.check_relations(c.conditions, local)
                continue
            # a negated condition's own bindings do not count: Soar refuses
            # -(<s> ^{a < <y>} <y>) ("unbound referent in negated relational test")
            for v in relational_variables(c.attr) + relational_variables(c.value):
                if v not in local:
                    assert c.location is not None
                    where = c.location
                    at: _Located = self.rel_tokens.get((v.name, where.line, where.col), where)
                    raise self.semantic(
                        f"variable {v} is used in a relational test but never bound by an "
                        "equality test in a positive condition, so the test cannot be evaluated",
                        at,
                    )

    # ------------------------------------------------------------ actions
    def parse_action(self) -> list[Action]:
        opening = self.advance()
        tok = self.peek()
        if tok.kind == "variable":
            self.advance()
            ident = Variable(str(tok.value))
            self.rhs_uses.append(("id", ident, tok))
            actions: list[Action] = []
            if self.peek().kind != "^":
                raise self.syntax(
                    f"expected '^attribute' after {ident}, found {_describe(self.peek())}",
                    self.peek(),
                )
            while self.peek().kind != ")":
                actions.extend(self.parse_make(ident))
            self.advance()
            return actions
        if tok.kind in ("symbol", "+", "-"):
            call = self.parse_call(opening, as_action=True)
            return [CallAction(call, location=self.loc(opening))]
        raise self.syntax(
            f"expected a variable or a function name after '(', found {_describe(tok)}", tok
        )

    def parse_call(self, opening: Token, *, as_action: bool) -> FunctionCall:
        name_tok = self.peek()
        if name_tok.kind not in ("symbol", "+", "-"):
            raise self.syntax(f"expected a function name, found {_describe(name_tok)}", name_tok)
        self.advance()
        args: list[RhsValue] = []
        while self.peek().kind != ")":
            args.append(self.parse_rhs_value("arg"))
        self.advance()
        name = str(name_tok.value)
        problem = self.table.check_call(name, len(args), as_action=as_action)
        if problem is not None:
            raise self.semantic(problem, name_tok)
        return FunctionCall(name, tuple(args), location=self.loc(opening))

    def enter(self, tok: Token) -> None:
        """One more level of ``{`` or of a nested function call."""
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise self.syntax(f"rule text is nested too deeply (more than {MAX_NESTING} levels)",
                              tok)

    def parse_rhs_value(self, role: str) -> RhsValue:
        tok = self.peek()
        if tok.kind == "(":
            self.advance()
            self.enter(tok)
            call = self.parse_call(tok, as_action=False)
            self.depth -= 1
            return call
        if tok.kind == "variable":
            self.advance()
            var = Variable(str(tok.value))
            self.rhs_uses.append((role, var, tok))
            return var
        if tok.kind in CONSTANT_KINDS:
            return self.constant(self.advance())
        raise self.syntax(
            f"expected a value (a variable, a constant or a function call), found {_describe(tok)}",
            tok,
        )

    def parse_make(self, ident: Variable) -> list[Action]:
        caret = self.peek()
        if caret.kind != "^":
            raise self.syntax(f"expected '^attribute' or ')', found {_describe(caret)}", caret)
        self.advance()
        loc = self.loc(caret)
        attrs = [self.parse_rhs_value("make")]
        while self.peek().kind == ".":
            self.advance()
            attrs.append(self.parse_rhs_value("make"))
        if self.peek().kind not in _RHS_VALUE_START:
            raise self.syntax(
                f"expected a value after the attribute, found {_describe(self.peek())}", self.peek()
            )
        actions: list[Action] = []
        current = ident
        for attr in attrs[:-1]:
            hidden = self.new_hidden()
            actions.append(MakeAction(current, attr, hidden, location=loc))
            current = hidden
        while self.peek().kind in _RHS_VALUE_START:
            value = self.parse_rhs_value("make")
            for kind, referent in self.parse_preferences():
                actions.append(MakeAction(current, attrs[-1], value, kind, referent, location=loc))
        tok = self.peek()
        if tok.kind not in ("^", ")"):
            raise self.syntax(
                f"expected a value, a preference, '^attribute' or ')', found {_describe(tok)}", tok
            )
        return actions

    def parse_preferences(self) -> list[tuple[PreferenceKind, RhsValue | None]]:
        prefs: list[tuple[PreferenceKind, RhsValue | None]] = []
        while True:
            tok = self.peek()
            if tok.kind in _UNARY_PREFS:
                self.advance()
                prefs.append((_UNARY_PREFS[tok.kind], None))
            elif tok.kind == "relation" and tok.value in _BINARY_PREFS:
                self.advance()
                unary, binary = _BINARY_PREFS[str(tok.value)]
                if self.peek().kind in _RHS_VALUE_START:
                    referent = self.parse_rhs_value("referent")
                    kind = binary
                    if kind is PreferenceKind.BINARY_INDIFFERENT and (
                        type(referent) is int or type(referent) is Float
                    ):
                        kind = PreferenceKind.NUMERIC_INDIFFERENT
                    prefs.append((kind, referent))
                else:
                    prefs.append((unary, None))
            else:
                break
            if self.peek().kind == ",":
                self.advance()
        return prefs or [(PreferenceKind.ACCEPTABLE, None)]

    def check_actions(self, lhs_bound: set[Variable]) -> None:
        known = set(lhs_bound)
        known |= {v for role, v, _ in self.rhs_uses if role == "make"}
        for role, var, tok in self.rhs_uses:
            if var in known:
                continue
            if role == "id":
                raise self.semantic(
                    f"variable {var} is used as an action's identifier but is neither bound by "
                    "a positive condition nor created as a value by an action",
                    tok,
                )
            what = "a function call" if role == "arg" else "a preference's referent"
            raise self.semantic(
                f"variable {var} is used in {what} but is neither bound by a positive condition "
                "nor created as a value by an action",
                tok,
            )


def parse_rules(
    text: str, *, file: str = "<string>", functions: FunctionTable | None = None,
    chunking: Chunking = "refuse",
) -> RuleFile:
    """Parse agent text: ``sp`` productions, comments and agent-file commands.

    Parameters
    ----------
    text : str
        The rule text.
    file : str
        The name used in error positions and warnings.
    functions : FunctionTable, optional
        The RHS functions calls are checked against (default: the built-ins).
    chunking : {"refuse", "off"}
        What commands that turn chunking on do: an error (the default), or
        nothing (an agent written for chunking, run with learning off).

    Returns
    -------
    RuleFile
        The productions, normalised, any warnings and the settings.
        ``source`` in the text reads files relative to the current directory.

    Raises
    ------
    RuleSyntaxError, RuleSemanticError
        At the first error; nothing is returned from a text with an error.

    Examples
    --------
    >>> parse_rules("sp {a (state <s>) --> (<s> ^b.c 1)}").productions[0].actions
    ... # doctest: +NORMALIZE_WHITESPACE, +ELLIPSIS
    (MakeAction(id=<s>, attr='b', value=<#1>, preference=<PreferenceKind.ACCEPTABLE: '+'>,
                referent=None, location=...),
     MakeAction(id=<#1>, attr='c', value=1, preference=<PreferenceKind.ACCEPTABLE: '+'>,
                referent=None, location=...))
    >>> rules = parse_rules('''srand 7
    ... sp "a (state <s>) --> (write |quoted body|)"''')
    >>> rules.settings, rules.productions[0].name
    (((0, Setting(kind='seed', name=None, value=7)),), 'a')
    """
    reader = _AgentReader(functions if functions is not None else _default_table(), chunking)
    try:
        reader.read_text(text, file)
    except RecursionError:
        raise RuleSyntaxError("rule text is nested too deeply", file=file) from None
    return reader.result()


_DEFAULT: list[FunctionTable] = []


def _default_table() -> FunctionTable:
    if not _DEFAULT:
        _DEFAULT.append(default_functions())
    return _DEFAULT[0]


def load_rule_file(
    path: str | os.PathLike[str], *, functions: FunctionTable | None = None,
    chunking: Chunking = "refuse",
) -> RuleFile:
    """Read an agent file (UTF-8, a byte-order mark allowed) and the files it sources.

    The file is read as Soar's ``source`` reads it: ``source`` lines inside it
    are relative to its directory (and to ``pushd`` / ``popd``).  Errors name
    each file by its path joined to the top file's path as given.

    Raises
    ------
    RuleError
        When a file cannot be read or is not UTF-8 text, and every
        :func:`parse_rules` error.
    """
    reader = _AgentReader(functions if functions is not None else _default_table(), chunking)
    name = os.fspath(path)
    try:
        reader.source(name, None)
    except RecursionError:
        raise RuleSyntaxError("rule text is nested too deeply", file=name) from None
    return reader.result()


def read_text_file(name: str) -> str:
    """The text of a UTF-8 file (a byte-order mark dropped).

    Raises
    ------
    RuleError
        When the file cannot be read, is a device, is larger than
        :data:`MAX_FILE_BYTES` (no more than that is read) or is not UTF-8 text.
    """
    try:
        mode = os.stat(name).st_mode
        if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):  # /dev/zero would never end
            raise RuleError("not a rule file but a device; expected a text file", file=name)
        with open(name, "rb") as handle:
            data = handle.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise RuleError(f"cannot read rule file: {exc.strerror or exc}", file=name) from None
    if len(data) > MAX_FILE_BYTES:
        raise RuleError(f"the file is larger than {MAX_FILE_BYTES // (1024 * 1024)} MiB; "
                        "expected a rule file", file=name)
    try:
        text = data.decode("utf-8-sig")  # a byte-order mark (as some editors write) is not text
    except UnicodeDecodeError as exc:
        before = data[: exc.start]
        line = before.count(b"\n") + 1
        col = exc.start - (before.rfind(b"\n") + 1) + 1
        raise RuleSyntaxError("the file is not UTF-8 text", file=name, line=line, col=col) from None
    return text[1:] if text.startswith("\ufeff") else text


class _AgentReader:
    """Reads agent files as Soar's ``source`` does: productions and commands."""

    def __init__(self, table: FunctionTable, chunking: Chunking) -> None:
        self.table = table
        self.chunking = chunking
        self.flags = _FLAGS_CHUNKING_OFF if chunking == "off" else _FLAGS
        #: the directory stack; relative paths resolve against the last one
        self.dirs: list[str] = [""]
        self.items: list[Production | Setting] = []
        self.files: list[str] = []
        self.depth = 0

    def result(self) -> RuleFile:
        """The productions (later ones replacing earlier ones of the same name)."""
        last: dict[str, int] = {}
        for k, item in enumerate(self.items):
            if isinstance(item, Production):
                last[item.name] = k
        productions: list[Production] = []
        settings: list[tuple[int, Setting]] = []
        warnings: list[str] = []
        seen: set[str] = set()
        for k, item in enumerate(self.items):
            if isinstance(item, Setting):
                settings.append((len(productions), item))
                continue
            if item.name in seen:
                where = item.location
                warnings.append(f"{where.file}:{where.line}:{where.col}: warning: "
                                f"production '{item.name}' replaces an earlier one"
                                if where is not None else
                                f"warning: production '{item.name}' replaces an earlier one")
            seen.add(item.name)
            if last[item.name] == k:
                productions.append(item)
        return RuleFile(tuple(productions), tuple(warnings), tuple(settings),
                        tuple(self.files))

    # -- files ---------------------------------------------------------------------
    def source(self, path: str, at: RuleError | None) -> None:
        """Read ``path`` as Soar's ``source`` does (``at``: the error to raise, with
        its position, when the file cannot be read)."""
        path = path.replace("\\", "/")
        folder, slash, filename = path.rpartition("/")
        base = self.dirs[-1]
        if slash:
            directory = _join(base, folder or "/")
            if not os.path.isdir(directory):
                raise _with_message(at, f"cannot source {path}: no directory {directory}",
                                    directory)
            self.dirs.append(directory)
        name = _join(self.dirs[-1], filename)
        try:
            if at is not None and not os.path.isfile(name):
                raise _with_message(at, f"cannot source {path}: no file {name}", name)
            text = read_text_file(name)
            self.files.append(name)
            self.depth += 1
            self.read_text(text, name)
            self.depth -= 1
        finally:
            if slash:
                self.dirs.pop()

    def read_text(self, text: str, file: str) -> None:
        """Read the productions and commands of ``text``."""
        if text.startswith("\ufeff"):
            text = text[1:]
        pos = 0
        n = len(text)
        while True:
            pos = skip_blank(text, pos)
            if pos >= n:
                return
            if text.startswith("sp", pos) and (pos + 2 == n or not _word_char(text[pos + 2])):
                after = skip_blank(text, pos + 2)
                if after >= n or text[after] != '"':
                    productions, pos = _Parser(text, file, self.table, pos,
                                               self.flags).parse_run()
                    self.items.extend(productions)
                    continue
            try:
                command = read_command(text, pos)
            except CommandSyntaxError as exc:
                raise _error(RuleSyntaxError, text, file, exc.offset, exc.message) from None
            pos = self.command(text, file, pos, command)

    def command(self, text: str, file: str, pos: int, command: Command) -> int:
        """Do one command; returns the offset after it."""
        words = command.words
        if words[0] == "sp":
            return self.quoted_production(text, file, command)
        try:
            meaning = interpret(command, self.chunking)
        except Refusal as exc:
            at = command.starts[min(exc.word, len(command.starts) - 1)]
            cls = RuleSyntaxError if exc.unknown else RuleSemanticError
            raise _error(cls, text, file, at, exc.message) from None
        if isinstance(meaning, Setting):
            self.items.append(meaning)
        elif isinstance(meaning, Source):
            if self.depth >= MAX_SOURCE_DEPTH:
                raise _error(RuleSemanticError, text, file, pos,
                             f"source depth ({MAX_SOURCE_DEPTH}) exceeded: does a file source "
                             "itself?")
            here = _error(RuleError, text, file, command.starts[1 if len(words) > 1 else 0], "")
            try:
                self.source(meaning.path, here)
            except RuleError as exc:
                if exc.file == here.file and exc.line == here.line:
                    raise
                raise type(exc)(f"{exc.message} (in a file sourced at {here.location})",
                                file=exc.file, line=exc.line, col=exc.col,
                                source_line=exc.source_line) from None
        elif isinstance(meaning, Pushd):
            directory = _join(self.dirs[-1], meaning.path.replace("\\", "/"))
            if not os.path.isdir(directory):
                raise _error(RuleSemanticError, text, file, command.starts[1],
                             f"pushd: no directory {directory}")
            self.dirs.append(directory)
        elif isinstance(meaning, Popd):
            if len(self.dirs) == 1:
                raise _error(RuleSemanticError, text, file, pos,
                             "popd: the directory stack is empty (no pushd before it)")
            self.dirs.pop()
        return command.end

    def quoted_production(self, text: str, file: str, command: Command) -> int:
        """``sp "..."``: the production in the quoted word, read in place."""
        if len(command.words) != 2 or text[command.starts[1]] != '"':
            raise _error(RuleSyntaxError, text, file, command.starts[0],
                         "expected '{' or '\"' after 'sp'")
        start, end = command.starts[1], command.end
        while text[end - 1] != '"':  # the word ends at its closing quote
            end -= 1
        # the same text with the quotes made braces and each escape one space
        # and the character (positions stay those of the file)
        body: list[str] = []
        i = start + 1
        while i < end - 1:
            c = text[i]
            if c == "\\" and i + 1 < end - 1:
                nxt = text[i + 1]
                body.append(" " + (" " if nxt in "abfnrtv" else nxt))
                i += 2
                continue
            body.append(c)
            i += 1
        masked = text[:start] + "{" + "".join(body) + "}" + text[end:]
        productions, stop = _Parser(masked, file, self.table, command.starts[0],
                                    self.flags).parse_run()
        self.items.extend(productions[:1])
        return end


def _word_char(c: str) -> bool:
    return not (c.isspace() or c in '{";#')


def _join(base: str, path: str) -> str:
    if not base or os.path.isabs(path):
        return os.path.normpath(path) if base else path
    return os.path.normpath(os.path.join(base, path))


def _error(cls: type[RuleError], text: str, file: str, offset: int, message: str) -> RuleError:
    line = text.count("\n", 0, offset) + 1
    line_start = text.rfind("\n", 0, offset) + 1
    line_end = text.find("\n", offset)
    source_line = text[line_start:] if line_end < 0 else text[line_start:line_end]
    return cls(message, file=file, line=line, col=offset - line_start + 1,
               source_line=source_line)


def _with_message(at: RuleError | None, message: str, file: str) -> RuleError:
    if at is None:
        return RuleError(f"cannot read rule file: {message}", file=file)
    return RuleSemanticError(message, file=at.file, line=at.line, col=at.col,
                             source_line=at.source_line)
