"""``rules check`` and ``rules run`` on generated rule text, and the trace tools on what ran.

The text is a real rule file (the water jug, or a small counter) with tokens
of the rule language inserted, deleted and repeated -- braces, conditions,
arrows, tests, right-hand-side calls that fail at run time (``(/ 1 0)``,
``(int abc)``), ``(halt)`` and ``(interrupt)`` -- or bytes that are not UTF-8.
Runs are bounded by ``--max-decisions``; the trace a run writes is then read
back by ``trace stats``, ``show``, ``wm`` and ``html``.
"""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from .harness import HALTING_RULES, Pool, examples, run_checked

TOKENS = ["sp {", "sp {x", "}", "{", "(", ")", "<s>", "<o>", "<c>", "^", "^operator", "-->", "state",
          "+", "-", "<", ">", "=", "<=>", "<<", ">>", "|", "|a b|", "(write", "(write |x| (crlf))",
          "(halt)", "(interrupt)", "(crlf)", "(+ 1 2)", "(/ 1 0)", "(div 1 0)", "(mod 3 0)",
          "(int abc)", "(float x)", "(exec foo)", "(cmd ls)", "(make-constant-symbol)", "#", ";",
          "\n", "\r\n", '"', "\\", "@", "!", "~", "&", "1e400", "-0", "3.", ".5", "9" * 40,
          "\ufeff", "é", "\u2028", "<s> ^superstate nil", "-{", "(<s> ^count <c>)", "^name.x.y",
          "(state <s> ^superstate nil)", "--> (<s> ^operator <o> +) (<o> ^name x)}", "\t"]


@st.composite
def rule_texts(draw: st.DrawFn, base: str) -> bytes:
    text = base
    for _ in range(draw(st.integers(0, 4))):
        at = draw(st.integers(0, len(text)))
        operation = draw(st.integers(0, 3))
        if operation == 0:
            text = text[:at] + draw(st.sampled_from(TOKENS)) + text[at:]
        elif operation == 1:
            text = text[:at] + text[at + draw(st.integers(1, 40)):]
        elif operation == 2:
            end = min(len(text), at + draw(st.integers(1, 200)))
            text = text[:end] + text[at:end] + text[end:]
        else:
            text = text[:at] + draw(st.text(max_size=5)) + text[at:]
    data = text.encode("utf-8", "surrogatepass")
    if draw(st.integers(0, 14)) == 0:
        data = data[: len(data) // 2] + b"\xff\xfe\x80" + data[len(data) // 2:]
    return data


def _check_and_run(pool: Pool, data: bytes, run_args: list[str]) -> None:
    folder = pool.outputs()
    rules = folder / "r.soar"
    rules.write_bytes(data)
    run_checked(pool, ["rules", "check", str(rules)])
    trace = folder / "t.jsonl"
    outcome = run_checked(pool, ["rules", "run", str(rules), *run_args, "--trace", str(trace)])
    if outcome.status != 1 and trace.exists():
        for command in (["stats"], ["show", "--level", "5"], ["wm"], ["html", "--out", str(folder / "t.html")]):
            run_checked(pool, ["trace", command[0], str(trace), *command[1:]])


RUN_ARGS = st.tuples(st.sampled_from(["0", "1", "5", "20"]),
                     st.sampled_from([[], ["--matcher", "naive"], ["--json"], ["--trace-level", "3"]]))


def test_generated_counter_rules(pool: Pool) -> None:
    @settings(max_examples=examples(40), deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(rule_texts(HALTING_RULES), RUN_ARGS)
    def check(data: bytes, args: tuple[str, list[str]]) -> None:
        _check_and_run(pool, data, ["--max-decisions", args[0], *args[1]])

    check()


def test_generated_water_jug_rules(pool: Pool) -> None:
    base = pool.files["wj.soar"].read_text(encoding="utf-8")

    @settings(max_examples=examples(25), deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(rule_texts(base), RUN_ARGS)
    def check(data: bytes, args: tuple[str, list[str]]) -> None:
        _check_and_run(pool, data, ["--max-decisions", args[0], *args[1]])

    check()


def test_random_text_as_rules(pool: Pool) -> None:
    @settings(max_examples=examples(40), deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow])
    @given(st.binary(max_size=200) | st.text(max_size=200).map(lambda t: t.encode("utf-8", "surrogatepass")))
    def check(data: bytes) -> None:
        _check_and_run(pool, data, ["--max-decisions", "3"])

    check()
