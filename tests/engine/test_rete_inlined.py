"""The Rete's join activations keep inlined copies of their helpers (the hot path, marked in
``adapt/engine/rete/join.py``): the memories and the token registry they build are what the
helpers would have built."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

from adapt.engine.rete.join import JoinNode
from adapt.engine.rete.network import Rete


def _bench() -> ModuleType:
    """``bench/rete.py``, loaded under a private name."""
    path = Path(__file__).resolve().parents[2] / "bench" / "rete.py"
    spec = importlib.util.spec_from_file_location("_bench_rete_inlined", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _joins(rete: Rete) -> list[JoinNode]:
    found: list[JoinNode] = []
    for group in rete._alpha.values():
        for memory in group.memories:
            found.extend(n for n in memory.successors if type(n) is JoinNode)
    return found


def test_the_inlined_keys_index_and_registry_agree_with_the_helpers() -> None:
    productions, wmes = _bench().value_join(60)
    rete = Rete()
    for p in productions:
        rete.add_production(p)
    # WMEs in, half of them before the production's tokens exist on each side, so both
    # activations (left_add and right_join) make tokens
    for w in wmes:
        rete.add_wme(w)
    added, _ = rete.take_changes()
    assert len(added) == 60
    joins = _joins(rete)
    assert joins
    registry = rete.state.tokens_by_wme
    tokens = 0
    for node in joins:
        for key, bucket in node.left.items():
            for token in (bucket if isinstance(bucket, dict) else (bucket,)):
                assert node.left_key(token.wmes) == key
        for key, bucket in node.right.items():
            for wme in (bucket.values() if isinstance(bucket, dict) else (bucket,)):
                assert node.right_key(wme) == key
    for timetag, entry in registry.items():
        for token in (entry if isinstance(entry, dict) else (entry,)):
            if type(token.node) is JoinNode:
                tokens += 1
                assert token.wmes[-1][4] == timetag
    assert tokens > 0
