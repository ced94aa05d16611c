"""``adapt rules run`` / ``adapt rules check``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from adapt.cli import main

ROOT = Path(__file__).resolve().parents[1]
GOOD = "sp {hello (state <s> ^superstate nil) --> (write |hello| (crlf)) (halt)}\n"


def test_run_human_summary(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "a.soar"
    f.write_text(GOOD)
    assert main(["rules", "run", str(f)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("hello\n") and "-- halt: 0 decisions" in out


def test_run_json_keys(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "a.soar"
    f.write_text(GOOD)
    assert main(["rules", "run", str(f), "--json", "--matcher", "naive", "--seed", "3"]) == 0
    report = json.loads(capsys.readouterr().out)
    for key in ("halted", "stop_reason", "decisions", "output", "operators", "impasses",
                "production_firings", "wm_size_final"):
        assert key in report
    assert report["output"] == "hello\n" and report["halted"] is True


def test_water_jug_example_runs(capsys: pytest.CaptureFixture[str]) -> None:
    path = ROOT / "rules" / "examples" / "water-jug.soar"
    if not path.exists():
        pytest.skip("rules/examples/water-jug.soar not written yet")
    assert main(["rules", "run", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["halted"] is True


def test_run_with_trace_and_bound(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "a.soar"
    f.write_text("sp {p (state <s> ^superstate nil) --> (<s> ^operator <o> +) (<o> ^name x)}\n")
    trace = tmp_path / "t.jsonl"
    assert main(["rules", "run", str(f), "--json", "--max-decisions", "3",
                 "--trace", str(trace), "--trace-level", "2"]) == 3
    report = json.loads(capsys.readouterr().out)
    assert report["stop_reason"] == "max-decisions" and report["decisions"] == 3
    assert report["exit_status"] == 3
    assert json.loads(trace.read_text().splitlines()[-1])["kind"] == "footer"


def test_bad_rules_positioned_error_no_traceback(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.soar"
    bad.write_text("sp {broken (state <s> ^a 1)\n  (<s> ^b 2)\n")
    good = tmp_path / "good.soar"
    good.write_text(GOOD)
    assert main(["rules", "check", str(good), str(bad)]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:" in err and "Traceback" not in err
    assert main(["rules", "run", str(bad)]) == 1
    assert "Traceback" not in capsys.readouterr().err
    assert main(["rules", "check", str(good)]) == 0


def test_replaced_production_warns_once(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "dup.soar"
    f.write_text(GOOD + GOOD)
    assert main(["rules", "check", str(f)]) == 0
    captured = capsys.readouterr()
    assert captured.err.count("warning") == 1 and f"{f}:1:1: warning:" not in captured.err
    assert ":2:1: warning: production 'hello' replaces" in captured.err
    assert captured.out == f"{f}: 1 production ok\n"


@pytest.mark.parametrize("where", ["t.txt", ".", "a.soar"])
def test_trace_path_that_cannot_be_written(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                           where: str) -> None:
    f = tmp_path / "a.soar"
    f.write_text(GOOD)
    target = tmp_path / where
    assert main(["rules", "run", str(f), "--trace", str(target)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("adapt: error: ") and str(target) in err and "Traceback" not in err


def test_bad_rule_file_keeps_an_existing_trace(tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.soar"
    bad.write_text("sp {broken (state <s> ^a 1)\n")
    trace = tmp_path / "t.jsonl"
    trace.write_text('{"kind": "header"}\n')
    assert main(["rules", "run", str(bad), "--trace", str(trace)]) == 1
    assert trace.read_text() == '{"kind": "header"}\n'


def test_rule_files_without_productions_warn(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    empty = tmp_path / "empty.soar"
    empty.write_text("# only a comment\n")
    assert main(["rules", "run", str(empty), "--max-decisions", "2", "--json"]) == 3
    captured = capsys.readouterr()
    assert "no productions" in captured.err
    report = json.loads(captured.out)
    assert report["impasses"] and report["impasses"][0][2:] == ["no-change", "state"]


def test_rule_files_with_productions_do_not_warn(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    rules = tmp_path / "one.soar"
    rules.write_text("sp {hello (state <s> ^superstate nil) --> (write |hi|) (halt)}\n")
    assert main(["rules", "run", str(rules)]) == 0
    assert "no productions" not in capsys.readouterr().err


def test_a_byte_order_mark_is_accepted(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "bom.soar"
    f.write_bytes(b"\xef\xbb\xbf" + GOOD.encode("utf-8"))
    assert main(["rules", "check", str(f)]) == 0
    assert main(["rules", "run", str(f)]) == 0
    assert capsys.readouterr().out.startswith(f"{f}: 1 production ok\nhello\n")


def test_check_verbose_prints_the_join_order_following_source(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "rules.soar").write_text(
        "sp {pair*done (state <s> ^holds <h1> <h2>) (<h1> ^on <p>) (<h2> ^on <p>)\n"
        "  (<h1> ^disk 1) (<h2> ^disk 2) --> (halt)}\n")
    top = tmp_path / "agent.soar"
    top.write_text("multi-attributes holds 8\npushd sub\nsource rules.soar\npopd\n")
    assert main(["rules", "check", str(top), "--verbose"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == f"{top}: 1 production ok"
    assert out[1] == "  sp pair*done  (reordered)"
    # each holding is narrowed to its disk before the next one is joined; of
    # the two tied ^holds, the last written first (Soar's order, checked
    # against the kernel's print --internal)
    assert [line.split(None, 1)[1] for line in out[2:]] == [
        "(state <s> ^holds <h2>)", "(<h2> ^disk 2)", "(<h2> ^on <p>)",
        "(state <s> ^holds <h1>)", "(<h1> ^disk 1)", "(<h1> ^on <p>)"]
    assert main(["rules", "check", str(top)]) == 0
    assert capsys.readouterr().out == f"{top}: 1 production ok\n"
