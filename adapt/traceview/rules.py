"""The rule files a traced run loaded, found again and parsed.

A trace header names the rule files as the run was given them (usually
relative to the directory the run started in).  :func:`find_rule_file`
looks for each relative to the current directory, then to the trace's
directory and its parents.
"""

from __future__ import annotations

import os
from pathlib import Path

from adapt.engine.joins import join_orders
from adapt.engine.parse import RuleFile, load_rule_file
from adapt.engine.production import Production
from adapt.errors import TraceError
from adapt.traceview.reader import Trace

__all__ = ["find_rule_file", "load_rule_files", "load_productions", "load_join_orders"]


def find_rule_file(name: str, trace_path: str) -> Path:
    """Where the rule file ``name`` from a trace header is now.

    Raises
    ------
    adapt.errors.TraceError
        If it is found nowhere.
    """
    given = Path(name)
    if given.is_file():  # absolute, or relative to the current directory: as the run named it
        return given
    if not given.is_absolute():
        for place in Path(os.path.abspath(trace_path)).parents:
            if (place / given).is_file():
                return place / given
    raise TraceError(
        f"rule file {name} (named in the header of {trace_path}) was not found in the current "
        f"directory or beside the trace; give the rule files with --rules"
    )


def load_rule_files(trace: Trace, files: list[str] | None = None) -> list[RuleFile]:
    """The rule files ``files`` (default: the trace header's), parsed, in the order the run
    loaded them."""
    paths = [Path(f) for f in files] if files else [
        find_rule_file(f, trace.path) for f in trace.header.files
    ]
    return [load_rule_file(path) for path in paths]


def load_productions(trace: Trace, files: list[str] | None = None) -> dict[str, Production]:
    """The productions of ``files`` (default: the trace header's), by name.

    A later file's production replaces an earlier one of the same name, as
    when the run loaded them in order.
    """
    return _by_name(load_rule_files(trace, files))


def _by_name(rule_files: list[RuleFile]) -> dict[str, Production]:
    """The productions of ``rule_files`` by name, a later one replacing an earlier."""
    return {p.name: p for rule_file in rule_files for p in rule_file.productions}


def load_join_orders(trace: Trace, files: list[str] | None = None
                     ) -> tuple[dict[str, Production], dict[str, list[int]]]:
    """The productions of ``files`` (default: the trace header's) by name, and each one's
    conditions' evaluation order as the run's matchers loaded the files
    (:func:`adapt.engine.joins.join_orders`: the ``multi-attributes`` hints in force and the
    symbol table's order of constants breaking the last ties)."""
    rule_files = load_rule_files(trace, files)
    return _by_name(rule_files), {p.name: order for p, order in join_orders(rule_files)}
