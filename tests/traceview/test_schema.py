"""Every record of real and generated traces follows ``docs/trace-format.schema.json``.

A tiny validator of the schema keywords the file uses (type, const, enum,
required, properties, additionalProperties, items, prefixItems, min/maxItems,
minimum/maximum, anyOf, oneOf, $ref); ``jsonschema`` is used as well when it
is installed.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from adapt.traceview.reader import Trace

SCHEMA = json.loads((Path(__file__).resolve().parents[2] / "docs" / "trace-format.schema.json")
                    .read_text(encoding="utf-8"))

TYPES = {"object": dict, "array": list, "string": str, "boolean": bool, "null": type(None)}


def _type_ok(value: Any, name: str) -> bool:
    if name == "integer":
        return isinstance(value, int) and not isinstance(value, bool)
    if name == "number":
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    return isinstance(value, TYPES[name])


def errors(value: Any, schema: dict[str, Any], path: str = "$") -> list[str]:
    if "$ref" in schema:
        return errors(value, SCHEMA["$defs"][schema["$ref"].rsplit("/", 1)[1]], path)
    out: list[str] = []
    if "type" in schema:
        names = schema["type"] if isinstance(schema["type"], list) else [schema["type"]]
        if not any(_type_ok(value, n) for n in names):
            return [f"{path}: {value!r} is not {schema['type']}"]
    if "const" in schema and value != schema["const"]:
        out.append(f"{path}: {value!r} != {schema['const']!r}")
    if "enum" in schema and value not in schema["enum"]:
        out.append(f"{path}: {value!r} not in {schema['enum']}")
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if "minimum" in schema and value < schema["minimum"]:
            out.append(f"{path}: {value} < {schema['minimum']}")
        if "maximum" in schema and value > schema["maximum"]:
            out.append(f"{path}: {value} > {schema['maximum']}")
    if isinstance(value, dict):
        out += [f"{path}: missing {k!r}" for k in schema.get("required", ()) if k not in value]
        props = schema.get("properties", {})
        for key, item in value.items():
            if key in props:
                out += errors(item, props[key], f"{path}.{key}")
            elif isinstance(schema.get("additionalProperties"), dict):
                out += errors(item, schema["additionalProperties"], f"{path}.{key}")
    if isinstance(value, list):
        if len(value) < schema.get("minItems", 0) or len(value) > schema.get("maxItems", 1 << 30):
            out.append(f"{path}: {len(value)} items")
        prefix = schema.get("prefixItems", [])
        for i, item in enumerate(value):
            sub = prefix[i] if i < len(prefix) else schema.get("items")
            if isinstance(sub, dict):
                out += errors(item, sub, f"{path}[{i}]")
    if "anyOf" in schema and all(errors(value, s, path) for s in schema["anyOf"]):
        out.append(f"{path}: matches none of anyOf")
    if "oneOf" in schema:
        ok = sum(not errors(value, s, path) for s in schema["oneOf"])
        if ok != 1:
            out.append(f"{path}: matches {ok} of oneOf")
    return out


def all_records(path: Path) -> list[dict[str, Any]]:
    trace = Trace(path)
    return [trace.header.raw, *trace.records()]


def check(path: Path) -> None:
    for record in all_records(path):
        assert errors(record, SCHEMA) == [], record
    try:
        import jsonschema
    except ImportError:
        return
    validator = jsonschema.Draft202012Validator(SCHEMA)
    for record in all_records(path):
        validator.validate(record)


def test_the_validator_catches_mistakes() -> None:
    assert errors({"kind": "phase", "d": -1, "phase": "apply"}, SCHEMA)
    assert errors({"kind": "decision", "d": 3, "level": 0, "selected": None}, SCHEMA)
    assert errors({"kind": "phase", "d": 1, "phase": "apply",
                   "adds": [[1, {"id": "S1"}, "x", 1]]}, SCHEMA)
    assert not errors({"kind": "footer", "decisions": 3}, SCHEMA)


@pytest.mark.parametrize("level", [1, 3, 5])
def test_generated_traces(counter_trace, level: int) -> None:
    check(counter_trace(20, level=level, tie_every=7, schema_every=5, frames=True))


@pytest.mark.parametrize("example", ["water-jug.soar", "blocks-world.soar"])
def test_engine_traces(tmp_path: Path, example: str) -> None:
    engine = pytest.importorskip("adapt.engine")
    rules = Path(__file__).resolve().parents[2] / "rules" / "examples" / example
    if not rules.exists():
        pytest.skip(f"{rules} is not written yet")
    agent = engine.Agent(trace=str(tmp_path / "run.jsonl"), trace_level=5, seed=1)
    agent.load_file(rules)
    agent.run(max_decisions=60)
    agent.close()
    check(tmp_path / "run.jsonl")


def test_runner_traces(tmp_path: Path) -> None:
    """A scenario run's trace: schema events, frames, the network and the summary too."""
    from adapt.runner import Runner
    from adapt.scenario import load_scenario

    root = Path(__file__).resolve().parents[2]
    scenario = load_scenario(root / "scenarios" / "unexpected-object.yaml",
                             overrides=("run.duration=0.3", "outputs.video=false",
                                        "outputs.figures=false", "outputs.report=false"))
    Runner(scenario, out=tmp_path / "run").run()
    path = tmp_path / "run" / "trace.jsonl"
    kinds = [r["kind"] for r in all_records(path)]
    assert {"schema", "frame", "network", "summary"} <= set(kinds)
    assert kinds[-1] == "footer" and kinds[-2] == "summary"
    check(path)
