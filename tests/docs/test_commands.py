"""Every command shown in ``README.md`` and ``docs/*.md`` runs as written.

Each page's commands run in order, in one scratch repository root per page
(:class:`docs.shell.DocShell`), so that a command may use what an earlier one
wrote (``--trace wj.jsonl``, then ``trace show wj.jsonl``).  Each must exit 0,
and where a ``console`` block shows the output under a command, every line
shown must appear in what it prints, in order (lines with ``...`` and the
run's timing excepted).  The commands left out are listed in :data:`SKIPPED`,
each with its reason; a skip that no longer matches any command fails, so the
list stays true.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .shell import ROOT, Command, DocShell, code_blocks, commands

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

#: Commands not run here: (page, start of the command) -> why.
SKIPPED: dict[tuple[str, str], str] = {
    ("README.md", "python -m pip install"): "installs the package (network, minutes); the tests run installed",
    ("README.md", "(command -v chromium"): "installs Chromium and runs the whole suite, which holds this test",
    ("getting-started.md", "python -m pip install"): "installs the package (network, minutes)",
    ("getting-started.md", "python -m pytest"): "the whole suite, which holds this test",
    ("getting-started.md", "python bench/"): "benchmarks: 5 s to 15 minutes each, run by hand "
                                             "(docs/performance.md)",
    ("getting-started.md", "python -m adapt run scenarios/bouncing-ball.yaml  "): "the main job, "
        "a whole 640x480 run (about 10 s); tests/runner/test_cli.py runs it for a few frames and "
        "the next commands here run it for 30",
    ("getting-started.md", "python -m adapt run scenarios/bouncing-ball.yaml --set"): "a whole "
        "640x480 run; the --set itself is checked by tests/runner/test_cli.py",
    ("getting-started.md", "python -m adapt sync"): "about 9 s of camera loop; docs/mmd.md's sync of a "
                                                    "turned camera, run by tests/vision/test_docs.py, "
                                                    "is the same loop",
    ("performance.md", "python bench/"): "benchmarks: 5 s to 15 minutes each, run by hand",
    ("reality.md", "python bench/make_video_sequence.py"): "rewrites the shipped video sequence in "
                                                           "scenarios/video",
    ("runner.md", "adapt run SCENARIO.yaml"): "a synopsis with placeholders, not a command",
    ("runner.md", "adapt check SCENARIO.yaml"): "a synopsis with placeholders, not a command",
    ("mmd.md", ""): "its commands are run, with their outputs checked, by tests/vision/test_docs.py",
    ("sweeps.md", "adapt sweep SCENARIO.yaml"): "a synopsis with placeholders, not a command",
    ("sweeps.md", "pip install"): "installs an extra (network)",
    ("sweeps.md", "adapt sweep scenarios/"): "sweeps of 50 to 2,400 whole runs (minutes to hours); "
                                             "tests/sweep runs small sweeps of the same command",
    ("sweeps.md", "dask "): "starts a Dask cluster on other machines",
    ("sweeps.md", "srun "): "starts Dask workers under Slurm",
    ("mirror.md", "python bench/"): "benchmarks: an hour of PyBullet realities; "
                                    "tests/reality/test_foreign_bench.py checks its throws",
    ("extending.md", "python examples/goalkeeper/run.py"): "50 whole runs (about 10 minutes); "
        "tests/examples runs the same script for one throw",
    ("extending.md", "python examples/two_balls/run.py"): "20 whole runs (about 10 minutes); "
        "tests/examples runs the same script for one seed",
    ("mirror.md", "adapt run scenarios/"): "whole 640x480 runs, 15-40 s each; tests/mirror runs the "
                                           "same scenarios at 320x240 and tests/runner/test_cli.py "
                                           "runs the main job's command for a few frames",
}


def _skip_reason(command: Command) -> str | None:
    for (page, start), reason in SKIPPED.items():
        if command.page == page and command.text.startswith(start):
            return reason
    return None


def page_commands(page: Path) -> list[Command]:
    return [c for block in code_blocks(page) for c in commands(page, block)]


def _shown_lines_appear(shown: tuple[str, ...], printed: str) -> str | None:
    """The first shown line that is not printed (in order), or ``None``."""
    out = printed.splitlines()
    at = 0
    for line in shown:
        if not line.strip() or "..." in line or line.startswith("run time:"):
            continue
        while at < len(out) and out[at].rstrip() != line.rstrip():
            at += 1
        if at == len(out):
            return line
        at += 1
    return None


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_the_commands_of_a_page_run_as_written(page: Path, tmp_path: Path) -> None:
    shell = DocShell(tmp_path)
    for command in page_commands(page):
        if _skip_reason(command) is not None:
            continue
        proc = shell.run(command.text)
        where = f"{command.page}:{command.line}: {command.text}"
        assert proc.returncode == 0, (where, proc.stdout[-2000:], proc.stderr[-2000:])
        assert "Traceback" not in proc.stderr, (where, proc.stderr)
        missing = _shown_lines_appear(command.shown, proc.stdout)
        assert missing is None, (where, f"shown but not printed: {missing!r}", proc.stdout)


def test_every_skip_still_names_a_command() -> None:
    used = {(c.page, start) for page in PAGES for c in page_commands(page)
            for (p, start) in SKIPPED if c.page == p and c.text.startswith(start)}
    assert used == set(SKIPPED), set(SKIPPED) - used


def test_the_pages_show_commands() -> None:
    counted = {page.name: len(page_commands(page)) for page in PAGES}
    assert counted["README.md"] >= 1 and counted["getting-started.md"] >= 10
    assert counted["traces.md"] >= 8 and counted["cli.md"] >= 5
