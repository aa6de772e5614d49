"""Progress of the long `cosim` verbs on stderr, and the verbosity of every verb (``-q``/``-v``).

One :class:`Reporter` serves every verb. On a terminal it keeps one line, ``[3/7] fig9``
(the count and the current item) or ``42% t = 4.2 s`` (a run in time), redrawn in place with
``\\r``, cut to the terminal width and cleared at the end, so the results printed afterwards
stand alone. Elsewhere (a pipe, a log file) it prints one plain line per item as it starts,
``cosim figures: [3/7] fig9``, and nothing for the fraction of a run. ``-q`` shows nothing;
``-v`` adds detail lines (per-item timing, the paths written).

The code that does the work reports to :func:`active`, the reporter of the running command (a
silent one outside the command line), so that the library functions keep their signatures.
Only the process that made the reporter writes: a worker process forked from it (the pools of
``build -j`` and ``figures -j``) stays silent, and the parent reports each result as it arrives.
"""
from __future__ import annotations

import contextlib
import os
import sys
import threading
import time

#: Verbosity levels: ``-q``, the default, ``-v``.
QUIET, NORMAL, VERBOSE = 0, 1, 2

#: Shortest time [s] between two redraws of a fraction (at most 10 updates per second).
INTERVAL = 0.1


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):  # no isatty, or a closed stream
        return False


def _width(stream) -> int:
    """Columns of the terminal ``stream`` writes to (80 if it cannot be asked)."""
    try:
        return os.get_terminal_size(stream.fileno()).columns or 80
    except (AttributeError, ValueError, OSError):
        return 80


class Reporter:
    """Progress and detail lines of one command on ``stream`` (default: ``sys.stderr``).

    Parameters
    ----------
    verb : str
        The command, named in the plain lines (``cosim VERB: ...``).
    level : int
        :data:`QUIET`, :data:`NORMAL` or :data:`VERBOSE`.
    stream : file, optional
        Where to write (default: ``sys.stderr`` when the reporter is made).
    """

    def __init__(self, verb: str, level: int = NORMAL, stream=None):
        self.verb, self.level = verb, level
        self.stream = sys.stderr if stream is None else stream
        self.tty = _is_terminal(self.stream)
        self._phases: list[list] = []  # [total, count, "[count/total] item", plain lines] per open phase
        self._pid = os.getpid()
        self._lock = threading.Lock()
        self._shown = 0  # characters of the progress line now on the terminal
        self._drawn = -INTERVAL  # time.monotonic() of the last redraw of a fraction
        self._started = time.monotonic()

    @property
    def quiet(self) -> bool:
        """True with ``-q``: no progress, no informational lines."""
        return self.level <= QUIET

    @property
    def verbose(self) -> bool:
        """True with ``-v``: detail lines too."""
        return self.level >= VERBOSE

    @contextlib.contextmanager
    def steps(self, total: int, plain: bool = True):
        """Count ``total`` items while the block runs. A phase opened inside another one (the
        builds of a demo step) shows after its parent's item on the terminal, ``[1/4] build >
        [3/7] Bicycle.Bicycles.Whipple``; plain lines come from the outermost phase only, and
        only if ``plain`` and it has more than one item (one item is said by the verb's result)."""
        with self._lock:
            self._phases.append([total, 0, "", plain and total > 1 and not self._phases])
        try:
            yield self
        finally:
            with self._lock:
                self._phases.pop()
                if self._phases:
                    self._draw(self._text())
                else:
                    self._clear()

    def item(self, name: str) -> None:
        """The next item of the current phase has started (or, in a pool, has just finished)."""
        with self._lock:
            if not self._phases:
                self._phases.append([0, 0, "", False])
            phase = self._phases[-1]
            phase[1] += 1
            phase[2] = f"[{phase[1]}/{phase[0]}] {name}" if phase[0] else name
            self._started = time.monotonic()
            if self.tty:
                self._draw(self._text())
            elif phase[3]:
                self._line(phase[2])

    def fraction(self, done: float, text: str = "") -> None:
        """A fraction ``done`` (0..1) of a long step, e.g. of a run's stop time: on a terminal
        only, redrawn at most every :data:`INTERVAL` seconds (cheap to call from a loop)."""
        if not self.tty or self.quiet:
            return
        now = time.monotonic()
        if now - self._drawn < INTERVAL and done < 1.0:
            return
        self._drawn = now
        with self._lock:
            self._draw(self._text(f"{max(0.0, min(1.0, done)):4.0%} {text}".rstrip()))

    def detail(self, text: str) -> None:
        """A line shown with ``-v`` only (the progress line is redrawn after it)."""
        if self.verbose:
            with self._lock:
                self._line(text)

    def elapsed(self) -> float:
        """Seconds [s] since the current item started."""
        return time.monotonic() - self._started

    def clear(self) -> None:
        """Take the progress line off the terminal before other output (it comes back with the
        next item or fraction)."""
        with self._lock:
            self._clear()

    def close(self) -> None:
        """Clear the progress line, so that what follows starts on a clean line."""
        with self._lock:
            self._clear()
            self._phases.clear()

    # -- writing -------------------------------------------------------------------------------

    def _write(self, text: str) -> None:
        if self.quiet or os.getpid() != self._pid:  # a worker forked from the reporting process
            return
        try:
            self.stream.write(text)
            self.stream.flush()
        except (OSError, ValueError):  # stderr closed or gone: progress is not worth an error
            self.level = QUIET

    def _text(self, last: str = "") -> str:
        """The progress line: each open phase's current item, then ``last``."""
        return " > ".join([phase[2] for phase in self._phases if phase[2]] + ([last] if last else []))

    def _draw(self, text: str) -> None:
        if not self.tty:
            return
        width = _width(self.stream) - 1  # the last column would wrap on some terminals
        text = text if len(text) <= width else "..." + text[len(text) - max(0, width - 3):]  # the current item stays
        pad = " " * max(0, self._shown - len(text))
        self._write(f"\r{text}{pad}")
        self._shown = len(text)

    def _clear(self) -> None:
        if self._shown:
            self._write("\r" + " " * self._shown + "\r")
            self._shown = 0

    def _line(self, text: str) -> None:
        self._clear()
        self._write(f"cosim {self.verb}: {text}\n")


_silent = Reporter("cosim", QUIET)
_active = _silent


def active() -> Reporter:
    """The reporter of the running command (a silent one when none runs)."""
    return _active


@contextlib.contextmanager
def reporting(reporter: Reporter):
    """Make ``reporter`` the :func:`active` one while the block runs; its line is cleared at the end."""
    global _active
    previous, _active = _active, reporter
    try:
        yield reporter
    finally:
        _active = previous
        reporter.close()
