"""``adapt trace ...`` on traces that break the format, and the queries a user trips on."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from adapt.cli import main

ROOT = Path(__file__).resolve().parents[1]
WATER_JUG = ROOT / "rules" / "examples" / "water-jug.soar"


@pytest.fixture(scope="module")
def wj(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("wj")
    trace = folder / "wj.jsonl"
    assert main(["rules", "run", str(WATER_JUG), "--trace", str(trace), "--json"]) == 0
    return trace


def _with_line(wj: Path, tmp_path: Path, index: int, line: str) -> Path:
    lines = wj.read_text().splitlines()
    lines[index] = line
    path = tmp_path / "bad.jsonl"
    path.write_text("\n".join(lines) + "\n")
    return path


def _run(capsys, *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return status, out, err


@pytest.mark.parametrize("command", [["show", "--level", "4"], ["wm"], ["diff", "{wj}"],
                                     ["html", "--out", "{tmp}/p.html"], ["stats"],
                                     ["why", "--wme", "30"]])
def test_adds_oops_is_an_error_at_its_line(wj: Path, tmp_path: Path, capsys, command) -> None:
    record = json.loads(wj.read_text().splitlines()[5])
    assert record["kind"] == "phase"
    record["adds"] = "oops"
    bad = _with_line(wj, tmp_path, 5, json.dumps(record))
    args = [a.replace("{wj}", str(wj)).replace("{tmp}", str(tmp_path)) for a in command[1:]]
    status, _, err = _run(capsys, "trace", command[0], str(bad), *args)
    assert status == 1
    assert err.startswith(f"adapt: error: {bad}:6: phase record: \"adds\" is 'oops'; expected a list")
    assert not (tmp_path / "p.html").exists()


def test_a_lone_surrogate_is_an_error_at_its_line(wj: Path, tmp_path: Path, capsys) -> None:
    record = json.loads(wj.read_text().splitlines()[5])
    record["writes"] = "\ud800"
    bad = _with_line(wj, tmp_path, 5, json.dumps(record))
    status, _, err = _run(capsys, "trace", "html", str(bad), "--out", str(tmp_path / "p.html"))
    assert status == 1 and f"{bad}:6: not a JSON record (a string holds a lone surrogate" in err


@pytest.mark.parametrize("line, message", [
    ('{"kind": "decision", "d": 2, "level": 0, "selected": {"id": "O1"}, "impasse": null}',
     '"selected"."id" is \'O1\'; expected an identifier'),
    ('{"kind": "phase", "d": -1, "phase": "apply"}', '"d" is -1; expected an integer >= 0'),
    ('{"kind": "phase", "d": 1, "phase": []}', '"phase" is []'),
    ('{"kind": "phase", "d": 1, "phase": "apply", "removes": null}', '"removes" is None'),
    ('{"kind": "decision", "d": 2, "level": 100000000, "selected": null, "impasse": null}',
     'a goal level, an integer from 0 to 10,000'),
    ('{"kind": "phase", "d": 1, "phase": "apply", "time_s": NaN}', "NaN is not a JSON number"),
    ('{"kind": "schema", "d": 1, "event": "e", "schema": "s", "data": ' + "[" * 100 + "]" * 100 + "}",
     "nests more than 64 levels deep"),
])
def test_records_that_break_the_schema(wj: Path, tmp_path: Path, capsys, line, message) -> None:
    bad = _with_line(wj, tmp_path, 5, line)
    status, _, err = _run(capsys, "trace", "show", str(bad))
    assert status == 1 and f"{bad}:6: " in err and message in err, err


def test_why_depth_is_bounded(wj: Path, capsys) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["trace", "why", str(wj), "--wme", "30", "--depth", "-5"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "adapt: error: trace why: argument --depth: '-5': expected a depth from 0 to 100" in err


def test_why_explains_each_wme_once(wj: Path, capsys) -> None:
    status, deep, _ = _run(capsys, "trace", "why", str(wj), "--wme", "57", "--depth", "100")
    assert status == 0 and len(deep.splitlines()) < 1000  # it was 876,332 lines at depth 20
    heads = [line.split(")")[0].strip() for line in deep.splitlines()
             if line.strip().startswith("(") and "explained at depth" not in line
             and "matched:" not in line]
    explained = [h for h in heads if heads.count(h) > 1 and f"{h})" in deep]
    assert "explained at depth" in deep and len(heads) > 10 and explained is not None


def test_wm_defaults_to_the_end_of_the_trace(wj: Path, capsys) -> None:
    status, out, _ = _run(capsys, "trace", "wm", str(wj))
    assert status == 0
    # 31, Soar's WM size there too (the states' ^epmem, ^smem, ^reward-link included)
    assert out.startswith("; working memory at the end of decision 8 (the end of the trace): 31 WMEs")
    _, at8, _ = _run(capsys, "trace", "wm", str(wj), "--at", "8")
    assert at8.splitlines()[1:] == out.splitlines()[1:]


@pytest.mark.parametrize("args, message", [
    (["--rule", "nosuch"], "rule nosuch never fired or retracted in"),
    (["--id", "Z99"], "matches --id Z99 at level 1"),
    (["--decisions", "20..30"], "has decision cycles 1..8; --decisions 20..30 selects none"),
])
def test_show_says_when_nothing_matched(wj: Path, capsys, args, message) -> None:
    status, out, err = _run(capsys, "trace", "show", str(wj), *args)
    assert status == 1 and out == "" and err.startswith("adapt: error: ") and message in err


def test_show_with_a_filter_that_matches(wj: Path, capsys) -> None:
    status, out, _ = _run(capsys, "trace", "show", str(wj), "--rule", "water-jug*apply*fill",
                          "--level", "3")
    assert status == 0 and "Firing water-jug*apply*fill" in out


def test_deep_identifier_chains_print_without_recursion(tmp_path: Path, capsys) -> None:
    chain = [[1, {"id": "S1"}, "next", {"id": "N1"}, False]]
    chain += [[i + 1, {"id": f"N{i}"}, "next", {"id": f"N{i + 1}"}, False] for i in range(1, 1500)]
    records = [
        {"kind": "header", "format": "adapt-trace", "version": 1, "files": [], "level": 4},
        {"kind": "phase", "d": 0, "phase": "input", "adds": chain, "removes": []},
        {"kind": "decision", "d": 1, "level": 0, "selected": None, "impasse": None},
    ]
    trace = tmp_path / "chain.jsonl"
    trace.write_text("".join(json.dumps(r) + "\n" for r in records))
    status, out, _ = _run(capsys, "trace", "wm", str(trace), "--depth", "100000")
    assert status == 0 and len(out.splitlines()) == 1501
    assert out.splitlines()[-1].strip() == "(N1499 ^next N1500)"
