"""Run All of every lesson, as a student (and nbval) does: each top to bottom in a fresh kernel.

Beside the lessons an empty notebook (one cell, ``pass``) is run the same way, in the same process:
its time is what starting a kernel costs on this machine at this moment.  Printed: a table of
seconds per lesson (the best of ``REPEATS`` runs) and the ratio to the empty notebook, then the last
line a JSON object with ``slowest_vs_empty``, the slowest lesson's time divided by the empty
notebook's (goal ≤ 2.5), ``slowest`` (its name) and ``empty_s``.

Usage: python benchmarks/bench_lessons.py [NOTEBOOK ...]   (default: notebooks/[0-9]*.ipynb)
"""

from __future__ import annotations

import json
import pathlib
import sys
import time

import nbformat
from nbclient import NotebookClient

ROOT = pathlib.Path(__file__).resolve().parent.parent
REPEATS = 2


def run_all(notebook: nbformat.NotebookNode, folder: pathlib.Path) -> float:
    """Seconds for one Run All in a fresh kernel, kernel start and shutdown included."""
    start = time.perf_counter()
    NotebookClient(
        notebook, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(folder)}}
    ).execute()
    return time.perf_counter() - start


def best_run(path: pathlib.Path | None) -> float:
    best = float("inf")
    for _ in range(REPEATS):
        if path is None:
            notebook = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("pass")])
            folder = ROOT / "notebooks"
        else:
            notebook, folder = nbformat.read(path, as_version=4), path.parent
        best = min(best, run_all(notebook, folder))
    return best


def main(argv: list[str]) -> int:
    paths = [pathlib.Path(a).resolve() for a in argv] or sorted((ROOT / "notebooks").glob("[0-9]*.ipynb"))
    empty = best_run(None)
    print(f"{'lesson':48s} {'seconds':>8s} {'× empty':>8s}")
    print(f"{'(empty notebook)':48s} {empty:8.2f} {1.0:8.2f}")
    times = {}
    for path in paths:
        times[path.name] = best_run(path)
        print(f"{path.name:48s} {times[path.name]:8.2f} {times[path.name] / empty:8.2f}", flush=True)
    slowest = max(times, key=times.get)
    print(json.dumps({"slowest_vs_empty": round(times[slowest] / empty, 2), "slowest": slowest,
                      "empty_s": round(empty, 2)}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
