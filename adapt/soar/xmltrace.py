"""The Soar kernel's XML trace, read as a flat sequence of tags.

SML sends the trace (``smlEVENT_XML_TRACE_OUTPUT``) as XML strings such as::

    <trace><phase name="decision"></phase><operator current_operator_id="O1"
    decision_cycle_count="1" name="init" stack_level="0"></operator>...</trace>

Only start tags carry information (the kernel writes each element's data as
attributes; a ``<production>`` holds its matched ``<wme tag="..">`` elements
and a ``<firing_production>`` its ``<production>``).  :func:`tags` returns
``(name, attributes)`` for every start tag in document order, which is all
:mod:`adapt.soar.recorder` needs, two to three times faster than building an
element tree.  Attribute values are unescaped; the newlines a ``(write
(crlf))`` puts into ``<rhs_write string="...">`` are kept (an XML parser
would turn them into spaces).

Examples
--------
>>> tags('<trace><rhs_write string="a &amp; b&#10;"></rhs_write></trace>')
[('rhs_write', {'string': 'a & b\\n'})]
>>> tags('<trace><wme attr="x" id="S1" tag="7" valtype="int" value="3"></wme></trace>')
[('wme', {'attr': 'x', 'id': 'S1', 'tag': '7', 'valtype': 'int', 'value': '3'})]
"""

from __future__ import annotations

import html
import re

__all__ = ["tags", "Tag"]

#: One start tag: its name and its attributes.
Tag = tuple[str, dict[str, str]]

_TAG = re.compile(r"<([A-Za-z_][\w-]*)((?:\s+[\w-]+\s*=\s*\"[^\"]*\")*)\s*/?>")
_ATTR = re.compile(r"([\w-]+)\s*=\s*\"([^\"]*)\"")


def tags(xml: str) -> list[Tag]:
    """Every start tag of ``xml`` but the enclosing ``<trace>``, in order."""
    out: list[Tag] = []
    for m in _TAG.finditer(xml):
        name = m.group(1)
        if name == "trace":
            continue
        attrs = {}
        for key, value in _ATTR.findall(m.group(2)):
            attrs[key] = html.unescape(value) if "&" in value else value
        out.append((name, attrs))
    return out
