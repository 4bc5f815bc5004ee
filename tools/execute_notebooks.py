"""Re-run notebooks in place, each top to bottom in a fresh kernel.

Usage: python tools/execute_notebooks.py [NOTEBOOK ...]   (default: every lesson)

The committed outputs are then exactly what a fresh run produces, which is what
strict nbval checks.  Cells tagged ``raises-exception`` may fail; any other
error stops with a non-zero exit.
"""

from __future__ import annotations

import os
import pathlib
import sys
import time

import nbformat
from nbclient import NotebookClient

ROOT = pathlib.Path(__file__).resolve().parent.parent
os.environ.setdefault("PYTHONHASHSEED", "0")  # kernels inherit it: sympy takes the same route every run


def execute(path: pathlib.Path) -> float:
    notebook = nbformat.read(path, as_version=4)
    start = time.perf_counter()
    client = NotebookClient(
        notebook,
        timeout=600,
        kernel_name="python3",
        resources={"metadata": {"path": str(path.parent)}},
        record_timing=False,
    )
    client.execute()
    notebook.metadata.pop("widgets", None)  # widget state is regenerated on every run
    nbformat.write(notebook, path)
    return time.perf_counter() - start


def main(argv: list[str]) -> int:
    paths = [pathlib.Path(a) for a in argv] or sorted((ROOT / "notebooks").glob("*.ipynb"))
    for path in paths:
        seconds = execute(path)
        print(f"executed {path.relative_to(ROOT) if path.is_absolute() else path}  ({seconds:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
