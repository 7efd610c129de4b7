r"""Safe YAML reading with line numbers, and one-line error messages that point at them.

Generic for every YAML file ecoplan reads (scenarios, vehicle files, map metadata): the
document is read with PyYAML's safe loader only, aliases are expanded in a bounded way
(alias bombs and recursive aliases are rejected before any Python object is built),
duplicate keys are errors, and the line of every node is kept in a :class:`LineMap` so
that a schema error (a pydantic :class:`~pydantic.ValidationError`) becomes one line
naming the file, the line, the field and what was expected::

    scenarios/ab.yaml:14: speed.v_mps: expected a number > 0; got -0.5

>>> data, lines = read_yaml("a: 1\nb:\n  c: 1e-3\n", "x.yaml")
>>> data, lines.line(("b", "c"))
({'a': 1, 'b': {'c': 0.001}}, 3)
"""

from __future__ import annotations

import re
import types
import typing
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Annotated, Any, Union

import yaml
from pydantic import BaseModel, ValidationError

from ecoplan.errors import InputError

__all__ = [
    "MAX_YAML_DEPTH",
    "MAX_YAML_NODES",
    "LineMap",
    "dotted",
    "error_at",
    "format_validation",
    "one_line",
    "read_text",
    "read_yaml",
]

#: Largest number of YAML nodes after alias expansion (defence against alias bombs).
MAX_YAML_NODES = 200_000
#: Largest nesting depth of a YAML document.
MAX_YAML_DEPTH = 64

#: A node's address in the document: its keys and list indices from the root.
KeyPath = tuple[str | int, ...]


class LineMap:
    """Line (1-based) of every node of a document, by its path of keys and indices."""

    def __init__(self) -> None:
        self.lines: dict[KeyPath, int] = {}

    def line(self, path: Sequence[str | int]) -> int | None:
        """Line of ``path`` or of its longest existing prefix.

        Parameters
        ----------
        path : sequence of str or int
            Keys and list indices from the document root.

        Returns
        -------
        int or None
            The 1-based line, None for an empty map.
        """
        p = tuple(path)
        while p:
            if p in self.lines:
                return self.lines[p]
            p = p[:-1]
        return self.lines.get((), None)


def one_line(text: str, limit: int = 160) -> str:
    r"""Collapse whitespace and cut ``text`` to ``limit`` characters.

    Parameters
    ----------
    text : str
        Any message.
    limit : int
        Largest length of the result.

    Returns
    -------
    str
        The message on one line.

    Examples
    --------
    >>> one_line("a\n  b")
    'a b'
    """
    flat = " ".join(text.split())
    return flat if len(flat) <= limit else flat[: limit - 3] + "..."


def dotted(loc: Sequence[str | int]) -> str:
    """Write a key path as ``a.b[2].c``.

    Parameters
    ----------
    loc : sequence of str or int
        Keys and list indices.

    Returns
    -------
    str
        The dotted path, ``"(top level)"`` when empty.

    Examples
    --------
    >>> dotted(["map", "obstacles", 2, "circle"])
    'map.obstacles[2].circle'
    """
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out or "(top level)"


def error_at(
    source: str,
    lines: LineMap,
    loc: Sequence[str | int],
    msg: str,
    error: type[InputError] = InputError,
) -> InputError:
    """An error whose one-line message names the file, the line and the field.

    Parameters
    ----------
    source : str
        File name (or ``"<string>"``).
    lines : LineMap
        Lines of the document.
    loc : sequence of str or int
        The field's key path.
    msg : str
        What is wrong.
    error : type of InputError
        The exception class to build.

    Returns
    -------
    InputError
        ``error("<source>:<line>: <field>: <msg>")``, to be raised by the caller.
    """
    line = lines.line(loc)
    where = f"{source}:{line}" if line is not None else source
    return error(one_line(f"{where}: {dotted(loc)}: {msg}", limit=400))


def read_text(
    path: str | Path,
    max_bytes: int,
    error: type[InputError] = InputError,
    kind: str = "file",
) -> str:
    """Read a UTF-8 text file of at most ``max_bytes`` bytes.

    Parameters
    ----------
    path : str or Path
        The file.
    max_bytes : int
        Largest size accepted [bytes].
    error : type of InputError
        The exception class raised.
    kind : str
        What the file is, for the messages (``"scenario file"``).

    Returns
    -------
    str
        The file's text.

    Raises
    ------
    InputError
        Missing, unreadable, too large or not UTF-8 (as ``error``).
    """
    p = Path(path)
    try:
        if not p.is_file():
            raise error(f"{p}: no such {kind}")
        size = p.stat().st_size
        if size > max_bytes:
            raise error(f"{p}: file too large ({size} bytes; at most {max_bytes})")
        raw = p.read_bytes()
    except OSError as exc:
        raise error(f"{p}: cannot read: {exc.strerror or exc}") from None
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"{p}: not UTF-8 text (byte {exc.start})") from None


def _check_size(root: yaml.Node, error: type[InputError]) -> None:
    """Reject recursive aliases, too deep documents and alias bombs (expanded size)."""
    sizes: dict[int, int] = {}
    active: set[int] = set()

    def size(node: yaml.Node, depth: int) -> int:
        key = id(node)
        if key in sizes:
            return sizes[key]
        if key in active:
            raise error("recursive YAML alias (an anchor used inside itself)")
        if depth > MAX_YAML_DEPTH:
            raise error(f"YAML nested deeper than {MAX_YAML_DEPTH} levels")
        active.add(key)
        total = 1
        if isinstance(node, yaml.SequenceNode):
            for child in node.value:
                total += size(child, depth + 1)
                if total > MAX_YAML_NODES:
                    break
        elif isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                total += size(k, depth + 1) + size(v, depth + 1)
                if total > MAX_YAML_NODES:
                    break
        active.discard(key)
        if total > MAX_YAML_NODES:
            raise error(
                f"YAML document expands to more than {MAX_YAML_NODES} nodes "
                "(too many aliases: an alias bomb?)"
            )
        sizes[key] = total
        return total

    size(root, 0)


def _record_lines(node: yaml.Node, path: KeyPath, out: LineMap, error: type[InputError]) -> None:
    out.lines.setdefault(path, node.start_mark.line + 1)
    if isinstance(node, yaml.SequenceNode):
        for i, child in enumerate(node.value):
            _record_lines(child, (*path, i), out, error)
    elif isinstance(node, yaml.MappingNode):
        seen: set[str] = set()
        for k, v in node.value:
            if isinstance(k, yaml.ScalarNode):
                if k.value in seen and k.value != "<<":
                    raise error(
                        f"{k.start_mark.line + 1}: duplicate key {k.value!r} in "
                        f"{dotted(path)} (YAML would silently keep the last one)"
                    )
                seen.add(k.value)
                # the key's own line, so "unknown key" points at it
                out.lines.setdefault((*path, k.value), k.start_mark.line + 1)
                _record_lines(v, (*path, k.value), out, error)


class _SafeLoader(yaml.SafeLoader):
    """PyYAML's safe loader, also reading ``1e-3`` as a float (YAML 1.2; 1.1 needs ``1.0e-3``)."""


_SafeLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


def read_yaml(
    text: str, source: str, error: type[InputError] = InputError, kind: str = "file"
) -> tuple[Any, LineMap]:
    """Parse one YAML document safely; return the data and the line of every node.

    Parameters
    ----------
    text : str
        The YAML document.
    source : str
        Name used in error messages (a file path).
    error : type of InputError
        The exception class raised (e.g. :class:`~ecoplan.errors.ScenarioError`).
    kind : str
        What the document is, for the messages (``"scenario file"``).

    Returns
    -------
    data : Any
        Plain Python data (dicts, lists, scalars).
    lines : LineMap
        Line of every node by its key path.

    Raises
    ------
    InputError
        Invalid YAML, an empty document, duplicate keys, recursive aliases, alias bombs or
        too deep nesting, as ``error`` with a one-line message naming file and line.
    """
    try:
        loader = _SafeLoader(text)
    except yaml.YAMLError as exc:  # e.g. a control character: the reader checks first
        raise error(f"{source}: invalid YAML: {one_line(str(exc))}") from None
    try:
        try:
            node = loader.get_single_node()
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line = f":{mark.line + 1}" if mark is not None else ""
            problem = exc.problem or exc.context or "invalid YAML"
            raise error(f"{source}{line}: invalid YAML: {problem}") from None
        except yaml.YAMLError as exc:
            raise error(f"{source}: invalid YAML: {one_line(str(exc))}") from None
        except RecursionError:
            raise error(f"{source}: YAML nested too deeply") from None
        if node is None:
            raise error(f"{source}: empty {kind}; expected a mapping")
        try:
            _check_size(node, error)
        except InputError as exc:
            raise error(f"{source}: {exc}") from None
        lines = LineMap()
        try:
            _record_lines(node, (), lines, error)
        except InputError as exc:
            raise error(f"{source}:{exc}") from None
        try:
            data = loader.construct_document(node)
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line = f":{mark.line + 1}" if mark is not None else ""
            problem = exc.problem or exc.context or "invalid value"
            raise error(f"{source}{line}: invalid YAML value: {problem}") from None
        except (yaml.YAMLError, ValueError, TypeError, OverflowError, RecursionError) as exc:
            why = one_line(str(exc))
            if "integer string conversion" in why:
                why = "an integer with more than 4300 digits"
            raise error(f"{source}: invalid YAML value: {why}") from None
    finally:
        loader.dispose()
    return data, lines


# --------------------------------------------------------------- pydantic -> message


def _unwrap(tp: Any) -> Any:
    """The model class inside ``X | None``, ``list[X]``, ``Annotated[X, ...]``."""
    while True:
        origin = typing.get_origin(tp)
        if origin is Annotated:
            tp = typing.get_args(tp)[0]
        elif origin in (Union, types.UnionType):
            args = [a for a in typing.get_args(tp) if a is not type(None)]
            tp = args[0] if len(args) == 1 else tp
            if len(args) != 1:
                return tp
        elif origin is list:
            tp = typing.get_args(tp)[0]
        else:
            return tp


def _model_at(root: type[BaseModel], loc: Sequence[str | int]) -> type[BaseModel] | None:
    model: Any = root
    for part in loc:
        if isinstance(part, int):
            continue
        if not (isinstance(model, type) and issubclass(model, BaseModel)):
            return None
        field = model.model_fields.get(part)
        if field is None:
            return None
        model = _unwrap(field.annotation)
    return model if isinstance(model, type) and issubclass(model, BaseModel) else None


_EXPECTED = {
    "float_type": "expected a number",
    "int_type": "expected an integer",
    "string_type": "expected a string",
    "bool_type": "expected true or false",
    "list_type": "expected a list",
    "dict_type": "expected a mapping",
    "model_type": "expected a mapping",
    "model_attributes_type": "expected a mapping",
    "finite_number": "expected a finite number",
}


def _describe(err: Mapping[str, Any]) -> str:
    kind = str(err.get("type", ""))
    ctx = err.get("ctx") or {}
    if kind in _EXPECTED:
        return _EXPECTED[kind]
    bounds = {
        "greater_than": ">",
        "greater_than_equal": ">=",
        "less_than": "<",
        "less_than_equal": "<=",
    }
    if kind in bounds:
        limit = next(iter(ctx.values()), "?")
        return f"expected a number {bounds[kind]} {limit}"
    if kind == "literal_error":
        return f"expected one of {ctx.get('expected', '?')}"
    if kind in ("too_short", "too_long"):
        n = ctx.get("min_length") if kind == "too_short" else ctx.get("max_length")
        word = "at least" if kind == "too_short" else "at most"
        return f"expected {word} {n} items"
    if kind == "value_error":
        return str(err.get("msg", "")).removeprefix("Value error, ")
    return str(err.get("msg", "invalid value")).lower()


def _short_repr(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def format_validation(
    exc: ValidationError, source: str, lines: LineMap, root: type[BaseModel]
) -> str:
    """One line for a pydantic validation error: file, line, field, expectation, value.

    Of several errors the most telling one is reported (an unknown key, often a typo,
    explains more than the "missing" error it causes) and the others are counted.

    Parameters
    ----------
    exc : pydantic.ValidationError
        The error of ``root.model_validate(data)``.
    source : str
        File name for the message.
    lines : LineMap
        Lines of the document the data came from.
    root : type of pydantic.BaseModel
        The validated model, to list the accepted keys of a section.

    Returns
    -------
    str
        ``"<source>:<line>: <field>: <what was expected>; got <value>"``.
    """
    rank = {"extra_forbidden": 0, "missing": 2}
    errors = sorted(exc.errors(include_url=False), key=lambda e: rank.get(e["type"], 1))
    err = errors[0]
    loc = [p for p in err["loc"] if isinstance(p, str | int)]
    line = lines.line(loc)
    where = f"{source}:{line}" if line is not None else source
    kind = err["type"]
    if kind == "extra_forbidden":
        parent = loc[:-1]
        model = _model_at(root, parent)
        accepted = f"; accepted: {', '.join(model.model_fields)}" if model else ""
        msg = f"unknown key {loc[-1]!r} in {dotted(parent)}{accepted}"
    elif kind == "missing":
        msg = f"{dotted(loc[:-1])}: missing required key {loc[-1]!r}"
    else:
        msg = f"{dotted(loc)}: {_describe(err)}"
        if kind != "value_error" and "input" in err:
            msg += f"; got {_short_repr(err['input'])}"
    more = len(errors) - 1
    suffix = f" (and {more} more error{'s' if more > 1 else ''})" if more else ""
    return one_line(f"{where}: {msg}{suffix}", limit=400)
