"""Progress of long calls: a bar on a terminal (tqdm's look, on stderr), nothing
elsewhere, or a callback a notebook hands in."""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from typing import Any, Callable, Optional, Union


@dataclass(frozen=True)
class Progress:
    """How far a long call has got: ``done`` of ``total`` ``unit``s after ``elapsed_s``
    seconds; ``then`` says what is under way once every unit is done (e.g. the report's
    landscapes and limits), else ``None``."""

    done: int
    total: int
    unit: str
    elapsed_s: float
    then: Optional[str] = None

    @property
    def fraction(self) -> float:
        """The share done, in ``[0, 1]``."""
        return 1.0 if self.total == 0 else min(1.0, self.done / self.total)

    @property
    def left_s(self) -> Optional[float]:
        """Seconds left at the throughput so far, when it can be told."""
        if self.done == 0 or self.elapsed_s <= 0:
            return None
        return max(0, self.total - self.done) * self.elapsed_s / self.done


ProgressCallback = Callable[[Progress], Any]
"""Called about ten times a second with a :class:`Progress` (and once at the start and
at the end)."""

ProgressOption = Union[bool, ProgressCallback, None]


def _duration(seconds: float) -> str:
    s = int(round(max(0.0, seconds)))
    return f"{s} s" if s < 60 else f"{s // 60} min {s % 60:02d} s"


class Bar:
    """A one-line text bar on a stream (stderr), redrawn in place."""

    WIDTH = 24

    def __init__(self, label: str, stream: Any = None) -> None:
        self.label = label
        self.stream = stream if stream is not None else sys.stderr
        self.shown = False

    def __call__(self, p: Progress) -> None:
        filled = int(self.WIDTH * p.fraction)
        bar = "#" * filled + "-" * (self.WIDTH - filled)
        if p.then is not None and p.done >= p.total:
            status = f"{_duration(p.elapsed_s)}; {p.then}"
        elif p.left_s is not None:
            status = f"{_duration(p.elapsed_s)} < {_duration(p.left_s)} left"
        else:
            status = _duration(p.elapsed_s)
        line = (
            f"{self.label}: {100 * p.fraction:3.0f}%|{bar}| {p.done}/{p.total} {p.unit}s [{status}]"
        )
        self.stream.write("\r" + line[:110].ljust(110))
        self.stream.flush()
        self.shown = True

    def close(self) -> None:
        if self.shown:
            self.stream.write("\n")
            self.stream.flush()


class Reporter:
    """What a long call reports progress to, from its ``progress=`` option: ``True`` (a
    bar when stderr is a terminal), ``False``/``None`` (nothing) or a callback."""

    def __init__(self, option: ProgressOption, label: str, unit: str) -> None:
        self.unit = unit
        self.bar: Optional[Bar] = None
        self.callback: Optional[ProgressCallback] = None
        if callable(option):
            self.callback = option
        elif option is True:
            isatty = getattr(sys.stderr, "isatty", None)
            if isatty is not None and isatty():
                self.bar = Bar(label)
                self.callback = self.bar
        elif option not in (False, None):
            raise TypeError("progress: True, False or a callable taking a trustcbr.Progress")
        self.started = time.monotonic()

    def native(self) -> Optional[Callable[[int, int, float, Optional[str]], None]]:
        """The callback the extension calls, ``f(done, total, elapsed_s, then)``."""
        callback = self.callback
        if callback is None:
            return None
        unit = self.unit

        def report(done: int, total: int, elapsed_s: float, then: Optional[str]) -> None:
            callback(Progress(done, total, unit, elapsed_s, then))

        return report

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
