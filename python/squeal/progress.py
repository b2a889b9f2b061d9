"""Progress events as tqdm bars."""

from __future__ import annotations

from typing import Any, Dict, Optional


class TqdmProgress:
    """A progress callback drawing each task as a tqdm bar (fractions) or a counter (steps).

    Pass it as ``progress=squeal.TqdmProgress()`` to any computation. Events are dicts with
    ``kind`` (``begin``, ``update``, ``end``, ``info``), ``task`` (an id), ``label``,
    ``message``, ``fraction`` (0..1 or None) and ``bar`` (the task reports fractions).
    ``info`` lines are written with ``tqdm.write`` unless ``info=False``.
    """

    def __init__(self, info: bool = True, **tqdm_kwargs: Any) -> None:
        from tqdm.auto import tqdm  # imported here: tqdm is optional

        self._tqdm = tqdm
        self._bars: Dict[int, Any] = {}
        self._info = info
        self._kwargs = tqdm_kwargs

    def __call__(self, event: Dict[str, Any]) -> None:
        kind, task = event["kind"], event["task"]
        if kind == "begin":
            total: Optional[float] = 1.0 if event["bar"] else None
            fmt = "{l_bar}{bar}| {postfix}" if event["bar"] else "{desc} {postfix}"
            self._bars[task] = self._tqdm(
                total=total, desc=event["label"], bar_format=fmt, leave=False, **self._kwargs
            )
        elif kind == "update":
            bar = self._bars.get(task)
            if bar is not None:
                if event["fraction"] is not None:
                    bar.n = event["fraction"]
                bar.set_postfix_str(event["message"], refresh=True)
        elif kind == "end":
            bar = self._bars.pop(task, None)
            if bar is not None:
                if bar.total is not None:
                    bar.n = bar.total
                bar.set_postfix_str(event["message"], refresh=True)
                bar.close()
        elif kind == "info" and self._info:
            self._tqdm.write(event["message"])

    def close(self) -> None:
        """Closes the bars still open (after an error)."""
        for bar in self._bars.values():
            bar.close()
        self._bars.clear()
