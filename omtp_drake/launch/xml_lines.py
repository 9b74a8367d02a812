"""XML with the line of each element, as error messages name it (``file:line``).

ElementTree keeps no line numbers; expat, which parses for it, knows them.
:func:`parse_xml` gives ElementTree's tree and each element's line beside it.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

from omtp_drake.errors import WorkspaceError


@dataclass
class XmlFile:
    """An XML file's root element, and the line each element starts on."""

    path: Path
    root: ET.Element
    lines: dict[int, int] = field(default_factory=dict)

    def line(self, element: ET.Element) -> int | None:
        return self.lines.get(id(element))

    def where(self, element: ET.Element) -> str:
        line = self.line(element)
        return f"{self.path}:{line}" if line else str(self.path)


def parse_xml(path: Path, text: str | None = None) -> XmlFile:
    """The XML file ``path`` (or ``text``, read from it); one WorkspaceError with the
    file and line for a file that is missing or not well-formed."""
    if text is None:
        if not path.is_file():
            raise WorkspaceError(f"{path}: no such file")
        try:
            text = path.read_text()
        except (OSError, UnicodeDecodeError) as e:
            raise WorkspaceError(f"{path}: cannot be read ({e})") from None
    builder = ET.TreeBuilder()
    parser = expat.ParserCreate()
    lines: dict[int, int] = {}

    def start(tag: str, attrs: dict[str, str]) -> None:
        lines[id(builder.start(tag, attrs))] = parser.CurrentLineNumber

    parser.StartElementHandler = start
    parser.EndElementHandler = builder.end
    parser.CharacterDataHandler = builder.data
    try:
        parser.Parse(text, True)
    except expat.ExpatError as e:
        problem = expat.errors.messages[e.code]
        raise WorkspaceError(f"{path}:{e.lineno}: not well-formed XML: {problem}") from None
    return XmlFile(path, builder.close(), lines)
