"""The frame tree as a picture, like ROS's ``view_frames``: ``view_frames(buffer, "frames")``
writes ``frames.pdf`` and ``frames.png``.
"""

from __future__ import annotations

import logging
import textwrap
from pathlib import Path
from typing import TYPE_CHECKING, Optional

from omtp_drake.sim.tf import TfBuffer

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.text import Text

_log = logging.getLogger(__name__)

_COLOURS = {
    "fixed": ("#f5f6f8", "#8391a7"),
    "moving": ("#cfe0fa", "#1f4e8c"),
    "camera": ("#ffe2c2", "#d2691e"),
    "detected": ("#d5f5d5", "#2e8b57"),
}


_LEGEND = {
    "fixed": "frame (fixed to its parent)",
    "moving": "frame (across a joint)",
    "camera": "logical camera frame",
    "detected": "model seen by a camera",
}


def _wrap(name: str, width: int = 15) -> str:
    """Splits a frame name at underscores into lines of about ``width`` characters."""
    lines: list[str] = []
    for word in name.split("_"):
        if lines and len(lines[-1]) + 1 + len(word) <= width:
            lines[-1] += "_" + word
        else:
            if lines:
                lines[-1] += "_"
            lines.append(word)
    return "\n".join(textwrap.fill(line, width + 1) for line in lines)


def _tree_layout(edges: list[tuple[str, str]], root: str) -> tuple[dict[str, tuple[float, int]], int]:
    """Tidy top-down layout: leaves at consecutive x in depth-first order, each
    parent centred over its children. Returns name -> (x, depth) and the leaf count."""
    children: dict[str, list[str]] = {}
    for parent, child in edges:
        children.setdefault(parent, []).append(child)
    for kids in children.values():
        kids.sort()
    position: dict[str, tuple[float, int]] = {}
    next_leaf = 0

    def place(name: str, depth: int) -> float:
        nonlocal next_leaf
        kids = children.get(name, [])
        if not kids:
            x = float(next_leaf)
            next_leaf += 1
        else:
            xs = [place(k, depth + 1) for k in kids]
            x = (xs[0] + xs[-1]) / 2
        position[name] = (x, depth)
        return x

    place(root, 0)
    return position, next_leaf


def _tree_axes(position: dict[str, tuple[float, int]], leaves: int) -> tuple[Figure, Axes]:
    """A figure sized for the layout ``position`` of ``leaves`` leaves, and its
    frameless axes in layout units (x: leaf slots, y: minus the depth)."""
    from matplotlib.figure import Figure

    depth = max(d for _, d in position.values())
    slot, row = 1.25, 0.95  # inches per leaf, per level
    width = max(8.0, slot * leaves + 1.0)
    height = row * (depth + 1) + 1.0
    fig = Figure(figsize=(width, height))
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    ax.set_xlim(-0.5 - 0.4 / slot, leaves - 0.5 + 0.4 / slot)
    ax.set_ylim(-(depth + 0.5), 0.5 + 0.6 / row)
    ax.axis("off")
    return fig, ax


def _draw_frame_boxes(ax: Axes, buffer: TfBuffer, position: dict[str, tuple[float, int]]) -> dict[str, Text]:
    """One box per frame at its layout position, coloured by its kind; name -> box."""
    fontsize = 8.5
    boxes = {}
    for name, (x, d) in position.items():
        face, edge = _COLOURS[buffer.frame_kind(name)]
        boxes[name] = ax.text(
            x,
            -d,
            _wrap(name),
            ha="center",
            va="center",
            fontsize=fontsize,
            zorder=3,
            bbox=dict(boxstyle="round,pad=0.35", facecolor=face, edgecolor=edge, linewidth=1.2),
        )
    return boxes


def _box_extents(fig: Figure, ax: Axes, boxes: dict[str, Text]) -> dict[str, tuple[float, float]]:
    """Name -> (bottom, top) of each box, in data units: each text's box laid out as its
    drawing lays it out (the figure is drawn once, when saved: a draw of the whole figure
    here, only to place the boxes, took a third of the tree's time)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    renderer = FigureCanvasAgg(fig).get_renderer()
    to_data = ax.transData.inverted()
    extent = {}
    for name, text in boxes.items():
        text.update_bbox_position_size(renderer)  # (what Text.draw does before drawing its box)
        (_, y0), (_, y1) = to_data.transform(text.get_bbox_patch().get_window_extent(renderer).get_points())
        extent[name] = (min(y0, y1), max(y0, y1))
    return extent


def _draw_connectors(
    ax: Axes,
    buffer: TfBuffer,
    edges: list[tuple[str, str]],
    position: dict[str, tuple[float, int]],
    extent: dict[str, tuple[float, float]],
) -> None:
    """Org-chart connectors: down from the parent, along a bus, an arrow down into each child."""
    from matplotlib.patches import FancyArrowPatch

    children: dict[str, list[str]] = {}
    for parent, child in edges:
        children.setdefault(parent, []).append(child)
    trunk = "#8391a7"
    for parent, kids in children.items():
        x0 = position[parent][0]
        bottom = extent[parent][0]
        bus = min(bottom - 0.12, max(extent[k][1] for k in kids) + 0.16)
        xs = [position[k][0] for k in kids]
        ax.plot([x0, x0], [bottom, bus], color=trunk, linewidth=1.0, zorder=1)
        ax.plot([min(xs + [x0]), max(xs + [x0])], [bus, bus], color=trunk, linewidth=1.0, zorder=1)
        for kid, x1 in zip(kids, xs):
            kind = buffer.frame_kind(kid)
            colour = _COLOURS[kind][1] if kind in ("detected", "moving") else trunk
            ax.add_patch(
                FancyArrowPatch(
                    (x1, bus),
                    (x1, extent[kid][1]),
                    arrowstyle="-|>",
                    mutation_scale=9,
                    color=colour,
                    linewidth=1.5 if kind == "moving" else 1.0,
                    linestyle="--" if kind == "detected" else "-",
                    shrinkA=0,
                    shrinkB=1,
                    zorder=2,
                )
            )


def _draw_heading_and_legend(ax: Axes, heading: str, t: float, frames: int) -> None:
    """The title line (``heading``, time, frame count) top left and the colour legend top right."""
    from matplotlib.patches import Patch

    ax.text(
        0.01,
        0.995,
        f"{heading}  (t = {t:.3f} s, {frames} frames)",
        transform=ax.transAxes,
        ha="left",
        va="top",
        fontsize=13,
        weight="bold",
    )
    ax.legend(
        handles=[Patch(facecolor=f, edgecolor=e, label=_LEGEND[k]) for k, (f, e) in _COLOURS.items()],
        loc="upper right",
        fontsize=9,
        frameon=False,
        ncol=4,
        bbox_to_anchor=(0.995, 0.995),
    )


def _save_pdf_and_png(fig: Figure, path_stem: Path) -> list[Path]:
    """Writes ``<stem>.pdf`` and ``<stem>.png`` (creating the folder); returns their paths."""
    paths = []
    path_stem.parent.mkdir(parents=True, exist_ok=True)
    for suffix in (".pdf", ".png"):
        path = path_stem.parent / (path_stem.name + suffix)
        fig.savefig(path, dpi=100)
        paths.append(path)
    return paths


def view_frames(
    buffer: TfBuffer, path_stem: str | Path, time: Optional[float] = None, *, title: Optional[str] = None
) -> list[Path]:
    """Draws the frame tree at ``time`` (None: latest) into ``<stem>.pdf`` and ``<stem>.png``.

    Like ROS ``view_frames``, with matplotlib (no graphviz): frames are boxes,
    arrows go parent -> child, ``world`` on top. Logical camera frames and the
    frames of the models they see are coloured. Returns the two paths written.
    A ``.pdf`` or ``.png`` suffix of ``path_stem`` is dropped.
    """
    # matplotlib is imported in the helpers: it takes ~0.3 s to import. No pyplot: no global state.
    path_stem = Path(path_stem)
    if path_stem.suffix.lower() in (".pdf", ".png"):
        path_stem = path_stem.with_suffix("")
    edges = buffer.edges(time)
    t = buffer.times[-1] if time is None else float(time)
    position, leaves = _tree_layout(edges, "world")
    fig, ax = _tree_axes(position, leaves)
    boxes = _draw_frame_boxes(ax, buffer, position)
    # Arrows run from the bottom of the parent's box to the top of the child's.
    extent = _box_extents(fig, ax, boxes)
    _draw_connectors(ax, buffer, edges, position, extent)
    _draw_heading_and_legend(ax, title or "Frame tree", t, len(position))
    paths = _save_pdf_and_png(fig, path_stem)
    _log.info("frame tree written to %s", ", ".join(str(p) for p in paths))
    return paths
