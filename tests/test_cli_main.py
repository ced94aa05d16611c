"""The command line's last resorts: usage errors, internal errors, undecodable file names,
a closed pipe."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from adapt.cli import main
from adapt.cli.exits import Exit

ROOT = Path(__file__).resolve().parents[1]
WATER_JUG = ROOT / "rules" / "examples" / "water-jug.soar"


def test_usage_errors_say_adapt_error_and_the_subcommand(capsys) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["trace", "show", "t.jsonl", "--level", "9"])
    assert exc.value.code == Exit.USAGE
    err = capsys.readouterr().err
    assert err.startswith("usage: adapt trace show")
    assert "adapt: error: trace show: argument --level: '9': the level is 1..5" in err


@pytest.fixture()
def broken_stats(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> list[str]:
    import adapt.traceview.stats

    def fail(*_args: object, **_kw: object) -> None:
        raise RuntimeError("a bug\nsecond line")

    monkeypatch.setattr(adapt.traceview.stats, "compute_stats", fail)
    trace = tmp_path / "t.jsonl"
    assert main(["rules", "run", str(WATER_JUG), "--trace", str(trace), "--json"]) == 0
    return ["trace", "stats", str(trace)]


def test_an_internal_error_is_one_line_and_status_70(broken_stats, capsys, monkeypatch) -> None:
    monkeypatch.delenv("ADAPT_DEBUG", raising=False)
    capsys.readouterr()
    assert main(broken_stats) == Exit.INTERNAL == 70
    err = capsys.readouterr().err
    assert err.startswith("adapt: internal error: RuntimeError: a bug (a bug in adapt")
    assert "please report it" in err and "ADAPT_DEBUG=1" in err
    assert "Traceback" not in err and len(err.splitlines()) == 1


def test_adapt_debug_shows_the_traceback(broken_stats, capsys, monkeypatch) -> None:
    monkeypatch.setenv("ADAPT_DEBUG", "1")
    capsys.readouterr()
    assert main(broken_stats) == Exit.INTERNAL
    err = capsys.readouterr().err
    assert "Traceback (most recent call last)" in err and "RuntimeError: a bug" in err
    assert err.splitlines()[-1].startswith("adapt: internal error: ")


def _adapt(*args: str | bytes, cwd: Path, **env: str) -> subprocess.CompletedProcess[bytes]:
    return subprocess.run([sys.executable, "-m", "adapt", *args], cwd=cwd, capture_output=True,
                          env={**os.environ, "PYTHONPATH": str(ROOT), **env}, timeout=120)


@pytest.mark.skipif(sys.platform != "linux", reason="file names as bytes")
def test_file_names_that_are_not_utf8(tmp_path: Path) -> None:
    """A file name's bytes come back as they were, on a strict UTF-8 standard output too."""
    rules = os.fsencode(tmp_path) + b"/\xff.soar"
    with open(rules, "wb") as f:
        f.write(WATER_JUG.read_bytes())
    trace = os.fsencode(tmp_path) + b"/\xff.jsonl"
    strict = {"PYTHONIOENCODING": "utf-8:strict"}
    run = _adapt("rules", "run", rules, "--trace", trace, cwd=tmp_path, **strict)
    assert run.returncode == 0, run.stderr
    for command in (["stats"], ["html"], ["show", "--level", "5"]):
        done = _adapt("trace", command[0], trace, *command[1:], cwd=tmp_path, **strict)
        assert done.returncode == 0 and b"Traceback" not in done.stderr, done.stderr
    assert b"\xff.jsonl" in _adapt("trace", "stats", trace, cwd=tmp_path, **strict).stdout
    missing = _adapt("trace", "show", b"\xfe.jsonl", cwd=tmp_path, **strict)
    assert missing.returncode == 1 and missing.stderr.startswith(b"adapt: error: \\udcfe.jsonl")


COUNTER = """\
sp {propose*init (state <s> ^superstate nil -^count) --> (<s> ^operator <o> +) (<o> ^name init)}
sp {apply*init (state <s> ^operator.name init) --> (<s> ^count 0)}
sp {propose*tick (state <s> ^count <c>) --> (<s> ^operator <o> +) (<o> ^name tick)}
sp {apply*tick (state <s> ^operator.name tick ^count <c>) --> (<s> ^count <c> - (+ <c> 1))}
"""


def test_a_closed_pipe_ends_quietly(tmp_path: Path) -> None:
    rules = tmp_path / "r.soar"
    rules.write_text(COUNTER)
    trace = tmp_path / "t.jsonl"
    assert main(["rules", "run", str(rules), "--max-decisions", "2000", "--trace", str(trace),
                 "--json"]) == Exit.DECISION_LIMIT
    proc = subprocess.Popen([sys.executable, "-m", "adapt", "trace", "show", str(trace), "--level", "5"],
                            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, bufsize=0)
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.read(10)
    proc.stdout.close()
    err = proc.stderr.read()
    assert proc.wait(timeout=60) == 0 and err == b"", err


def test_version_says_which_engine_runs(capsys) -> None:  # type: ignore[no-untyped-def]
    from adapt import __version__
    from adapt.engine.compiled import engine_build

    with pytest.raises(SystemExit) as done:
        main(["--version"])
    assert done.value.code == 0
    assert capsys.readouterr().out == f"adapt {__version__}, engine: {engine_build()}\n"


BOUNCING = ROOT / "scenarios" / "bouncing-ball.yaml"


@pytest.mark.parametrize("argv, words", [
    (["run", str(BOUNCING), "--seed", "-1"], ("--seed", "an integer >= 0", "'-1'")),
    (["render", str(BOUNCING), "--out", "x.png", "--seed", "-1"], ("--seed", "an integer >= 0")),
    (["imagine", str(BOUNCING), "--horizon", "1", "--seed", "-1"], ("--seed",)),
    (["run", str(BOUNCING), "--out", ""], ("--out", "expected a folder name")),
    (["sweep", str(BOUNCING), "--out", " "], ("--out", "expected a folder name")),
], ids=["run-seed", "render-seed", "imagine-seed", "run-out", "sweep-out"])
def test_values_refused_before_any_work(argv: list[str], words: tuple[str, ...], tmp_path: Path,
                                        monkeypatch: pytest.MonkeyPatch, capsys) -> None:
    """Issue 21: ``--seed -1`` was an internal error (status 70), ``--out ''`` the default."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == Exit.USAGE
    err = capsys.readouterr().err
    assert all(w in err for w in words) and "internal error" not in err, err
    assert list(tmp_path.iterdir()) == []


def test_the_runner_refuses_a_negative_seed() -> None:
    from adapt.errors import RunError
    from adapt.runner import Runner
    from adapt.scenario import load_scenario

    with pytest.raises(RunError, match="the seed must be an integer >= 0, got -1"):
        Runner(load_scenario(BOUNCING), seed=-1)


def test_lines_to_both_streams_come_in_the_order_they_were_written(tmp_path: Path) -> None:
    # ``adapt rules run zero.soar 2>&1`` (docs/cli.md) printed the error before the run's
    # summary when Python buffered a piped standard output (PYTHONUNBUFFERED unset, as on a
    # fresh machine)
    rules = tmp_path / "zero.soar"
    rules.write_text("sp {a (state <s> ^superstate nil) --> (<s> ^x (/ 1 0)) (halt)}\n")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.run([sys.executable, "-m", "adapt", "rules", "run", str(rules)], cwd=tmp_path,
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env, timeout=120)
    lines = proc.stdout.decode().splitlines()
    assert proc.returncode == 6, lines
    assert lines[-2].startswith("-- halt:") and lines[-1].startswith("Error: attempt to divide"), lines
