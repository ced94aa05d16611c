"""Working memory: the set of WMEs, with buffered changes and garbage collection.

:class:`WorkingMemory` holds WMEs with Soar's semantics:

* **set semantics** -- a WME is identified by ``(id, attr, value,
  acceptable)``; adding one that exists is a no-op, removing one that does not
  exist is a no-op;
* **buffered changes** -- :meth:`WorkingMemory.add` and
  :meth:`WorkingMemory.remove` only record an intention; :meth:`WorkingMemory.commit`
  (called by the decision cycle at the end of every elaboration cycle and
  phase, Soar's "working-memory phase") applies them.  A WME removed and added
  in the same batch stays in place with its old timetag and is not reported as
  changed, so no rule re-fires on it;
* **timetags** -- every WME added gets the next timetag (1, 2, 3, ...), in the
  order the additions were requested;
* **indexes** -- by identifier (for printing and garbage collection) and by
  value identifier (the links pointing at an identifier);
* **garbage collection** -- when a link to an identifier disappears, and the
  identifier can no longer be reached from any *root* (the states), all of its
  WMEs are removed too, recursively (cycles included).

The WMEs changed by a commit are passed to a *listener* (the matcher) in
Soar's order -- ``add_wme`` for each addition, the newest first, then
``remove_wme`` for each removal, the last requested (and the garbage
collected) first -- and returned to the caller in the order they happened.

Working memory does not know about preferences or support; the decision
cycle decides which WMEs should exist and asks for the changes.

Examples
--------
>>> from adapt.engine.symbols import IdentifierFactory
>>> ids = IdentifierFactory()
>>> s1, o1 = ids.state(), ids.new("O")
>>> wm = WorkingMemory()
>>> wm.add_root(s1)
>>> wm.add(s1, "count", 1)
>>> wm.add(s1, "thing", o1)
>>> wm.add(o1, "name", "box")
>>> added, removed = wm.commit()
>>> added
[(1: S1 ^count 1), (2: S1 ^thing O1), (3: O1 ^name box)]
>>> wm.remove(s1, "count", 1); wm.add(s1, "count", 1)   # remove + add: stays
>>> wm.commit()
([], [])
>>> wm.remove(s1, "thing", o1)       # O1 becomes unreachable: collected
>>> wm.commit()[1]
[(2: S1 ^thing O1), (3: O1 ^name box)]
>>> len(wm)
1
"""

from __future__ import annotations

from typing import Iterator, Protocol

from adapt.engine.symbols import Identifier, Symbol, format_symbol, symbol_sort_key
from adapt.engine.wme import WME

__all__ = ["WorkingMemory", "WmeListener", "WmeKey"]

#: Builds a WME from a 5-tuple without the named tuple's keyword handling.
_tuple_new = tuple.__new__

#: ``(id, attr, value, acceptable)``: what makes two WMEs the same.
WmeKey = tuple[Symbol, Symbol, Symbol, bool]


class WmeListener(Protocol):
    """What working memory tells about committed changes (a matcher)."""

    def add_wme(self, wme: WME) -> None:
        """``wme`` is now in working memory."""

    def remove_wme(self, wme: WME) -> None:
        """``wme`` has left working memory."""


class WorkingMemory:
    """The WMEs of one agent, with buffered changes and garbage collection.

    Parameters
    ----------
    listener : WmeListener, optional
        Told about every committed removal and addition (removals first).
    """

    __slots__ = ("_wmes", "_by_id", "_links_to", "_timetag", "_adds", "_removes",
                 "_roots", "listener")

    def __init__(self, listener: WmeListener | None = None) -> None:
        self._wmes: dict[WmeKey, WME] = {}
        self._by_id: dict[Symbol, dict[WmeKey, WME]] = {}
        self._links_to: dict[Identifier, dict[WmeKey, WME]] = {}
        self._timetag = 0
        self._adds: dict[WmeKey, None] = {}
        self._removes: dict[WmeKey, None] = {}
        self._roots: set[Identifier] = set()
        self.listener = listener

    # -- roots ---------------------------------------------------------
    def add_root(self, ident: Identifier) -> None:
        """Make ``ident`` a root: it and everything linked from it are kept."""
        self._roots.add(ident)

    def remove_root(self, ident: Identifier) -> None:
        """``ident`` is no longer a root (its structure may be collected)."""
        self._roots.discard(ident)

    # -- buffered changes ------------------------------------------------
    def add(self, id: Symbol, attr: Symbol, value: Symbol, acceptable: bool = False) -> None:
        """Request the WME ``(id ^attr value [+])``; applied by :meth:`commit`."""
        key = (id, attr, value, acceptable)
        self._adds[key] = None

    def remove(self, id: Symbol, attr: Symbol, value: Symbol, acceptable: bool = False) -> None:
        """Request the removal of ``(id ^attr value [+])``; applied by :meth:`commit`.

        A removal requested after an addition of the same WME in the same batch
        cancels that addition if the WME did not exist before.
        """
        key = (id, attr, value, acceptable)
        if key in self._adds and key not in self._wmes:
            del self._adds[key]
            return
        self._removes[key] = None

    def add_key(self, key: WmeKey) -> None:
        """:meth:`add` by key ``(id, attr, value, acceptable)``."""
        self._adds[key] = None

    def remove_key(self, key: WmeKey) -> None:
        """:meth:`remove` by key ``(id, attr, value, acceptable)``."""
        if key in self._adds and key not in self._wmes:
            del self._adds[key]
            return
        self._removes[key] = None

    @property
    def pending_adds(self) -> dict[WmeKey, None]:
        """The buffered additions, by key; the kernel requests an addition
        with ``pending_adds[key] = None`` (same as :meth:`add`)."""
        return self._adds

    @property
    def pending(self) -> bool:
        """True when changes wait for :meth:`commit`."""
        return bool(self._adds or self._removes)

    def commit(self) -> tuple[list[WME], list[WME]]:
        """Apply the buffered changes, collect garbage, notify the listener.

        Returns
        -------
        (added, removed) : tuple of lists of WME
            The WMEs that entered and left working memory, in order.  A WME
            both removed and added in this batch is in neither list.
        """
        adds, removes = self._adds, self._removes
        if not adds and not removes:
            return [], []
        self._adds, self._removes = {}, {}
        wmes = self._wmes
        removed: list[WME] = []
        if removes:
            by_id = self._by_id
            for key in removes:
                if key in adds:
                    continue
                w = wmes.pop(key, None)
                if w is not None:
                    bucket = by_id[key[0]]
                    del bucket[key]
                    if not bucket:
                        del by_id[key[0]]
                    value = key[2]
                    if type(value) is Identifier:
                        links = self._links_to[value]
                        del links[key]
                        if not links:
                            del self._links_to[value]
                    removed.append(w)
        added: list[WME] = []
        if adds:
            by_id = self._by_id
            links_to = self._links_to
            tt = self._timetag
            new = _tuple_new
            for key in adds:
                if key in wmes:
                    continue
                tt += 1
                w = new(WME, key + (tt,))
                wmes[key] = w
                ident = key[0]
                known = by_id.get(ident)
                if known is None:
                    by_id[ident] = {key: w}
                else:
                    known[key] = w
                value = key[2]
                if type(value) is Identifier:
                    linked = links_to.get(value)
                    if linked is None:
                        links_to[value] = {key: w}
                    else:
                        linked[key] = w
                added.append(w)
            self._timetag = tt
        if removed:
            for w in removed:
                if type(w[2]) is Identifier:
                    self._collect(removed)
                    break
        listener = self.listener
        if listener is not None:
            # Soar's order (do_buffered_wm_changes): its lists of WMEs to add and
            # to remove grow at the head, and it passes the additions, then the
            # removals (garbage collection's last), through its Rete
            if added:
                add_wme = listener.add_wme
                for w in reversed(added):
                    add_wme(w)
            if removed:
                remove_wme = listener.remove_wme
                for w in reversed(removed):
                    remove_wme(w)
        return added, removed

    def _unlink(self, key: WmeKey, w: WME) -> None:
        del self._wmes[key]
        bucket = self._by_id[key[0]]
        del bucket[key]
        if not bucket:
            del self._by_id[key[0]]
        value = key[2]
        if type(value) is Identifier:
            links = self._links_to[value]
            del links[key]
            if not links:
                del self._links_to[value]

    def _reachable(self, ident: Identifier) -> tuple[bool, set[Identifier]]:
        """Search backwards along links: is ``ident`` reachable from a root?"""
        seen = {ident}
        frontier = [ident]
        roots = self._roots
        links_to = self._links_to
        while frontier:
            node = frontier.pop()
            if node in roots:
                return True, seen
            for key in links_to.get(node, ()):
                parent = key[0]
                if type(parent) is Identifier and parent not in seen:
                    seen.add(parent)
                    frontier.append(parent)
        return False, seen

    def _collect(self, removed: list[WME]) -> None:
        """Remove the structure no longer reachable from a root (appends to ``removed``)."""
        suspects = [w[2] for w in removed if type(w[2]) is Identifier]
        if not suspects:
            return
        while suspects:
            ident = suspects.pop()
            if ident in self._roots or ident not in self._by_id:
                continue
            alive, group = self._reachable(ident)
            if alive:
                continue
            for node in group:
                bucket = self._by_id.get(node)
                if not bucket:
                    continue
                for key, w in list(bucket.items()):
                    self._unlink(key, w)
                    removed.append(w)
                    if type(w.value) is Identifier:
                        suspects.append(w.value)

    # -- reading -----------------------------------------------------------
    def __len__(self) -> int:
        return len(self._wmes)

    def __iter__(self) -> Iterator[WME]:
        return iter(list(self._wmes.values()))

    def __contains__(self, key: object) -> bool:
        return key in self._wmes

    def get(self, id: Symbol, attr: Symbol, value: Symbol, acceptable: bool = False) -> WME | None:
        """The WME ``(id ^attr value [+])`` if it is in working memory."""
        return self._wmes.get((id, attr, value, acceptable))

    def of(self, ident: Symbol) -> list[WME]:
        """The WMEs whose identifier is ``ident``, oldest first."""
        bucket = self._by_id.get(ident)
        if not bucket:
            return []
        return sorted(bucket.values(), key=lambda w: w.timetag)

    def values(self, ident: Symbol, attr: Symbol) -> list[Symbol]:
        """The values of ``(ident ^attr *)`` (not acceptable preferences), oldest first."""
        bucket = self._by_id.get(ident)
        if not bucket:
            return []
        # a bucket's insertion order is timetag order (timetags only grow)
        return [w[2] for w in bucket.values() if w[1] == attr and not w[3]]

    def links_to(self, ident: Identifier) -> list[WME]:
        """The WMEs whose value is ``ident``."""
        return list(self._links_to.get(ident, {}).values())

    def identifiers(self) -> set[Symbol]:
        """Every identifier that has WMEs."""
        return set(self._by_id)

    def tree(self, root: Identifier, depth: int = 1) -> str:
        """Print the structure under ``root`` like Soar's ``print --depth N``.

        Each identifier is printed once, as ``(S1 ^attr value ...)``, its
        attributes sorted; identifiers reached within ``depth`` levels follow.

        Examples
        --------
        >>> from adapt.engine.symbols import IdentifierFactory
        >>> ids = IdentifierFactory(); s1, i1 = ids.state(), ids.new("I")
        >>> wm = WorkingMemory(); wm.add_root(s1)
        >>> wm.add(s1, "io", i1); wm.add(i1, "x", 2); wm.add(s1, "a", "b")
        >>> _ = wm.commit()
        >>> print(wm.tree(s1, 2))
        (S1 ^a b ^io I1)
          (I1 ^x 2)
        """
        lines: list[str] = []
        seen: set[Symbol] = set()

        def show(ident: Symbol, level: int) -> None:
            if ident in seen:
                return
            seen.add(ident)
            ws = sorted(self.of(ident), key=lambda w: (str(w.attr), symbol_sort_key(w.value)))
            parts = [f"^{format_symbol(w.attr)} {format_symbol(w.value)}"
                     + (" +" if w.acceptable else "") for w in ws]
            lines.append("  " * level + f"({format_symbol(ident)} " + " ".join(parts) + ")")
            if level + 1 < depth:
                for w in ws:
                    if type(w.value) is Identifier and w.value in self._by_id:
                        show(w.value, level + 1)

        show(root, 0)
        return "\n".join(lines)
