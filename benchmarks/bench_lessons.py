"""Run All of every lesson, as a student (and nbval) does: each top to bottom in a fresh kernel.

Beside the lessons an empty notebook (one cell, ``pass``) is run the same way, in the same process:
its time is what starting a kernel costs on this machine at this moment.  The runs go in ``REPEATS``
rounds, each round the empty notebook then every lesson once, so that a burst of load from other
programs falls on the empty notebook as much as on the lessons.  Printed: a table of seconds per
lesson (the best of its ``REPEATS`` runs) and the ratio to the empty notebook's best, then the last
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
REPEATS = 3


def run_all(notebook: nbformat.NotebookNode, folder: pathlib.Path) -> float:
    """Seconds for one Run All in a fresh kernel, kernel start and shutdown included."""
    start = time.perf_counter()
    NotebookClient(
        notebook, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(folder)}}
    ).execute()
    return time.perf_counter() - start


def one_run(path: pathlib.Path | None) -> float:
    """One Run All of the lesson at ``path`` (``None``: the empty notebook) in a fresh kernel."""
    if path is None:
        notebook = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("pass")])
        folder = ROOT / "notebooks"
    else:
        notebook, folder = nbformat.read(path, as_version=4), path.parent
    return run_all(notebook, folder)


def main(argv: list[str]) -> int:
    paths = [pathlib.Path(a).resolve() for a in argv] or sorted((ROOT / "notebooks").glob("[0-9]*.ipynb"))
    runs: dict[str, list[float]] = {"": []} | {path.name: [] for path in paths}
    for _ in range(REPEATS):
        runs[""].append(one_run(None))
        for path in paths:
            runs[path.name].append(one_run(path))
    empty = min(runs.pop(""))
    print(f"{'lesson':48s} {'seconds':>8s} {'× empty':>8s}")
    print(f"{'(empty notebook)':48s} {empty:8.2f} {1.0:8.2f}")
    times = {name: min(values) for name, values in runs.items()}
    for name, seconds in times.items():
        print(f"{name:48s} {seconds:8.2f} {seconds / empty:8.2f}", flush=True)
    slowest = max(times, key=times.get)
    print(json.dumps({"slowest_vs_empty": round(times[slowest] / empty, 2), "slowest": slowest,
                      "empty_s": round(empty, 2)}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
