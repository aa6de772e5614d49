"""A progress bar with rate and ETA on stderr (a redrawn line on a terminal, a line every 10 % elsewhere)."""
from __future__ import annotations

import sys
import time


def _duration(seconds: float) -> str:
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


class Progress:
    def __init__(self, total: int, done: int = 0, stream=None, enabled: bool = True, width: int = 28):
        self.total, self.done = total, done
        self.stream = stream or sys.stderr
        self.enabled = enabled and total > 0
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.width = width
        self.started = time.monotonic()
        self.failed = self.disagree = 0
        self._drawn = 0.0
        self._first = None
        self._next_line = 0.1
        if self.enabled:
            self.draw(force=True)

    def update(self, record: dict) -> None:
        self.done += 1
        if self._first is None:  # rate and ETA count from the first result (the workers have started)
            self._first = (time.monotonic(), self.done)
        if record.get("agreement") == "failed":
            self.failed += 1
        elif record.get("agreement") == "disagree":
            self.disagree += 1
        self.draw()

    def line(self) -> str:
        frac = self.done / self.total if self.total else 1.0
        filled = int(round(frac * self.width))
        t_first, n_first = self._first or (time.monotonic(), self.done)
        elapsed = time.monotonic() - t_first
        ran = self.done - n_first
        rate = ran / elapsed * 60 if elapsed > 0 and ran > 0 else 0.0
        eta = (self.total - self.done) * elapsed / ran if ran > 0 else None
        bar = "#" * filled + "-" * (self.width - filled)
        text = f"[{bar}] {self.done}/{self.total} {frac:4.0%}  {rate:6.0f} runs/min  "
        text += f"ETA {_duration(eta)}" if eta is not None else "ETA --:--"
        if self.failed or self.disagree:
            text += f"  failed {self.failed}  disagree {self.disagree}"
        return text

    def draw(self, force: bool = False) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        if self.tty:
            if force or now - self._drawn > 0.1 or self.done == self.total:
                self.stream.write("\r" + self.line() + " ")
                self.stream.flush()
                self._drawn = now
        else:
            frac = self.done / self.total
            if force or frac >= self._next_line or self.done == self.total:
                self.stream.write(self.line() + "\n")
                self.stream.flush()
                while self._next_line <= frac:
                    self._next_line += 0.1

    def close(self) -> None:
        if self.enabled and self.tty:
            self.stream.write("\n")
            self.stream.flush()
