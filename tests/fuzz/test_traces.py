"""Every ``adapt trace`` command, on generated broken traces.

A trace is a real run's trace (the water jug, level 5) with a few records
broken: a field replaced by another JSON value (a string where a list is
expected, ``"adds": "oops"``, a lone surrogate ``"\\ud800"``, a huge or
negative number, a deep nesting), a field removed, a record's kind changed,
lines deleted, duplicated or swapped, bytes that are not UTF-8, a truncated
last line.  Each ``trace`` subcommand must answer or refuse it with a
positioned ``adapt: error: FILE:LINE: ...``; the reader checks every record
(``adapt/traceview/records.py``) so that no inspector meets a value of the
wrong type.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from adapt.traceview.reader import Trace
from adapt.traceview.records import check_record, phase_ok

from .harness import Pool, examples, run_checked

SCHEMA_PATH = Path(__file__).resolve().parents[2] / "docs" / "trace-format.schema.json"

JSON_LEAVES = st.one_of(
    st.none(), st.booleans(), st.integers(-(2**70), 2**70), st.sampled_from([0, 1, -1, 10**30]),
    st.floats(allow_nan=False, allow_infinity=False), st.text(max_size=6),
    st.sampled_from(["oops", "\ud800", "\udfff", "S1", "apply", "tie", "+", "", "operator"]),
)
JSON_VALUES = st.recursive(
    JSON_LEAVES,
    lambda inner: st.lists(inner, max_size=5) | st.dictionaries(
        st.sampled_from(["id", "rule", "kind", "d", "x"]) | st.text(max_size=4), inner, max_size=4),
    max_leaves=12,
)
SPECIAL_LINES = [b"", b"{}", b"[]", b"null", b'{"kind": 3}', b'{"kind": "phase"}',
                 b'{"kind": "phase", "d": 1, "phase": "apply", "adds": "oops"}',
                 b'{"kind": "decision", "d": NaN, "level": 0}', b'{"kind": "x", "v": 1e999}',
                 b"[" * 5000 + b"]" * 5000, b'{"kind": "footer", "decisions": "many"}',
                 b"\xff\xfe\x00garbage", b'{"kind": "decision", "d": 2, "level": 99999999}']


def _paths(value: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Every path to a value inside a record (keys and indices)."""
    found = [prefix] if prefix else []
    if isinstance(value, dict):
        for k, v in value.items():
            found += _paths(v, prefix + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            found += _paths(v, prefix + (i,))
    return found


def _replace(record: Any, path: tuple[Any, ...], value: Any, delete: bool) -> None:
    target = record
    for key in path[:-1]:
        target = target[key]
    if delete:
        del target[path[-1]]
    else:
        target[path[-1]] = value


@st.composite
def broken_traces(draw: st.DrawFn, lines: list[bytes]) -> bytes:
    lines = list(lines)
    for _ in range(draw(st.integers(1, 3))):
        operation = draw(st.integers(0, 9))
        # the header (line 0) only now and then: most of a trace is its other records
        index = draw(st.integers(0, len(lines) - 1) if draw(st.integers(0, 9)) == 0
                     else st.integers(min(1, len(lines) - 1), len(lines) - 1))
        if operation <= 5:  # change a value inside one record
            try:
                record = json.loads(lines[index])
            except ValueError:
                continue
            paths = _paths(record)
            if paths:
                path = draw(st.sampled_from(paths))
                delete = draw(st.integers(0, 4)) == 0
                _replace(record, path, draw(JSON_VALUES), delete)
                lines[index] = json.dumps(record).encode("utf-8")
        elif operation == 6:
            del lines[index]
            if not lines:
                lines = [b"{}"]
        elif operation == 7:
            lines.insert(index, lines[draw(st.integers(0, len(lines) - 1))])
        elif operation == 8:
            lines.insert(index, draw(st.sampled_from(SPECIAL_LINES)))
        else:
            other = draw(st.integers(0, len(lines) - 1))
            lines[index], lines[other] = lines[other], lines[index]
    text = b"\n".join(lines) + b"\n"
    if draw(st.integers(0, 9)) == 0:
        text = text[: draw(st.integers(0, len(text)))]
    return text


SUBCOMMANDS = [
    ["show", "--level", "5"], ["show", "--level", "4", "--id", "S1"],
    ["show", "--rule", "water-jug*apply*fill", "--level", "3"], ["show", "--decisions", "2..4"],
    ["wm"], ["wm", "--at", "3", "--internal"], ["why", "--wme", "(S1 ^steps 2)", "--depth", "3"],
    ["why", "--wme", "25"], ["why", "--rule", "water-jug*propose*announce", "--at", "3"],
    ["stats"], ["stats", "--json"], ["diff", "{original}", "--exit-code"], ["html", "--out", "{out}"],
]


@pytest.mark.parametrize("sub", SUBCOMMANDS, ids=" ".join)
def test_broken_traces_keep_the_contract(pool: Pool, sub: list[str]) -> None:
    original = pool.files["wj5.jsonl"]
    lines = original.read_bytes().splitlines()

    @settings(max_examples=examples(40), deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(broken_traces(lines))
    def check(data: bytes) -> None:
        folder = pool.outputs()
        trace = folder / "t.jsonl"
        trace.write_bytes(data)
        (folder / "wj.soar").write_bytes(pool.files["wj.soar"].read_bytes())  # for `why`
        args = [a.replace("{original}", str(original)).replace("{out}", str(folder / "t.html"))
                for a in sub]
        run_checked(pool, ["trace", args[0], str(trace), *args[1:]])

    check()


@pytest.mark.parametrize("line", SPECIAL_LINES, ids=lambda b: b[:30].decode("latin-1"))
@pytest.mark.parametrize("command", ["show", "wm", "stats", "html", "diff"])
def test_each_reported_kind_of_bad_record(pool: Pool, line: bytes, command: str) -> None:
    lines = pool.files["wj5.jsonl"].read_bytes().splitlines()
    folder = pool.outputs()
    trace = folder / "t.jsonl"
    trace.write_bytes(b"\n".join(lines[:5] + [line] + lines[5:]) + b"\n")
    extra = [str(pool.files["wj5.jsonl"])] if command == "diff" else []
    outcome = run_checked(pool, ["trace", command, str(trace), *extra])
    if line.strip() and line not in (b"{}",):  # every other special line is refused at its line
        assert outcome.status == 1 and f"{trace}:6" in outcome.err, outcome


def test_the_reader_and_the_json_schema_agree(pool: Pool) -> None:
    """Records the reader accepts follow docs/trace-format.schema.json, and the reader
    refuses the mutants the schema refuses (where the schema is as strict as the reader)."""
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))
    validator = jsonschema.validators.validator_for(schema)(schema)
    lines = pool.files["wj5.jsonl"].read_bytes().splitlines()
    for name in ("wj5.jsonl", "wj3.jsonl", "wj1.jsonl"):
        trace = Trace(pool.files[name])
        for record in trace.records():
            validator.validate(record)

    @settings(max_examples=examples(200), deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow])
    @given(st.integers(1, len(lines) - 1), st.data())
    def check(index: int, data: st.DataObject) -> None:
        record = json.loads(lines[index])
        path = data.draw(st.sampled_from(_paths(record)))
        _replace(record, path, data.draw(JSON_LEAVES), data.draw(st.booleans()))
        try:
            check_record(record)
        except ValueError:
            return  # the reader refuses: stricter than or as strict as the schema
        if record.get("kind") in ("phase", "decision", "footer", "schema"):
            validator.validate(record)  # accepted by the reader => valid

    check()


def test_the_fast_check_of_phase_records_agrees_with_the_full_one(pool: Pool) -> None:
    phases = [json.loads(line) for line in pool.files["wj5.jsonl"].read_bytes().splitlines()[1:]
              if b'"kind":"phase"' in line]
    phases = [p for p in phases if p.get("firings") or p.get("adds")]

    @settings(max_examples=examples(150), deadline=None, derandomize=True)
    @given(st.sampled_from(range(len(phases))), st.data())
    def check(index: int, data: st.DataObject) -> None:
        record = json.loads(json.dumps(phases[index]))
        for _ in range(data.draw(st.integers(0, 2))):
            path = data.draw(st.sampled_from(_paths(record)))
            _replace(record, path, data.draw(JSON_VALUES), data.draw(st.booleans()))
        try:
            check_record(record, fast=False)
            full = True
        except ValueError:
            full = False
        if record.get("kind") == "phase":
            assert phase_ok(record) == full, record

    check()
