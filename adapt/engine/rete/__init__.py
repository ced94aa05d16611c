"""The Rete matcher, one node kind per module.

=================  ==========================================================
``network``        :class:`Rete`: building, sharing, pruning; WME adds/removes
``alpha``          alpha memories, hashed on constant tests; relation tests
``build``          condition ordering and test placement
``token``          tokens and the token tree (emit, retract, delete)
``join``           join nodes, hashed on every equality test
``negative``       negated conditions
``ncc``            conjunctive negations (NCC node and partner)
``pnode``          production nodes: tokens become matches
``state``          per-network bookkeeping and pending match changes
=================  ==========================================================
"""

from __future__ import annotations

from adapt.engine.rete.network import Rete

__all__ = ["Rete"]
