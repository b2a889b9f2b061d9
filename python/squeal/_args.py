"""Checks of the public functions' arguments: a wrong type raises ``TypeError``, a wrong value
``ValueError``, each naming the function and the argument, what it must be and what it got."""

from __future__ import annotations

import math
import numbers
import os
from typing import Any, Optional, Sequence

from ._squeal import Scene


def _got(v: Any) -> str:
    r = repr(v)
    if len(r) > 60:
        r = r[:57] + "..."
    return f"{type(v).__name__} {r}"


def type_error(func: str, arg: str, expected: str, got: Any) -> TypeError:
    return TypeError(f"{func}: argument `{arg}` must be {expected}, not {_got(got)}")


def value_error(func: str, arg: str, message: str) -> ValueError:
    return ValueError(f"{func}: argument `{arg}`: {message}")


def scene(func: str, v: Any) -> Scene:
    if not isinstance(v, Scene):
        raise type_error(func, "scene", "a squeal.Scene (Scene.from_file, from_toml, from_dict, from_arrays)", v)
    return v


def path(func: str, arg: str, v: Any) -> Optional[str]:
    """None, or a str / os.PathLike as a str."""
    if v is None:
        return None
    if not isinstance(v, (str, os.PathLike)):
        raise type_error(func, arg, "a path (str or os.PathLike) or None", v)
    return os.fspath(v)


def callback(func: str, arg: str, v: Any) -> Any:
    if v is not None and not callable(v):
        raise type_error(func, arg, "a callable receiving one event dict, or None", v)
    return v


def _real(v: Any) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool)


def real(func: str, arg: str, v: Any) -> Optional[float]:
    """None, or a real number (its type only: the value is the library's to check, as for
    ``compare``'s tolerances, which ``CompareOptions::validate`` refuses naming the option)."""
    if v is None:
        return None
    if not _real(v):
        raise type_error(func, arg, "a real number or None", v)
    return float(v)


def number(func: str, arg: str, v: Any, low: Optional[float] = None, high: Optional[float] = None) -> Optional[float]:
    """None, or a finite real number in [low, high]."""
    if v is None:
        return None
    if not _real(v):
        raise type_error(func, arg, "a real number or None", v)
    x = float(v)
    if not math.isfinite(x) or (low is not None and x < low) or (high is not None and x > high):
        bounds = f"[{low if low is not None else '-inf'}, {high if high is not None else 'inf'}]"
        raise value_error(func, arg, f"{x} must be finite and in {bounds}")
    return x


def integer(func: str, arg: str, v: Any, low: int) -> Optional[int]:
    """None, or an int >= low (numpy integers accepted; bool refused)."""
    if v is None:
        return None
    if isinstance(v, bool) or not isinstance(v, numbers.Integral):
        raise type_error(func, arg, f"an int >= {low} or None", v)
    if int(v) < low:
        raise value_error(func, arg, f"{int(v)} must be >= {low}")
    return int(v)


def boolean(func: str, arg: str, v: Any) -> bool:
    if not isinstance(v, bool):
        raise type_error(func, arg, "a bool", v)
    return v


def text(func: str, arg: str, v: Any, choices: Optional[Sequence[str]] = None) -> Optional[str]:
    if v is None:
        return None
    if not isinstance(v, str):
        raise type_error(func, arg, "a str" + (f" (one of {', '.join(choices)})" if choices else ""), v)
    if choices is not None and v not in choices:
        raise value_error(func, arg, f"`{v}` is not one of {', '.join(choices)}")
    return v


def mu_range(func: str, v: Any) -> Optional[tuple]:
    """None, or (first, last, count): finite reals and an int count >= 1 (as ``--mu A:B:N``)."""
    if v is None:
        return None
    if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) != 3:
        raise type_error(func, "mu", "a tuple (first, last, count) or None", v)
    first = number(func, "mu[0] (first)", v[0])
    last = number(func, "mu[1] (last)", v[1])
    count = integer(func, "mu[2] (count)", v[2], 1)
    return (first, last, count)
