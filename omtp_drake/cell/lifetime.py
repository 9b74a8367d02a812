"""Freeing a built cell: the reference cycles Python's gc cannot collect, broken at close.

With pydrake 1.51 on Python 3.11 a diagram holding one of our Python
``LeafSystem`` subclasses is never freed by itself, for two reasons:

- A Python subclass of ``LeafSystem`` that is part of a reference cycle is never
  collected (``k = MySystem(); k.me = k; del k; gc.collect()`` leaves it alive):
  gc visits such an object's ``__dict__`` twice (``gc.get_referents`` lists it
  twice: once for Python's subclass, once for pybind11's base), so the dict looks
  referenced from outside the cycle. ``DiagramBuilder.AddSystem`` puts every
  system in a cycle with its builder (pydrake's ``ref_cycle``), and our systems
  keep the plant, ports and each other, so every system, its diagram, the plant,
  the scene graph and the Contexts built on them stayed for the life of the process.
- An output port's or cache entry's calc (and allocate) callback is held by C++
  (an event's callback is not: it sits in the system's own ``__dict__``), so a
  bound method or a closure over ``self`` there keeps its system alive from C++,
  where gc cannot see it.

So the owner of a diagram breaks the cycles when it is done with it
(:func:`release`), and systems hand their port and cache callbacks to C++ through
:func:`weak_method`. A released diagram must not run again: its systems have lost
their members and their events' callbacks (running it would crash the process),
which is why only a closing owner (``FactoryRuntime.close``) calls :func:`release`.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Iterator
from typing import Any

from pydrake.systems.framework import Diagram, System


def weak_method(method: Callable[..., Any]) -> Callable[..., Any]:
    """``method`` (a bound method of a system) as a callback that does not keep
    its system alive: for the calc and allocate callbacks of output ports and cache
    entries, which C++ holds. The system outlives every call Drake makes."""
    function, ref = method.__func__, weakref.ref(method.__self__)  # type: ignore[attr-defined]

    def call(*args: Any) -> Any:
        return function(ref(), *args)  # (a WeakMethod's call costs about 3x this)

    return call


def python_systems(diagram: Diagram) -> Iterator[System]:
    """The systems of ``diagram`` (in nested diagrams too, and those diagrams themselves)
    implemented in Python."""
    for system in diagram.GetSystems():
        if isinstance(system, Diagram):
            yield from python_systems(system)
        if not type(system).__module__.startswith("pydrake."):
            yield system  # a Python diagram too (its members hold its subsystems)


def release(diagram: Diagram) -> None:
    """Breaks the cycles through ``diagram``'s Python systems (their members are
    dropped), so the diagram, its plant, scene graph and Contexts are freed once
    nothing else holds them. ``diagram`` must not be used afterwards."""
    for system in list(python_systems(diagram)):
        vars(system).clear()
