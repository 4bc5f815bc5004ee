"""The release's two bundles, as zip archives in ``dist/``: ``make dist``.

Usage: python tools/make_dist.py [--output DIR]

* ``mechanism-kinematics-VERSION-student.zip``: what a student needs to run the lessons and practise —
  the lessons (``notebooks/NN_*.ipynb``), the exercise sets (``notebooks/exercises/``), ``course_lib``,
  ``pyproject.toml``, the student set ``environment.txt``, the licences and the citation, and a short
  ``README.md`` (START HERE) that says how to install and open them.  No solutions, no nbgrader, no
  tests or tools.
* ``mechanism-kinematics-VERSION-instructor.zip``: every file git tracks, solutions and nbgrader included.

Each archive holds one top folder, ``mechanism-kinematics-VERSION/``.  The files are those of the
commit checked out (``--ref``, default HEAD), as git stores them: what is not committed is not released.
Entries are sorted and dated ``date-released`` of CITATION.cff, so a commit gives the same archive
every time; executables keep their mode.  Only git and Python are needed.
"""

from __future__ import annotations

import argparse
import datetime
import pathlib
import re
import subprocess
import sys
import tomllib
import zipfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
NAME = "mechanism-kinematics"
STUDENT_FILES = ["pyproject.toml", "environment.txt", "LICENSE", "LICENSE-content", "CITATION.cff"]
STUDENT_PATTERNS = [re.compile(r"notebooks/\d\d_[^/]+\.ipynb"),
                    re.compile(r"notebooks/exercises/[^/]+\.ipynb"), re.compile(r"course_lib/.+\.py")]

START_HERE = """\
# Mechanism Kinematics, step by step — version {version}

Jupyter lessons on the kinematics of planar mechanisms (a four-bar linkage, the offset slider-crank
of a power saw, a five-bar parallel robot) and `course_lib`, the small library they import.

## Start here

You need Python 3.11, 3.12 or 3.13. In this folder, in a terminal:

```bash
python -m venv .venv
source .venv/bin/activate            # Windows: .venv\\Scripts\\activate
python -m pip install -r environment.txt
jupyter lab notebooks/00_start_here.ipynb
```

`environment.txt` installs the tested versions of everything the lessons use, JupyterLab, and
`course_lib` from this folder. Lesson 00 checks your set-up and shows how to run a lesson.

## What is here

- `notebooks/00_start_here.ipynb` … `notebooks/12_your_own_mechanism.ipynb`: the lessons, read in order.
- `notebooks/exercises/`: the exercise sets. Replace each `None` with your answer and run the check
  cell under it: it tells you what looks wrong (never the answer).
- `course_lib/`: the library the lessons import.

The code (`course_lib` and the notebooks' code cells) is BSD-3-Clause (`LICENSE`); the lesson text and
figures are CC-BY-4.0 (`LICENSE-content`). `CITATION.cff` says how to cite the collection.
"""


def release_date(citation: str) -> datetime.date:
    match = re.search(r"^date-released:\s*\"?(\d{4}-\d\d-\d\d)", citation, re.M)
    if not match:
        raise SystemExit("CITATION.cff has no date-released")
    return datetime.date.fromisoformat(match.group(1))


def committed(ref: str = "HEAD") -> dict[str, tuple[bytes, bool]]:
    """Every file of commit ``ref``: path → (content, executable)."""
    listing = subprocess.run(["git", "ls-tree", "-r", "-z", ref], cwd=ROOT, capture_output=True,
                             check=True).stdout.decode()
    entries = []
    for line in filter(None, listing.split("\0")):
        meta, path = line.split("\t", 1)
        mode, kind, blob = meta.split()
        if kind == "blob":
            entries.append((path, blob, mode == "100755"))
    batch = subprocess.run(["git", "cat-file", "--batch"], cwd=ROOT, capture_output=True, check=True,
                           input="".join(f"{blob}\n" for _, blob, _ in entries).encode()).stdout
    files, at = {}, 0
    for path, _, executable in entries:
        header_end = batch.index(b"\n", at)
        size = int(batch[at:header_end].split()[2])
        files[path] = (batch[header_end + 1: header_end + 1 + size], executable)
        at = header_end + 1 + size + 1
    return files


def tracked(ref: str = "HEAD") -> list[str]:
    """Every file of commit ``ref``, sorted."""
    return sorted(committed(ref))


def student_files(files: list[str]) -> list[str]:
    chosen = [path for path in files if path in STUDENT_FILES
              or any(pattern.fullmatch(path) for pattern in STUDENT_PATTERNS)]
    missing = [path for path in STUDENT_FILES if path not in chosen]
    if missing:
        raise SystemExit(f"the student bundle needs {', '.join(missing)}, which git does not track")
    return chosen


def write_zip(target: pathlib.Path, top: str, entries: dict[str, tuple[bytes, bool]],
              date: datetime.date) -> None:
    stamp = (date.year, date.month, date.day, 0, 0, 0)
    target.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(target, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=9) as archive:
        for path in sorted(entries):
            content, executable = entries[path]
            info = zipfile.ZipInfo(f"{top}/{path}", date_time=stamp)
            info.external_attr = (0o100755 if executable else 0o100644) << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(info, content)


def main(arguments: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=pathlib.Path, default=ROOT / "dist")
    parser.add_argument("--ref", default="HEAD", help="the commit to release (default HEAD)")
    options = parser.parse_args(arguments)
    files = committed(options.ref)
    release = tomllib.loads(files["pyproject.toml"][0].decode())["project"]["version"]
    date = release_date(files["CITATION.cff"][0].decode())
    top = f"{NAME}-{release}"
    student = options.output / f"{top}-student.zip"
    instructor = options.output / f"{top}-instructor.zip"
    chosen = {path: files[path] for path in student_files(sorted(files))}
    chosen["README.md"] = (START_HERE.format(version=release).encode(), False)
    write_zip(student, top, chosen, date)
    write_zip(instructor, top, files, date)
    ignore = options.output / ".gitignore"  # dist/ keeps itself out of git
    if not ignore.exists():
        ignore.write_text("# made by tools/make_dist.py\n*\n")
    for path in (student, instructor):
        with zipfile.ZipFile(path) as archive:
            count = len(archive.namelist())
        print(f"{path.relative_to(ROOT) if path.is_relative_to(ROOT) else path}: {count} files, "
              f"{path.stat().st_size / 1e6:.1f} MB")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
