"""Time to build every exported model from clean, and for a no-op rebuild (side by side, one run)."""
from __future__ import annotations

import tempfile
import time
from pathlib import Path

from cosim.compiler.build import build


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        t0 = time.perf_counter()
        results = build(output=out, jobs=2)
        clean = time.perf_counter() - t0
        t0 = time.perf_counter()
        again = build(output=out, jobs=2)
        noop = time.perf_counter() - t0
        assert all(r.rebuilt for r in results) and not any(r.rebuilt for r in again)
        print(f"models: {len(results)}")
        print(f"clean build:  {clean:7.2f} s")
        print(f"no-op build:  {noop:7.2f} s")
        print(f"ratio clean/no-op: {clean / noop:5.1f}x")


if __name__ == "__main__":
    main()
