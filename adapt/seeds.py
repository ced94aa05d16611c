"""One seed, independent random streams.

A run has one seed (``run.seed`` or ``--seed``).  Everything random in it
draws from its own stream, split from that seed with
:class:`numpy.random.SeedSequence`, so adding a draw to one part (the
synthetic reality's sensor noise, say) never changes another's (the agent's
tie-breaks, the prediction ensembles).  The same seed gives the same run.

Examples
--------
>>> a, b = Streams(7), Streams(7)
>>> a.generator("reality.noise").random() == b.generator("reality.noise").random()
True
>>> a.generator("reality.noise").random() == a.generator("ensemble").random()
False
>>> a.integer("agent") == Streams(7).integer("agent")
True
"""

from __future__ import annotations

import hashlib

import numpy as np

__all__ = ["Streams", "STREAMS"]

#: The streams a run uses, documented here so none is added by accident twice.
STREAMS = (
    "agent",              # the rule engine's indifferent-selection choices
    "reality.parameters",  # true physical parameters drawn from ranges, camera offsets
    "reality.events",     # throw times, positions and velocities
    "reality.noise",      # sensor noise, wheel slip
    "ensemble",           # prediction ensembles
    "schemas",            # anything random in perception
)


class Streams:
    """Named, independent random streams from one seed.

    A stream's name picks its child of the seed's ``SeedSequence`` (by a
    stable hash of the name), so streams do not depend on the order in which
    they are first asked for.
    """

    def __init__(self, seed: int | None) -> None:
        self.seed = 0 if seed is None else int(seed)
        if self.seed < 0:
            raise ValueError(f"a seed must be a non-negative integer, got {seed}")

    def sequence(self, name: str) -> np.random.SeedSequence:
        """The ``SeedSequence`` of stream ``name``."""
        key = int.from_bytes(hashlib.sha256(name.encode("utf-8")).digest()[:8], "little")
        return np.random.SeedSequence(entropy=self.seed, spawn_key=(key,))

    def generator(self, name: str) -> np.random.Generator:
        """A fresh generator for stream ``name`` (the same numbers every time it is asked for)."""
        return np.random.default_rng(self.sequence(name))

    def integer(self, name: str) -> int:
        """A 31-bit integer seed for libraries that take one (``random.Random``)."""
        return int(self.sequence(name).generate_state(1, np.uint32)[0] >> 1)
