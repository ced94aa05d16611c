"""Soar's random numbers: the same Mersenne Twister stream, drawn the same way.

Soar draws every random number from one Mersenne Twister (MT19937, Richard
Wagner's ``MTRand``, ``Core/SoarKernel/src/shared/soar_rand.h``) seeded with
``init_genrand(seed)`` by ``srand N`` (``decide set-random-seed N``).  Python's
:class:`random.Random` is the same generator, seeded differently; a
:class:`SoarRandom` is one seeded as Soar seeds it, whose draws are Soar's:

* ``rand_int(n)``: Soar's ``SoarRandInt(n)``, an integer in ``[0, n]`` -- the
  next 32-bit outputs masked to the bits ``n`` uses, until one is ``<= n``;
* ``rand()``: Soar's ``SoarRand()``, ``randInt() / (2**32 - 1)``, in ``[0, 1]``;
* ``rand_uint32()``: ``SoarRandInt()``.

``randrange(n)`` and ``random()`` are Soar's draws too, so
:func:`adapt.engine.preferences.choose` picks among indifferent operators as
Soar's ``exploration_randomly_select`` / ``exploration_probabilistically_select``
do, and ``(rand-int 10)`` in a rule gives the number real Soar gives for the
same seed.

Examples
--------
>>> rng = SoarRandom(1)
>>> rng.rand_int(10), rng.rand_int(10), "%f" % rng.rand(), rng.rand_uint32() > 0
(5, 8, '0.000114', True)
"""

from __future__ import annotations

import random
from typing import Any

__all__ = ["SoarRandom"]

_N = 624
_SCALE = 1.0 / 4294967295.0


def _init_genrand(seed: int) -> tuple[int, ...]:
    """The MT19937 state after ``init_genrand(seed)`` (seed taken modulo 2**32)."""
    mt = [0] * _N
    mt[0] = seed & 0xFFFFFFFF
    for i in range(1, _N):
        prev = mt[i - 1]
        mt[i] = (1812433253 * (prev ^ (prev >> 30)) + i) & 0xFFFFFFFF
    return tuple(mt)


class SoarRandom(random.Random):
    """A :class:`random.Random` seeded and drawn as Soar's ``MTRand``."""

    def seed(self, a: Any = None, version: int = 2) -> None:
        """Seed as Soar's ``srand a`` does (``a`` an int; ``None``: 0)."""
        value = 0 if a is None else int(a)
        self.setstate((3, _init_genrand(value) + (_N,), None))

    def rand_uint32(self) -> int:
        """The next 32-bit output (Soar's ``SoarRandInt()``)."""
        return self.getrandbits(32)

    def rand_int(self, n: int) -> int:
        """An integer in ``[0, n]`` for ``0 <= n < 2**32`` (Soar's ``SoarRandInt(n)``)."""
        used = n
        used |= used >> 1
        used |= used >> 2
        used |= used >> 4
        used |= used >> 8
        used |= used >> 16
        while True:
            i = self.getrandbits(32) & used
            if i <= n:
                return i

    def rand(self) -> float:
        """A float in ``[0, 1]`` (Soar's ``SoarRand()``)."""
        return self.getrandbits(32) * _SCALE

    def random(self) -> float:
        """Soar's ``SoarRand()`` (what :func:`~adapt.engine.preferences.choose` draws)."""
        return self.rand()

    def randrange(self, start: int, stop: int | None = None, step: int = 1) -> int:
        """``randrange(n)``: Soar's ``SoarRandInt(n - 1)`` (only this form is Soar's)."""
        if stop is None and step == 1 and start > 0:
            return self.rand_int(start - 1)
        return super().randrange(start, stop, step)
