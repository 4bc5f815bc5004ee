"""Re-run notebooks in place, each top to bottom in a fresh kernel.

Usage: python tools/execute_notebooks.py [--normalize-only] [NOTEBOOK ...]   (default: every lesson)

The committed outputs are then exactly what a fresh run produces, which is what
strict nbval checks.  Cells tagged ``raises-exception`` may fail; any other
error stops with a non-zero exit.

Each file is written as JupyterLab 4 saves it, so that opening a lesson does not mark it
modified: nbformat 4.5 with an id on every cell (existing ids kept, missing ones derived from
the file name, position and source), the kernelspec of ipykernel's ``python3`` kernel, no widget
state, and nbformat's own JSON layout (indent 1, sorted keys, UTF-8 text, a final newline).
``--normalize-only`` does that without running anything.
"""

from __future__ import annotations

import atexit
import hashlib
import json
import os
import pathlib
import re
import shutil
import sys
import tempfile
import time
import warnings

import nbformat
from nbclient import NotebookClient

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from kernels import kernel_manager  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent


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


#: What JupyterLab writes as the kernelspec of a notebook running ipykernel's ``python3`` kernel.
KERNELSPEC = {"display_name": "Python 3 (ipykernel)", "language": "python", "name": "python3"}
_CELL_ID = re.compile(r"^[a-zA-Z0-9_-]{1,64}$")  # nbformat 4.5's rule


def normalize(notebook: nbformat.NotebookNode, name: str) -> nbformat.NotebookNode:
    """The notebook as JupyterLab 4 saves it (in place; returned for convenience).

    Consecutive stream outputs of one cell (stdout, stderr) are merged, so a print comes out the same
    however the kernel flushed it.  Cell ids are kept when valid and unique; a missing one is the first 8
    hex digits of the SHA-1 of the file name, the cell's position and its source, so the same notebook
    always gets the same ids.
    """
    notebook.nbformat, notebook.nbformat_minor = 4, 5
    seen: set[str] = set()
    for index, cell in enumerate(notebook.cells):
        cell_id = cell.get("id")
        if not isinstance(cell_id, str) or not _CELL_ID.match(cell_id) or cell_id in seen:
            salt = 0
            while cell_id is None or cell_id in seen or not _CELL_ID.match(cell_id):
                text = f"{name}\n{index}\n{salt}\n{cell.get('source', '')}"
                cell_id, salt = hashlib.sha1(text.encode("utf-8")).hexdigest()[:8], salt + 1
            cell["id"] = cell_id
        seen.add(cell_id)
    for cell in notebook.cells:  # a print arrives in one or several stream messages, as the kernel flushes
        merged = []
        for output in cell.get("outputs", []):
            if (merged and output.get("output_type") == "stream" and merged[-1].get("output_type") == "stream"
                    and merged[-1].get("name") == output.get("name")):
                merged[-1]["text"] = "".join(merged[-1]["text"]) + "".join(output["text"])
            else:
                merged.append(output)
        if "outputs" in cell:
            cell["outputs"] = merged
    notebook.metadata["kernelspec"] = dict(KERNELSPEC)
    notebook.metadata.pop("widgets", None)  # widget state is regenerated on every run
    return notebook


def read(path: pathlib.Path) -> nbformat.NotebookNode:
    """The notebook, without the random ids nbformat's reader gives cells that have none."""
    text = path.read_text(encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "cell is missing an id field": normalize() gives one
        notebook = nbformat.reads(text, as_version=4)
    for cell, stored in zip(notebook.cells, json.loads(text).get("cells", []), strict=False):
        if "id" not in stored:
            cell.pop("id", None)
    return notebook


def write(notebook: nbformat.NotebookNode, path: pathlib.Path) -> None:
    """Normalize and write as JupyterLab would (nbformat's writer: indent 1, sorted keys, newline)."""
    nbformat.validate(normalize(notebook, path.name))
    nbformat.write(notebook, path)


def execute(path: pathlib.Path) -> float:
    notebook = read(path)
    start = time.perf_counter()
    manager = kernel_manager()
    client = NotebookClient(
        notebook,
        km=manager,
        timeout=600,
        kernel_name="python3",
        resources={"metadata": {"path": str(path.parent)}},
        record_timing=False,
    )
    try:
        client.execute()
    finally:  # a manager handed to the client is not shut down by it
        if manager.has_kernel:
            manager.shutdown_kernel(now=True)
    write(notebook, path)
    return time.perf_counter() - start


def main(argv: list[str]) -> int:
    only_normalize = "--normalize-only" in argv
    argv = [a for a in argv if a != "--normalize-only"]
    paths = [pathlib.Path(a) for a in argv] or sorted((ROOT / "notebooks").glob("*.ipynb"))
    for path in paths:
        shown = path.relative_to(ROOT) if path.is_absolute() and path.is_relative_to(ROOT) else path
        if only_normalize:
            write(read(path), path)
            print(f"normalized {shown}")
        else:
            seconds = execute(path)
            print(f"executed {shown}  ({seconds:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
