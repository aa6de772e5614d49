"""Reading the input files of `cosim simulate --input NAME=FILE`: time against rows, side by side.

Writes input files of 10^4, 10^5 and 10^6 rows (time [s], value; a sine) into a temporary folder
and times, for each, what ``input_signals`` does with a file once the input's name is checked:

* ``csv``: :func:`cosim.fmu.simulate.read_input` of a CSV (numpy's parser; every value checked);
* ``csv, checked rows``: the same file with a comment line after the header, which numpy's parser
  leaves to the row-by-row reader (the one that names a bad cell's file, line and column);
* ``npy``: :func:`read_input` of the same data saved by ``numpy.save``;
* ``merge``: :func:`cosim.fmu.simulate.merge_signals`, the CSV's columns to FMPy's input array.

Times are the best of ``--repeat`` runs [s] (the machine may be shared); the ratio column is the
time of a file ten times longer divided by the time of the shorter one: about 10 where time grows
linearly with the rows, about 100 where it grows with their square. Nothing is asserted::

    python benchmarks/inputs.py            # best of 3
    python benchmarks/inputs.py -n 5
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path


import numpy as np

from cosim.fmu.simulate import merge_signals, read_input

ROWS = (10**4, 10**5, 10**6)
NAME = "T"  # the input's name (the steer torque of the simple bicycles)


def write_inputs(folder: Path, rows: int) -> dict[str, Path]:
    """The three files of ``rows`` rows: plain CSV, CSV with a comment line, NPY."""
    t = np.linspace(0.0, rows * 1e-3, rows)
    data = np.column_stack([t, np.sin(t)])
    plain, commented, npy = folder / f"plain{rows}.csv", folder / f"commented{rows}.csv", folder / f"in{rows}.npy"
    np.savetxt(plain, data, delimiter=",", header=f"time,{NAME}", comments="", fmt="%.17g")
    text = plain.read_text()
    header, _, body = text.partition("\n")
    commented.write_text(f"{header}\n# a comment line: read row by row\n{body}")
    np.save(npy, data)
    return {"csv": plain, "csv, checked rows": commented, "npy": npy}


def best_time(f, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        f()
        times.append(time.perf_counter() - started)
    return min(times)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("-n", "--repeat", type=int, default=3, help="runs per measurement, the best is shown (default 3)")
    args = p.parse_args(argv)
    results: dict[str, list[float]] = {}
    with tempfile.TemporaryDirectory(prefix="cosim-inputs-bench-") as tmp:
        for rows in ROWS:
            files = write_inputs(Path(tmp), rows)
            for label, path in files.items():
                results.setdefault(label, []).append(best_time(lambda: read_input(path, NAME), args.repeat))
            columns = read_input(files["csv"], NAME)
            results.setdefault("merge", []).append(
                best_time(lambda: merge_signals({NAME: columns}, 0.0), args.repeat))
            print(f"  measured {rows:,} rows", file=sys.stderr)
    print(f"best of {args.repeat} runs [s]; ratio = time of 10x the rows / time (about 10: linear)")
    heads = [f"{r:,} rows" for r in ROWS] + [f"ratio 1e{len(str(b)) - 1}/1e{len(str(a)) - 1}"
                                              for a, b in zip(ROWS, ROWS[1:])]
    print(f"{'':20}" + "".join(f"{h:>17}" for h in heads))
    for label, times in results.items():
        ratios = [b / a for a, b in zip(times, times[1:])]
        print(f"{label:20}" + "".join(f"{t:17.4f}" for t in times) + "".join(f"{r:17.1f}" for r in ratios))
    per_million = results["csv"][-1] / (ROWS[-1] / 1e6)
    print(f"csv: {per_million:.2f} s per million rows")
    return 0


if __name__ == "__main__":
    sys.exit(main())
