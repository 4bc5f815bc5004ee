"""Run All of every lesson, as a student (and nbval) does: each top to bottom in a fresh kernel.

Beside the lessons an empty notebook (one cell, ``pass``) is run the same way, in the same process:
its time is what starting a kernel costs on this machine at this moment.  So is a floor notebook, the
least a lesson does: import numpy, sympy, pyplot and course_lib, draw one small figure, typeset one
formula; the floor's ratio to the empty notebook bounds from below what any lesson can reach.  The
runs go in ``REPEATS`` rounds, each round the empty and floor notebooks then every lesson once, so
that a burst of load from other programs falls on them as much as on the lessons.  Printed: a
table of seconds per lesson (the best of its ``REPEATS`` runs) and the ratio to the empty notebook's
best, then the last line a JSON object with ``slowest_vs_empty``, the slowest lesson's time divided
by the empty notebook's (goal ≤ 2.5), ``slowest`` (its name), ``empty_s``, ``floor_vs_empty`` and
``slowest_vs_floor``.

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
sys.path.insert(0, str(ROOT / "tools"))
from kernels import kernel_manager  # noqa: E402  (the kernels `make execute` starts)


def run_all(notebook: nbformat.NotebookNode, folder: pathlib.Path) -> float:
    """Seconds for one Run All in a fresh kernel, kernel start and shutdown included."""
    start = time.perf_counter()
    manager = kernel_manager()
    try:
        NotebookClient(notebook, km=manager, timeout=600, kernel_name="python3",
                       resources={"metadata": {"path": str(folder)}}).execute()
    finally:  # a manager handed to the client is not shut down by it
        if manager.has_kernel:
            manager.shutdown_kernel(now=True)
    return time.perf_counter() - start


FLOOR = [
    "import numpy as np\nimport sympy as sp\nimport matplotlib.pyplot as plt\n"
    "from IPython.display import Math, display\nfrom course_lib import fourbar, saw",
    "fig, ax = plt.subplots(figsize=(6, 3.5))\nax.plot([0, 1], [0, 1])\nplt.show()",
    "x = sp.symbols('x')\ndisplay(Math(sp.latex(sp.sin(x) ** 2)))",
]


def one_run(path: pathlib.Path | str) -> float:
    """One Run All of the lesson at ``path`` ("empty", "floor": those notebooks) in a fresh kernel."""
    if isinstance(path, str):
        sources = ["pass"] if path == "empty" else FLOOR
        notebook = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(s) for s in sources])
        folder = ROOT / "notebooks"
    else:
        notebook, folder = nbformat.read(path, as_version=4), path.parent
    return run_all(notebook, folder)


def main(argv: list[str]) -> int:
    paths = [pathlib.Path(a).resolve() for a in argv] or sorted((ROOT / "notebooks").glob("[0-9]*.ipynb"))
    runs: dict[str, list[float]] = {"empty": [], "floor": []} | {path.name: [] for path in paths}
    for _ in range(REPEATS):
        runs["empty"].append(one_run("empty"))
        runs["floor"].append(one_run("floor"))
        for path in paths:
            runs[path.name].append(one_run(path))
    empty, floor = min(runs.pop("empty")), min(runs.pop("floor"))
    print(f"{'lesson':48s} {'seconds':>8s} {'× empty':>8s}")
    print(f"{'(empty notebook)':48s} {empty:8.2f} {1.0:8.2f}")
    print(f"{'(floor: imports, one figure, one formula)':48s} {floor:8.2f} {floor / empty:8.2f}")
    times = {name: min(values) for name, values in runs.items()}
    for name, seconds in times.items():
        print(f"{name:48s} {seconds:8.2f} {seconds / empty:8.2f}", flush=True)
    slowest = max(times, key=times.get)
    print(json.dumps({"slowest_vs_empty": round(times[slowest] / empty, 2), "slowest": slowest,
                      "empty_s": round(empty, 2), "floor_vs_empty": round(floor / empty, 2),
                      "slowest_vs_floor": round(times[slowest] / floor, 2)}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
