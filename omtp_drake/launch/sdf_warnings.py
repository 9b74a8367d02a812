"""What sdformat warns about in a world or model file and loads without: elements SDF does not
define (a stray ``<xacro:...>`` call, a URDF ``<joint>`` under ``<world>``). One warning line
each, naming ``file:line``; the element is left out, as Gazebo leaves it out
(docs/own_files.md lists the cases)."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from omtp_drake.launch.xml_lines import XmlFile


def strip_strays(doc: XmlFile, element: ET.Element) -> list[str]:
    """Removes the namespaced elements under ``element`` (a stray ``<xacro:...>`` call in a
    model: no SDF element has a prefix) and returns sdformat's warning for each, naming
    ``file:line``; Drake's parser gets the model without them, as Gazebo loads it."""
    warnings = []
    for parent in list(element.iter()):
        for child in list(parent):
            if isinstance(child.tag, str) and ":" in child.tag:
                line = f"{doc.where(child)}: XML element <{child.tag}> under <{parent.tag}>"
                warnings.append(f"{line} is not defined in SDF (a xacro call?); ignored")
                parent.remove(child)
    return warnings


def not_sdf_line(element: ET.Element, where: str) -> str:
    """sdformat's warning for an element SDF does not define under ``<world>``."""
    tag = element.tag
    if tag == "joint":
        return (
            f"{where}: XML element <joint> (name {element.get('name', '')!r}) under <world> is not an SDF "
            "world's joint (a URDF joint?); ignored, as Gazebo does"
        )
    if tag.startswith("xacro:") or ":" in tag:
        return f"{where}: XML element <{tag}> under <world> is not defined in SDF (a xacro call?); ignored"
    return f"{where}: XML element <{tag}> under <world> is not defined in SDF; ignored"
