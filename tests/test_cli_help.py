"""``--help`` of every subcommand: consistent option names and readable metavars."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pytest

from adapt.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[1]


def _subparsers(parser: argparse.ArgumentParser, prefix: str = "") -> dict[str, argparse.ArgumentParser]:
    found: dict[str, argparse.ArgumentParser] = {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                full = f"{prefix} {name}".strip()
                children = _subparsers(sub, full)
                found.update(children or {full: sub})
    return found


COMMANDS = _subparsers(build_parser())


def test_every_command_is_found() -> None:
    assert {"rules run", "rules check", "render", "imagine", "mmd", "sync", "trace show",
            "trace html"} <= set(COMMANDS)


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_options_have_help_and_no_shouted_dest_metavars(name: str) -> None:
    for action in COMMANDS[name]._actions:
        if not action.option_strings or action.nargs == 0 or action.dest == "help":
            continue
        assert action.help, f"{name} {action.option_strings[0]} has no help"
        if action.choices is None:
            # argparse's default metavar is the dest in capitals (MAX_ITER): say what it is
            assert action.metavar is not None, f"{name} {action.option_strings[0]} has no metavar"


@pytest.mark.parametrize("name", ["rules run", "render", "imagine"])
def test_seed_option_where_a_run_is_random(name: str) -> None:
    options = {o for a in COMMANDS[name]._actions for o in a.option_strings}
    assert "--seed" in options


def test_imagine_seed_is_reported(capsys: pytest.CaptureFixture[str]) -> None:
    scenario = str(ROOT / "scenarios" / "room.yaml")
    assert main(["imagine", scenario, "--horizon", "0.2", "--json", "--seed", "11"]) == 0
    assert json.loads(capsys.readouterr().out)["seed"] == 11
