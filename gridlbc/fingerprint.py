"""The content of a Python object as hashable data: what :func:`gridlbc.sweep` uses to tell two
user-defined systems (or costs) apart.

:func:`state_record` walks an object's state recursively: numbers, strings, containers, numpy
arrays (by dtype, shape and bytes), dataclasses and objects with a ``__dict__`` or ``__slots__``
(by class and attributes), functions (by code, constants, defaults and closure; not the module
globals they read), classes and modules (by import path). Two objects with equal records built
in the same program compute the same thing, as far as their own state can say. What it cannot
follow (an open file, a compiled extension object without state) raises a :class:`TypeError` that
names the attribute and what to do: give the class a ``parameters()`` method (every constructor
argument that changes what it computes), and record it there.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import types
from typing import Any

import numpy as np

__all__ = ["UnidentifiableError", "digest", "json_default", "state_record"]

_MAX_DEPTH = 40


class UnidentifiableError(TypeError):
    """An object whose state :func:`state_record` cannot follow."""


def _qualified(obj) -> str:
    return f"{getattr(obj, '__module__', '?')}.{getattr(obj, '__qualname__', repr(obj))}"


def digest(record, arrays: dict) -> str:
    """The SHA-256 (hex) of a JSON-ready ``record`` (keys sorted; numpy numbers and arrays in it
    as lists) and of the ``arrays`` it refers to, each by name, dtype, shape and bytes: equal
    for equal records and arrays."""
    h = hashlib.sha256(json.dumps(record, sort_keys=True, default=json_default).encode())
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}:{a.dtype}:{a.shape}".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def json_default(obj):
    """``json.dumps``'s ``default=`` for records that hold numpy numbers and arrays: as lists
    (and Python numbers)."""
    if isinstance(obj, np.generic | np.ndarray):
        return obj.tolist()
    raise TypeError(f"{type(obj).__name__} is not JSON-serialisable")


def state_record(obj, arrays: dict, where: str = "object") -> Any:
    """``obj``'s state as JSON-ready data; its numpy arrays go into ``arrays``.

    Parameters
    ----------
    obj : object
        What to describe (a system, a cost, anything in their attributes).
    arrays : dict
        Receives the arrays met on the way, under names made from ``where`` and the attribute
        path; the record refers to them by those names.
    where : str
        The name of ``obj`` in messages and array names (e.g. ``"system"``).

    Returns
    -------
    object
        Nested lists, dicts, strings and numbers; equal for objects with equal state.

    Raises
    ------
    UnidentifiableError
        Where some attribute's state cannot be followed; the message names it.
    """
    return _record(obj, arrays, where, 0, set())


def _record(obj, arrays, path, depth, active):
    if depth > _MAX_DEPTH:
        raise UnidentifiableError(f"{path}: nested more than {_MAX_DEPTH} levels deep")
    if obj is None or isinstance(obj, bool | int | str):
        return obj
    if isinstance(obj, float | complex):
        return repr(obj)  # NaN and ±inf stay distinct and JSON-safe
    if isinstance(obj, bytes):
        return {"bytes": obj.hex()}
    if isinstance(obj, np.generic):
        return {"scalar": str(obj.dtype), "value": repr(obj.item())}
    if isinstance(obj, np.ndarray):
        if obj.dtype.hasobject:
            return {
                "object_array": list(obj.shape),
                "items": _items(obj.ravel(), arrays, path, depth, active),
            }
        name = f"{path}#{len(arrays)}"
        arrays[name] = obj
        return {"array": name}
    if isinstance(obj, type | types.ModuleType):
        return {"ref": _qualified(obj) if isinstance(obj, type) else obj.__name__}
    if isinstance(obj, np.ufunc | types.BuiltinFunctionType):
        owner = getattr(obj, "__self__", None)
        if owner is not None and not isinstance(owner, types.ModuleType):
            return {
                "builtin_method": obj.__name__,
                "of": _record(owner, arrays, f"{path}.__self__", depth + 1, active),
            }
        return {"ref": f"{getattr(obj, '__module__', None) or ''}.{obj.__name__}"}
    key = id(obj)
    if key in active:
        return {"cycle": type(obj).__qualname__}
    active.add(key)
    try:
        return _compound(obj, arrays, path, depth, active)
    finally:
        active.discard(key)


def _items(items, arrays, path, depth, active):
    return [_record(v, arrays, f"{path}[{i}]", depth + 1, active) for i, v in enumerate(items)]


def _compound(obj, arrays, path, depth, active):
    if isinstance(obj, list | tuple):
        return {type(obj).__name__: _items(obj, arrays, path, depth, active)}
    if isinstance(obj, set | frozenset):
        records = _items(obj, arrays, path, depth, active)
        return {type(obj).__name__: sorted(records, key=repr)}
    if isinstance(obj, dict):
        return {
            "dict": sorted(
                (
                    [
                        _record(k, arrays, f"{path}<key>", depth + 1, active),
                        _record(v, arrays, f"{path}[{k!r}]", depth + 1, active),
                    ]
                    for k, v in obj.items()
                ),
                key=repr,
            )
        }
    if isinstance(obj, types.MethodType):
        return {
            "method": _record(obj.__func__, arrays, path, depth + 1, active),
            "of": _record(obj.__self__, arrays, f"{path}.__self__", depth + 1, active),
        }
    if isinstance(obj, types.FunctionType):
        cells = obj.__closure__ or ()
        return {
            "function": _qualified(obj),
            "code": _code(obj.__code__, arrays, path, depth, active),
            "defaults": _record(obj.__defaults__, arrays, f"{path}<defaults>", depth + 1, active),
            "kwdefaults": _record(
                obj.__kwdefaults__, arrays, f"{path}<kwdefaults>", depth + 1, active
            ),
            "closure": [
                _record(_cell(c), arrays, f"{path}<{name}>", depth + 1, active)
                for name, c in zip(obj.__code__.co_freevars, cells)
            ],
        }
    if isinstance(obj, types.CodeType):
        return _code(obj, arrays, path, depth, active)
    if dataclasses.is_dataclass(obj):
        fields = {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}
        extra = {k: v for k, v in getattr(obj, "__dict__", {}).items() if k not in fields}
        return _instance(obj, {**fields, **extra}, arrays, path, depth, active)
    state = _attributes(obj)
    if state is None:
        raise UnidentifiableError(
            f"{path} is a {type(obj).__qualname__}, whose state cannot be read to tell two of "
            "them apart"
        )
    return _instance(obj, state, arrays, path, depth, active)


def _instance(obj, state, arrays, path, depth, active):
    return {
        "class": _qualified(type(obj)),
        "state": {
            str(k): _record(v, arrays, f"{path}.{k}", depth + 1, active)
            for k, v in sorted(state.items(), key=lambda kv: str(kv[0]))
        },
    }


def _attributes(obj) -> dict | None:
    """An instance's attributes (``__dict__`` and ``__slots__``), or None if it has neither."""
    state: dict = {}
    found = False
    if hasattr(obj, "__dict__") and isinstance(vars(obj), dict):
        state.update(vars(obj))
        found = True
    for cls in type(obj).__mro__:
        slots = cls.__dict__.get("__slots__", ())
        for name in (slots,) if isinstance(slots, str) else slots:
            if name in ("__dict__", "__weakref__"):
                continue
            found = True
            if hasattr(obj, name):
                state[name] = getattr(obj, name)
    return state if found else None


def _cell(cell):
    try:
        return cell.cell_contents
    except ValueError:  # an empty cell (a name not yet bound)
        return None


def _code(code, arrays, path, depth, active):
    return {
        "bytecode": code.co_code.hex(),
        "names": list(code.co_names),
        "consts": [_record(c, arrays, f"{path}<const>", depth + 1, active) for c in code.co_consts],
    }
