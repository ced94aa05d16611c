"""Reading and inspecting adapt's JSON Lines traces.

The engine writes a trace in the format of ``docs/trace-format.md``; this
package reads it back, streaming, and answers the questions a rule writer
asks: what did working memory hold at decision *D* (:mod:`.memory`), why is
this WME there and why did that rule not fire (:mod:`.why`), what happened
between decisions *A* and *B* (:mod:`.show`), how did the run go overall
(:mod:`.stats`), where do two runs part (:mod:`.diff`); and it renders one
self-contained HTML viewer (:mod:`.html`).

Every function streams the file: memory stays bounded by the live working
memory, never by the length of the run.
"""

from __future__ import annotations
