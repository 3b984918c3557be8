"""What follows a URDF's root element, read as urdfdom reads it.

XML allows one document element; TinyXML2 (urdfdom's parser) reads every node at the top
level and urdfdom takes the first ``<robot>``, so a file that closes ``</robot>`` and goes
on (a commented-out old version whose nested comment ends early, leaving elements and a
second ``</robot>``) loads in ROS and Pinocchio. TinyXML2 still refuses some tails, and so
does armik, by the same rules (checked against Pinocchio in
``tests/model/test_urdf_tail.py``):

- whitespace, comments, elements (closed, attributes quoted and not repeated) and text
  followed by a ``<`` are read and ignored;
- a closing tag with no element open ends the parse: whatever follows it is never read;
- a declaration or processing instruction (``<?...?>``), an unclosed comment, CDATA or
  element, a mismatched closing tag, a ``<`` that starts no tag, and text at the very end
  are refused.
"""

from __future__ import annotations

import re
from xml.parsers import expat

from armik.errors import URDFError

_NAME = r"[^\s/>=<!?\"']+"
_ATTRIBUTE = re.compile(rf"\s+({_NAME})\s*=\s*(?:\"[^\"]*\"|'[^']*')")
_START = re.compile(rf"<({_NAME})((?:\s+{_NAME}\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)\s*(/?)>")
_END = re.compile(rf"</({_NAME})\s*>")
_CLOSED = {"<!--": "-->", "<![CDATA[": "]]>"}


def after_root(text: str, where: str) -> tuple[str, int]:
    """``text`` up to the end of its root element when what follows that element stops
    the strict parse, and the line where what follows starts; else ``text`` and 0 (the
    strict parse fails within the root element, or not at all).
    Raises ``URDFError`` naming the line when urdfdom (TinyXML2) refuses what follows."""
    data = text.encode("utf-8")
    parser = expat.ParserCreate(namespace_separator="}")  # as ElementTree parses
    depth, closed = 0, -1

    def opened(name: str, attributes: dict) -> None:
        nonlocal depth
        depth += 1

    def ended(name: str) -> None:
        nonlocal depth, closed
        depth -= 1
        if depth == 0 and closed < 0:  # at the root's '</': its end is the next '>'
            closed = data.index(b">", parser.CurrentByteIndex) + 1

    parser.StartElementHandler, parser.EndElementHandler = opened, ended
    try:
        parser.Parse(text, True)  # a str: read as UTF-8 (as ElementTree reads it), indexed so
    except expat.ExpatError:
        pass
    else:
        return text, 0
    if closed < 0:  # the error lies within the root element: not this module's
        return text, 0
    head = data[:closed].decode("utf-8")
    problem = _refused(text, len(head))
    line = head.count("\n") + 1
    if problem is not None:
        what, at = problem
        bad = text.count("\n", 0, at) + 1
        raise URDFError(
            f"URDF file {where!r} is not well-formed XML (junk after document element: the "
            f"root element ends on line {line}, and after it {what}: line {bad}): urdfdom "
            "refuses it too; remove what follows the root element's </robot>",
            path=where,
        )
    rest = text[len(head) :]
    return head, text.count("\n", 0, len(text) - len(rest.lstrip())) + 1


def _refused(text: str, at: int) -> tuple[str, int] | None:
    """Why TinyXML2 refuses the nodes from ``at`` on, and where, or None."""
    open_tags: list[str] = []
    n = len(text)
    while at < n:
        lt = text.find("<", at)
        if lt < 0:
            if open_tags:
                return f"<{open_tags[-1]}> is never closed", n
            rest = text[at:]
            if rest.strip():
                return "text at the end of the file", n - len(rest.lstrip())
            return None
        at = lt
        opened = next((o for o in _CLOSED if text.startswith(o, at)), None)
        if opened is not None:
            close = text.find(_CLOSED[opened], at + len(opened))
            if close < 0:
                return f"an unclosed {'comment' if opened == '<!--' else 'CDATA section'}", at
            at = close + len(_CLOSED[opened])
        elif text.startswith("<?", at):
            return "a declaration or processing instruction after the root element", at
        elif text.startswith("<!", at):  # <!DOCTYPE ...>: TinyXML2 keeps it as unknown
            close = text.find(">", at)
            if close < 0:
                return "an unclosed '<!'", at
            at = close + 1
        elif (m := _END.match(text, at)) is not None:
            if not open_tags:
                return None  # TinyXML2 stops here: nothing after it is read
            if m.group(1) != open_tags[-1]:
                return f"</{m.group(1)}> closes <{open_tags[-1]}>", at
            open_tags.pop()
            at = m.end()
        elif (m := _START.match(text, at)) is not None:
            names = _ATTRIBUTE.findall(m.group(2))
            if len(set(names)) != len(names):
                return f"a duplicate attribute in <{m.group(1)}>", at
            if not m.group(3):
                open_tags.append(m.group(1))
            at = m.end()
        else:
            return "a '<' that starts no tag", at
    if open_tags:
        return f"<{open_tags[-1]}> is never closed", n
    return None
