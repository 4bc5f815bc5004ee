"""Re-run notebooks in place, each top to bottom in a fresh kernel.

Usage: python tools/execute_notebooks.py [NOTEBOOK ...]   (default: every lesson)

The committed outputs are then exactly what a fresh run produces, which is what
strict nbval checks.  Cells tagged ``raises-exception`` may fail; any other
error stops with a non-zero exit.
"""

from __future__ import annotations

import atexit
import os
import pathlib
import shutil
import sys
import tempfile
import time

import nbformat
from nbclient import NotebookClient

ROOT = pathlib.Path(__file__).resolve().parent.parent
os.environ.setdefault("PYTHONHASHSEED", "0")  # kernels inherit it: sympy takes the same route every run


def _short_tracebacks() -> None:
    """Kernels started from here print an error as its name and message only ("Minimal" mode).

    A lesson's deliberate errors then show the library's message without file paths and line
    numbers of the machine that ran it (nbval ignores tracebacks, so this changes no comparison).
    """
    if "IPYTHONDIR" in os.environ:
        return
    ipython_dir = pathlib.Path(tempfile.mkdtemp(prefix="course-ipython-"))
    (ipython_dir / "profile_default").mkdir()
    (ipython_dir / "profile_default" / "ipython_kernel_config.py").write_text(
        'c.InteractiveShell.xmode = "Minimal"\n'
    )
    os.environ["IPYTHONDIR"] = str(ipython_dir)
    atexit.register(shutil.rmtree, ipython_dir, ignore_errors=True)


_short_tracebacks()


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
