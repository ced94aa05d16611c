"""``docs/cli.md`` and ``adapt.cli.exits`` say the same: the status table and each command's statuses."""

from __future__ import annotations

import re

from adapt.cli import build_parser
from adapt.cli.exits import COMMAND_STATUSES, Exit

from .shell import ROOT

PAGE = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")


def _rows(heading: str) -> list[list[str]]:
    section = PAGE.split(heading, 1)[1].split("\n## ", 1)[0]
    rows = [[cell.strip() for cell in line.strip().strip("|").split("|")]
            for line in section.splitlines() if line.startswith("|")]
    return rows[2:]  # past the header and the rule


def test_the_status_table_is_the_exit_enum() -> None:
    table = {int(row[0]): row[1].strip("`") for row in _rows("## Exit statuses")}
    assert table == {int(e): e.name for e in Exit}


def test_each_command_lists_its_statuses() -> None:
    listed: dict[str, set[int]] = {}
    for row in _rows("## The commands"):
        words = re.match(r"`adapt ((?:[a-z]+ ?)+)", row[0])
        assert words, row
        listed[words.group(1).strip()] = {int(s) for s in row[3].split(",")}
    expected = {name: {int(s) for s in statuses} - {int(Exit.INTERRUPTED)}
                for name, statuses in COMMAND_STATUSES.items()}
    assert {k: v - {int(Exit.INTERRUPTED)} for k, v in listed.items()} == expected


def test_every_command_of_the_parser_is_on_the_page() -> None:
    import argparse

    def leaves(parser: argparse.ArgumentParser, prefix: str = "") -> set[str]:
        found: set[str] = set()
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    full = f"{prefix} {name}".strip()
                    found |= leaves(sub, full) or {full}
        return found

    assert leaves(build_parser()) == set(COMMAND_STATUSES)
