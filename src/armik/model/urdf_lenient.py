"""Reading the URDFs ROS reads although they are not well-formed XML.

urdfdom (and so Pinocchio and ROS) parses URDFs with TinyXML2, which accepts files that
Python's XML parser refuses. Three kinds are common in published robot descriptions:

- a comment nested in a comment, ``<!-- a <!-- b --> c -->``: TinyXML2 ends a comment at
  the first ``-->``, so `` c -->`` is read as text (and any element there is live);
- ``--`` inside a comment (``<!-- ---- arm ---- -->``);
- a namespace prefix never declared (``<xacro:property .../>`` or a ``xacro:`` attribute
  without ``xmlns:xacro``): urdfdom looks elements and attributes up by their plain
  names, so prefixed ones are ignored.

Also forgiven: a bare ``&`` or an undefined entity (TinyXML2 keeps it as written), a
``<`` inside an attribute value, and what follows the root element (urdfdom reads the
first ``<robot>``: published URDFs close it and then carry a commented-out tail whose
nested comment ends early, leaving elements and a second ``</robot>``). Such a tail is
ignored when TinyXML2 parses it (``armik.model.urdf_tail``) and refused where it does not.

``forgiving_parse`` runs only after the strict parse has failed: such comments are blanked
as TinyXML2 delimits them (to spaces), stray ``&`` and ``<`` are escaped, undeclared
prefixes are declared on the root and the elements and attributes that use them dropped.
Line numbers are kept, so what was forgiven is warned about with its lines, and anything
else still fails with the strict parser's reason and line (as urdfdom refuses it too).
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from armik import errors
from armik.errors import URDFError
from armik.model.urdf_tail import after_root

# The namespace given to prefixes the file never declares: elements in it are dropped.
UNDECLARED = "urn:armik:undeclared:"

_TOKEN = re.compile(
    r"<!--(?P<comment>.*?)-->"  # TinyXML2: a comment ends at the first -->
    r"|<!\[CDATA\[.*?\]\]>"
    r"|<\?.*?\?>"
    r"|<!(?:[^\[>]|\[[^\]]*\])*>"  # <!DOCTYPE ...>, with its internal subset
    r"|<(?P<tag>[^\s/>!?]+)(?:\"[^\"]*\"|'[^']*'|[^'\">])*>",
    re.S,
)
_AMPERSAND = re.compile(r"&(?!(?:lt|gt|amp|quot|apos|#[0-9]+|#x[0-9a-fA-F]+);)")
_QUOTED = re.compile(r"\"[^\"]*\"|'[^']*'")
_ATTRIBUTE = re.compile(r"([^\s=/<>\"']+)\s*=\s*(?:\"[^\"]*\"|'[^']*')")
_SHOWN_LINES = 6


@dataclass
class _Forgiven:
    nested: list[int] = field(default_factory=list)  # lines of comments nested in comments
    dashes: list[int] = field(default_factory=list)  # lines of comments holding --
    prefixes: dict[str, list[tuple[int, str]]] = field(default_factory=dict)  # (line, name)
    ampersands: list[int] = field(default_factory=list)  # lines of & starting no reference
    less_than: list[int] = field(default_factory=list)  # lines of < in attribute values
    tail: int = 0  # the line where what follows the root element starts (0: nothing)

    def escape(self, segment: str, line: int, in_tag: bool) -> str:
        """``segment`` (text, or a start tag when ``in_tag``) from ``line`` with each ``&``
        that starts no XML reference escaped (TinyXML2 keeps it, and ``&name;``, as
        written) and, in a tag, each ``<`` inside a quoted value."""
        if "&" in segment:
            for m in _AMPERSAND.finditer(segment):
                self.ampersands.append(line + segment.count("\n", 0, m.start()))
            segment = _AMPERSAND.sub("&amp;", segment)
        if in_tag and "<" in segment[1:]:

            def escaped(m: re.Match[str]) -> str:
                if "<" not in m.group():
                    return m.group()
                self.less_than.append(line + segment.count("\n", 0, m.start()))
                return m.group().replace("<", "&lt;")

            segment = _QUOTED.sub(escaped, segment)
        return segment


def forgiving_parse(
    text: str, where: str, error: ET.ParseError, warn: bool = True
) -> tuple[ET.Element, tuple[str, ...]]:
    """Parse ``text`` as urdfdom does, after the strict parse failed with ``error``.
    Returns the root and what was forgiven (one line per kind, also warned when ``warn``).
    Raises ``URDFError`` naming the problem and its line when urdfdom would refuse too."""
    cleaned, forgiven = _clean(text)
    cleaned, forgiven.tail = after_root(cleaned, where)  # the first element only
    if cleaned == text:  # nothing this module forgives: today's error
        raise _not_well_formed(where, error) from None
    try:
        root = ET.fromstring(cleaned)
    except ET.ParseError as exc:  # lines are unchanged by the cleaning
        raise _not_well_formed(where, exc) from None
    _drop_undeclared(root)
    notes = _notes(forgiven, where)
    if warn:
        for note in notes:
            errors.warn(note)
    return root, notes


def _not_well_formed(where: str, exc: ET.ParseError) -> URDFError:
    return URDFError(f"URDF file {where!r} is not well-formed XML ({exc}): fix the XML", path=where)


def _clean(text: str) -> tuple[str, _Forgiven]:
    """The text with what TinyXML2 forgives made well-formed, line numbers kept: comments
    blanked, stray ``&`` and ``<`` escaped, undeclared prefixes declared on the root
    element. Also what was done, by line."""
    forgiven = _Forgiven()
    pieces: list[str] = []
    declared: set[str] = set()
    used: dict[str, list[tuple[int, str]]] = {}
    root_slot = -1  # the index in pieces where the root's declarations go
    done, line = 0, 1  # text[:done] is in pieces; line is the line number at done
    for m in _TOKEN.finditer(text):
        start, end = m.span()
        pieces.append(forgiven.escape(text[done:start], line, in_tag=False))
        line += text.count("\n", done, start)
        body, tag = m.group("comment"), m.group("tag")
        if body is not None and ("--" in body or body.endswith("-")):
            (forgiven.nested if "<!--" in body else forgiven.dashes).append(line)
            pieces.append(re.sub(r"[^\n]", " ", m.group()))
        elif tag is not None:
            token = m.group()
            names = [(tag, True)]
            if ":" in token:  # most tags have no prefix: skip the attribute scan
                names += [(a, False) for a in _ATTRIBUTE.findall(token, len(tag) + 1)]
            for name, is_element in names:
                prefix, colon, local = name.partition(":")
                if not colon or not prefix:
                    continue
                if prefix == "xmlns":
                    declared.add(local)
                elif prefix != "xml":
                    at = line + token.count("\n", 0, token.find(name))
                    used.setdefault(prefix, []).append((at, f"<{name}>" if is_element else name))
            token = forgiven.escape(token, line, in_tag=True)
            if root_slot < 0:
                pieces.append(token[: len(tag) + 1])
                root_slot = len(pieces)
                pieces.extend(("", token[len(tag) + 1 :]))
            else:
                pieces.append(token)
        else:
            pieces.append(m.group())
        line += text.count("\n", start, end)
        done = end
    pieces.append(forgiven.escape(text[done:], line, in_tag=False))
    forgiven.prefixes = {p: places for p, places in used.items() if p not in declared}
    if root_slot >= 0 and forgiven.prefixes:
        pieces[root_slot] = "".join(
            f' xmlns:{p}="{UNDECLARED}{p}"' for p in sorted(forgiven.prefixes)
        )
    return "".join(pieces), forgiven


def _drop_undeclared(root: ET.Element) -> None:
    """Remove the elements and attributes in an undeclared prefix: urdfdom never reads
    them (it looks names up without prefixes)."""

    def undeclared(name: str) -> bool:
        return name.startswith("{" + UNDECLARED)

    for elem in list(root.iter()):
        for child in list(elem):
            if isinstance(child.tag, str) and undeclared(child.tag):
                elem.remove(child)
        for key in [k for k in elem.attrib if undeclared(k)]:
            del elem.attrib[key]


def _notes(forgiven: _Forgiven, where: str) -> tuple[str, ...]:
    notes = []
    if forgiven.nested:
        notes.append(
            f"URDF file {where!r}, {_lines(forgiven.nested)}: a comment nested in a comment, "
            "read as urdfdom reads it: the comment ends at the first '-->' and what follows "
            "is read as XML"
        )
    if forgiven.dashes:
        notes.append(
            f"URDF file {where!r}, {_lines(forgiven.dashes)}: '--' inside a comment (not "
            "allowed in XML), read as urdfdom reads it: the comment ends at the first '-->'"
        )
    if forgiven.ampersands:
        notes.append(
            f"URDF file {where!r}, {_lines(forgiven.ampersands)}: a bare '&' or an undefined "
            "entity (write '&amp;'), read as urdfdom reads it: as written"
        )
    if forgiven.less_than:
        notes.append(
            f"URDF file {where!r}, {_lines(forgiven.less_than)}: a '<' inside an attribute "
            "value (write '&lt;'), read as urdfdom reads it: as a '<'"
        )
    if forgiven.tail:
        notes.append(
            f"URDF file {where!r}, line {forgiven.tail}: what follows the root element "
            "(junk after the document element) is ignored, as urdfdom ignores it: it reads "
            "the first <robot> element only"
        )
    for prefix, places in sorted(forgiven.prefixes.items()):
        names = sorted({name for _, name in places})
        shown = ", ".join(names[:_SHOWN_LINES]) + (", ..." if len(names) > _SHOWN_LINES else "")
        notes.append(
            f"URDF file {where!r}, {_lines([at for at, _ in places])}: the prefix {prefix!r} is "
            f"used without xmlns:{prefix} declared ({shown}); urdfdom ignores such elements "
            "and attributes, and so does armik"
        )
    return tuple(notes)


def _lines(numbers: list[int]) -> str:
    numbers = sorted(set(numbers))
    if len(numbers) == 1:
        return f"line {numbers[0]}"
    shown = ", ".join(str(n) for n in numbers[:_SHOWN_LINES])
    more = len(numbers) - _SHOWN_LINES
    return f"lines {shown}" + (f" and {more} more" if more > 0 else "")
