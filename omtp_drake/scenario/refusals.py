"""Why a scenario document was refused: the first refused value, named by its key path.

Drake's typed loader (``yaml_load_typed``) is the scenario's one checker of
keys and types: :func:`omtp_drake.scenario.loader.scenario_from_dict` hands it
the whole document and nothing else looks at the types of a document that
loads. Drake's own messages say neither where the value is nor what would be
valid (``The fields ['hfov'] were unknown to the schema``). So when it refuses
a document, :func:`refusal_message` walks the document beside the schema and
asks the same loader about each piece until it finds the first one refused,
then says it in one line::

    cams.yaml: cameras[logical_camera_2]: unknown key 'hfov' (did you mean
    'horizontal_fov'?); valid keys: name, parent, ...
    bad.yaml: cameras[c].occlusion must be true or false, got 'yes'

Also here: the schema's field types (:func:`schema_fields`, :func:`is_record`,
:func:`unwrap_optional`), which the batch sweep's ``--set`` reads too, and
:func:`closest_name`.
"""

import dataclasses
import difflib
import typing
from collections.abc import Sequence
from typing import Any, Optional

import numpy as np
from pydrake.common.yaml import yaml_load_typed

#: What the loader accepts for a value of each plain type, as the message says it.
_PLAIN = {float: "a number", int: "an integer", bool: "true or false", str: "a string"}
_PLAIN_PLURAL = {float: "numbers", int: "integers", bool: "true/false values", str: "strings"}

#: The errors Drake's typed loader raises for a value it refuses.
LOADER_ERRORS = (RuntimeError, AssertionError, TypeError, ValueError)


def schema_fields(schema: Any) -> dict[str, Any]:
    """Field name -> type of a dataclass or a pydrake config class (of the
    scenario's schema); empty for any other type."""
    if dataclasses.is_dataclass(schema):
        hints = typing.get_type_hints(schema)
        return {f.name: hints[f.name] for f in dataclasses.fields(schema)}
    return {f.name: f.type for f in getattr(schema, "__fields__", ())}


def is_record(schema: Any) -> bool:
    """Is ``schema`` a group of keys (a dataclass or a pydrake config class)?"""
    return dataclasses.is_dataclass(schema) or hasattr(schema, "__fields__")


def unwrap_optional(schema: Any) -> Any:
    """``X`` for ``Optional[X]``; any other type as it is (a variant of several
    types stays a variant)."""
    if typing.get_origin(schema) is typing.Union:
        options = [a for a in typing.get_args(schema) if a is not type(None)]
        return options[0] if len(options) == 1 else schema
    return schema


def closest_name(name: str, valid: Sequence[str]) -> Optional[str]:
    """The valid name ``name`` was most likely meant to be: a close spelling, or
    one that holds its letters in order (an abbreviation: ``hfov`` for
    ``horizontal_fov``); None when nothing is close."""
    near = difflib.get_close_matches(name, list(valid), n=1, cutoff=0.5)
    if near:
        return near[0]

    def holds(word: str) -> bool:
        letters = iter(word)
        return all(c in letters for c in name)

    abbreviations = sorted((v for v in valid if holds(v)), key=len)
    return abbreviations[0] if abbreviations and len(name) >= 2 else None


def unknown_key_message(where: str, key: str, valid: Sequence[str]) -> str:
    """``WHERE: unknown key 'KEY' (did you mean 'K'?); valid keys: ...``."""
    near = closest_name(key, valid)
    hint = f" (did you mean {near!r}?)" if near else ""
    return f"{where}: unknown key {key!r}{hint}; valid keys: {', '.join(valid)}"


def refusal_message(document: dict, schema: Any, source: str, error: Exception, dump: Any) -> str:
    """One line for a ``document`` that Drake's loader refused with ``error``:
    the first refused key or value by its path in ``source``, or, where no
    single piece is refused, Drake's own first line. ``dump`` turns plain data
    into the YAML text the loader reads."""
    found = _first_refused(document, schema, source, "", _Judge(dump))
    if found:
        return found
    text = str(error).strip()
    first = text.splitlines()[0] if text else type(error).__name__
    return f"{source}: bad value or type: {first}"


class _Judge:
    """Asks Drake's loader whether a record takes one key's value."""

    def __init__(self, dump: Any) -> None:
        self._dump = dump

    def refuses(self, record: Any, key: str, value: Any) -> bool:
        try:
            yaml_load_typed(schema=record, data=self._dump({key: value}), defaults=record())
        except LOADER_ERRORS:
            return True
        return False


def _first_refused(value: Any, schema: Any, source: str, path: str, judge: _Judge) -> Optional[str]:
    """``SOURCE: PATH ...`` for the first piece of ``value`` (of type ``schema``,
    at ``path`` in the document) that the loader refuses; None when every piece
    is taken."""
    fields = schema_fields(schema)
    where = f"{source}: {path}" if path else source
    if not isinstance(value, dict):
        return f"{where} must be a mapping of keys ({', '.join(fields)}), got {_show(value)}"
    for key in value:
        if key not in fields:
            return unknown_key_message(where, str(key), list(fields))
    for key, item in value.items():
        inner = f"{path}.{key}" if path else str(key)
        item_schema = unwrap_optional(fields[key])
        nested = (item is not None and is_record(item_schema)) or (
            isinstance(item, list) and _record_items(item_schema)
        )
        if nested and not judge.refuses(schema, key, item):
            # A mapping (or list of them) the loader takes whole has no refused piece:
            # one question instead of one per key inside it.
            found = None
        elif item is not None and is_record(item_schema):
            found = _first_refused(item, item_schema, source, inner, judge)
        elif isinstance(item, list) and _record_items(item_schema):
            found = _first_refused_item(item, typing.get_args(item_schema)[0], source, inner, judge)
        elif judge.refuses(schema, key, item):
            found = f"{source}: {inner} must be {_expected(item_schema)}, got {_show(item)}"
        else:
            found = None
        if found:
            return found
    return None


def _first_refused_item(
    items: list, item_schema: Any, source: str, path: str, judge: _Judge
) -> Optional[str]:
    for i, item in enumerate(items):
        label = item.get("name", i) if isinstance(item, dict) else i
        found = _first_refused(item, item_schema, source, f"{path}[{label}]", judge)
        if found:
            return found
    return None


def _record_items(schema: Any) -> bool:
    return typing.get_origin(schema) is list and is_record(typing.get_args(schema)[0])


def _expected(schema: Any) -> str:
    """What a value of ``schema`` must be, in words."""
    if schema in _PLAIN:
        return _PLAIN[schema]
    if is_record(schema):
        return f"a mapping of keys ({', '.join(schema_fields(schema))})"
    args = typing.get_args(schema)
    if typing.get_origin(schema) is list:
        return f"a list of {'mappings' if is_record(args[0]) else _PLAIN_PLURAL.get(args[0], 'values')}"
    if typing.get_origin(schema) is typing.Union and all(is_record(a) for a in args):
        forms = [f"!{a.__name__} {{{', '.join(schema_fields(a))}}}" for a in args]
        return "one of " + ", ".join(forms)
    if args and args[0] is np.ndarray:  # pydrake's vector fields of a pose: all Vector3
        return "3 numbers"
    return f"a {getattr(schema, '__name__', schema)}"


def _show(value: Any) -> str:
    tag, body = getattr(value, "tag", None), getattr(value, "value", value)
    return f"{tag} {body!r}" if tag else repr(value)
