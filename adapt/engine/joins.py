"""The order in which each production of a rule file is joined (``adapt rules check --verbose``).

:func:`join_orders` gives, for every production of a parsed rule file, the
indexes of its conditions in the order they are evaluated: the positive ones
in the Rete's join order (:func:`adapt.engine.reorder.join_order`, with the
``multi-attributes`` hints in force where the production is loaded and ties
broken by the constants' order in Soar's symbol table, as in Soar), each
negation after what it tests.

Examples
--------
>>> from adapt.engine.parse import parse_rules
>>> rules = parse_rules("sp {p (state <s> ^a <x>) (<y> ^e 1) (<x> ^b <y>) -(<s> ^c <y>) "
...                     "--> (<s> ^d 1)}")
>>> [(p.name, order) for p, order in join_orders(rules)]  # (<y> ^e 1) once <y> is bound
[('p', [0, 2, 3, 1])]
"""

from __future__ import annotations

from typing import Sequence

from adapt.engine.conditions import evaluation_order
from adapt.engine.parse import RuleFile
from adapt.engine.production import Production
from adapt.engine.reorder import ConstantOrder, join_order

__all__ = ["join_orders"]


def join_orders(rules: RuleFile | Sequence[RuleFile]) -> list[tuple[Production, list[int]]]:
    """Each production with its conditions' indexes in evaluation order (see the module
    docstring); of several rule files, loaded in that order into one agent (the hints and
    the symbol table go on from one file to the next)."""
    hints: dict[str, int] = {}
    constants = ConstantOrder()
    out: list[tuple[Production, list[int]]] = []
    for rule_file in [rules] if isinstance(rules, RuleFile) else rules:
        settings = list(rule_file.settings)
        k = 0
        for i, p in enumerate(rule_file.productions):
            while k < len(settings) and settings[k][0] <= i:
                setting = settings[k][1]
                if setting.kind == "multi-attributes" and setting.name is not None:
                    hints[setting.name] = int(setting.value)  # type: ignore[arg-type]
                    constants.add(setting.name)
                elif setting.kind == "symbols":
                    constants.add(str(setting.value))
                k += 1
            conds = p.conditions
            constants.add_production(p)
            out.append((p, evaluation_order(conds, (), join_order(conds, (), hints, constants))))
    return out
