"""The release's two bundles, as zip archives in ``dist/``: ``make dist``.

Usage: python tools/make_dist.py [--output DIR]

* ``mechanism-kinematics-VERSION-student.zip``: what a student needs to run the lessons and practise —
  the lessons (``notebooks/NN_*.ipynb``), the exercise sets (``notebooks/exercises/``), ``course_lib``,
  ``pyproject.toml``, the student set ``environment.txt`` and its lock ``environment.lock``, the licences
  and the citation, and a short ``README.md`` (START HERE) that says how to install and open them.  No
  solutions, no nbgrader, no tests or tools.
* ``mechanism-kinematics-VERSION-instructor.zip``: every file git tracks, solutions and nbgrader included.

Each archive holds one top folder, ``mechanism-kinematics-VERSION/``.  The files are those of the
commit checked out (``--ref``, default HEAD), as git stores them: what is not committed is not released.
Entries are sorted and dated ``date-released`` of CITATION.cff, so a commit gives the same archive
every time; executables keep their mode.  Only git and Python are needed.

Nothing is written unless the release is sound: ``--ref`` names a commit (never an option), the
``[project] version`` of its pyproject.toml is a PEP 440 version in its normal form, equal to
``course_lib.__version__`` of the same commit, every archive entry stays inside the bundle's folder,
and ``--output`` is a folder (or not there yet).  Otherwise the tool says which setting is wrong, and
how, and exits with status 2.
"""

from __future__ import annotations

import argparse
import ast
import contextlib
import datetime
import os
import pathlib
import re
import subprocess
import sys
import tomllib
import zipfile

try:
    from packaging.version import InvalidVersion, Version
except ImportError:  # pragma: no cover - packaging comes with pip's environments; the regex alone then
    Version = None

ROOT = pathlib.Path(__file__).resolve().parent.parent
NAME = "mechanism-kinematics"
STUDENT_FILES = ["pyproject.toml", "environment.txt", "environment.lock", "LICENSE", "LICENSE-content",
                 "CITATION.cff"]
STUDENT_PATTERNS = [re.compile(r"notebooks/\d\d_[^/]+\.ipynb"),
                    re.compile(r"notebooks/exercises/[^/]+\.ipynb"),
                    re.compile(r"course_lib/.+\.(?:py|json|txt)")]  # the library and its package data
# a PEP 440 public version in its normal form (PEP 440, appendix B, without the spellings normalisation
# would rewrite): 1.0.0, 2.1rc1, 1.0.post2, 3.0.dev4, 1!2.0
VERSION = re.compile(r"(?:[1-9][0-9]*!)?(?:0|[1-9][0-9]*)(?:\.(?:0|[1-9][0-9]*))*"
                     r"(?:(?:a|b|rc)(?:0|[1-9][0-9]*))?(?:\.post(?:0|[1-9][0-9]*))?(?:\.dev(?:0|[1-9][0-9]*))?",
                     re.ASCII)


class ReleaseError(Exception):
    """The release cannot be made as asked (the message names the setting and its value)."""

START_HERE = """\
# Mechanism Kinematics, step by step — version {version}

Jupyter lessons on the kinematics of planar mechanisms (a four-bar linkage, the offset slider-crank
of a power saw, a five-bar parallel robot) and `course_lib`, the small library they import.

## Start here

You need Python 3.11, 3.12 or 3.13. In this folder, in a terminal:

```bash
python3 -m venv .venv                # Windows: py -m venv .venv
source .venv/bin/activate            # Windows: .venv\\Scripts\\activate
python -m pip install -c environment.lock -r environment.txt
jupyter lab notebooks/00_start_here.ipynb
```

The install needs the internet once: it downloads about 140 MB. `environment.txt` installs the tested
versions of everything the lessons use, JupyterLab, and `course_lib` from this folder; `environment.lock`
holds every package they pull in to the version the collection was tested with. Lesson 00 checks your
set-up and shows how to run a lesson.

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
        raise ReleaseError("CITATION.cff has no date-released")
    try:
        return datetime.date.fromisoformat(match.group(1))
    except ValueError:
        raise ReleaseError(f"CITATION.cff: date-released {match.group(1)!r} is not a date") from None


def _git(*arguments: str, stdin: bytes | None = None) -> subprocess.CompletedProcess:
    try:
        return subprocess.run(["git", *arguments], cwd=ROOT, capture_output=True, input=stdin)
    except OSError as error:
        raise ReleaseError(f"git cannot be run: {error}") from None


def commit_of(ref: str = "HEAD") -> str:
    """The commit ``ref`` names (its hash); a ref that is no commit, or reads as an option, is refused."""
    if not isinstance(ref, str) or not ref or ref.startswith("-") or any(c in ref for c in "\0\n\r"):
        raise ReleaseError(f"--ref must name a commit (a branch, tag or hash, not an option), not {ref!r}")
    found = _git("rev-parse", "--verify", "--quiet", "--end-of-options", f"{ref}^{{commit}}")
    commit = found.stdout.decode(errors="replace").strip()
    if found.returncode != 0 or not re.fullmatch(r"[0-9a-f]{40}(?:[0-9a-f]{24})?", commit):
        raise ReleaseError(f"--ref {ref!r} is not a commit of this repository ({ROOT})")
    return commit


def committed(ref: str = "HEAD") -> dict[str, tuple[bytes, bool]]:
    """Every file of commit ``ref``: path → (content, executable)."""
    commit = commit_of(ref)
    listed = _git("ls-tree", "-r", "-z", "--end-of-options", commit)
    if listed.returncode != 0:
        raise ReleaseError(f"git cannot list the files of --ref {ref!r}: "
                           f"{listed.stderr.decode(errors='replace').strip()}")
    entries = []
    for line in filter(None, listed.stdout.decode().split("\0")):
        meta, path = line.split("\t", 1)
        mode, kind, blob = meta.split()
        if kind == "blob":
            entries.append((path, blob, mode == "100755"))
    read = _git("cat-file", "--batch", stdin="".join(f"{blob}\n" for _, blob, _ in entries).encode())
    if read.returncode != 0:
        raise ReleaseError(f"git cannot read the files of --ref {ref!r}: "
                           f"{read.stderr.decode(errors='replace').strip()}")
    batch = read.stdout
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
        raise ReleaseError(f"the student bundle needs {', '.join(missing)}, which git does not track")
    return chosen


def _text(files: dict[str, tuple[bytes, bool]], path: str, ref: str) -> str:
    if path not in files:
        raise ReleaseError(f"{path} is not in --ref {ref!r}")
    try:
        return files[path][0].decode("utf-8")
    except UnicodeDecodeError:
        raise ReleaseError(f"{path} at --ref {ref!r} is not UTF-8 text") from None


def is_release_version(version: str) -> bool:
    """A PEP 440 public version in its normal form (what ``packaging`` would write back unchanged)."""
    if not isinstance(version, str) or not VERSION.fullmatch(version):
        return False
    if Version is None:
        return True
    try:
        return str(Version(version)) == version
    except InvalidVersion:
        return False


def project_version(files: dict[str, tuple[bytes, bool]], ref: str = "HEAD") -> str:
    """``[project] version`` of pyproject.toml at ``ref``, checked: a PEP 440 version in its normal form,
    equal to ``course_lib.__version__`` of the same commit."""
    try:
        project = tomllib.loads(_text(files, "pyproject.toml", ref)).get("project", {})
    except tomllib.TOMLDecodeError as error:
        raise ReleaseError(f"pyproject.toml at --ref {ref!r} is not valid TOML ({error}); "
                           'its [project] version must read like version = "1.0.0"') from None
    version = project.get("version") if isinstance(project, dict) else None
    if version is None:
        raise ReleaseError(f'pyproject.toml at --ref {ref!r} has no [project] version (version = "1.0.0")')
    if not is_release_version(version):
        raise ReleaseError(f"pyproject.toml: [project] version must be a PEP 440 version in its normal form "
                           f"(such as 1.0.0, 2.1rc1), not {version!r}")
    library = library_version(files, ref)
    if library is None:
        raise ReleaseError(f"course_lib/__init__.py at --ref {ref!r} sets no __version__ (a string), which "
                           f"must equal pyproject.toml's [project] version {version!r}")
    if library != version:
        raise ReleaseError(f"pyproject.toml: [project] version {version!r} is not course_lib.__version__ "
                           f"{library!r} (course_lib/__init__.py): make them the same")
    return version


def library_version(files: dict[str, tuple[bytes, bool]], ref: str = "HEAD") -> str | None:
    """``course_lib.__version__`` as course_lib/__init__.py at ``ref`` assigns it (a string literal)."""
    try:
        tree = ast.parse(_text(files, "course_lib/__init__.py", ref))
    except SyntaxError as error:
        raise ReleaseError(f"course_lib/__init__.py at --ref {ref!r} is not valid Python: {error}") from None
    for node in tree.body:
        if (isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__version__"
                                                 for t in node.targets)
                and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str)):
            return node.value.value
    return None


def entry_name(top: str, path: str) -> str:
    """``top/path``, the archive entry of ``path``, refused unless it stays inside the folder ``top``."""
    name = f"{top}/{path}"
    parts = name.split("/")
    if (not top or "/" in top or top in {".", ".."} or not path or path.startswith("/") or "\\" in name
            or any(part in {"", ".", ".."} for part in parts)
            or any(ord(c) < 32 or c == "\x7f" for c in name) or re.match(r"[A-Za-z]:", path)):
        raise ReleaseError(f"the archive entry {name!r} would not stay inside the bundle's folder {top!r}/")
    return name


def write_zip(target: pathlib.Path, top: str, entries: dict[str, tuple[bytes, bool]],
              date: datetime.date) -> None:
    stamp = (date.year, date.month, date.day, 0, 0, 0)
    names = {path: entry_name(top, path) for path in entries}  # every entry checked before writing
    target.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(target, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=9) as archive:
        for path in sorted(entries):
            content, executable = entries[path]
            info = zipfile.ZipInfo(names[path], date_time=stamp)
            info.external_attr = (0o100755 if executable else 0o100644) << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(info, content)


def output_folder(output: pathlib.Path) -> pathlib.Path:
    """``--output``: a folder, or a path where one can be made (refused when a file is in the way)."""
    for path in (output, *output.parents):
        if path.exists():
            if not path.is_dir():
                raise ReleaseError(f"--output {str(output)!r} must be a folder, but {str(path)!r} is a file")
            break
    return output


def release(output: pathlib.Path, ref: str = "HEAD") -> list[pathlib.Path]:
    """Both bundles of commit ``ref`` in ``output``: every setting is checked before anything is written,
    and the archives are written beside their names first, so a refusal or a failure leaves nothing."""
    output = output_folder(output)
    files = committed(ref)
    version = project_version(files, ref)
    date = release_date(_text(files, "CITATION.cff", ref))
    top = f"{NAME}-{version}"
    chosen = {path: files[path] for path in student_files(sorted(files))}
    chosen["README.md"] = (START_HERE.format(version=version).encode(), False)
    bundles = {output / f"{top}-student.zip": chosen, output / f"{top}-instructor.zip": files}
    for target, entries in bundles.items():
        for path in entries:
            entry_name(top, path)
        if target.exists() and not target.is_file():
            raise ReleaseError(f"--output {str(output)!r}: {target.name} is there and is not a file")
    made = [path for path in (output, *output.parents) if not path.exists()]
    parts = {target: target.with_name(f".{target.name}.part") for target in bundles}
    try:
        for target, entries in bundles.items():
            write_zip(parts[target], top, entries, date)
        for target, part in parts.items():
            os.replace(part, target)
        ignore = output / ".gitignore"  # dist/ keeps itself out of git
        if not ignore.exists():
            ignore.write_text("# made by tools/make_dist.py\n*\n")
    except OSError as error:
        for part in parts.values():
            part.unlink(missing_ok=True)
        for path in made:  # the folders this run made, if they are still empty
            with contextlib.suppress(OSError):
                path.rmdir()
        raise ReleaseError(f"--output {str(output)!r} cannot be written: {error}") from None
    return list(bundles)


def main(arguments: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=pathlib.Path, default=ROOT / "dist")
    parser.add_argument("--ref", default="HEAD", help="the commit to release (default HEAD)")
    options = parser.parse_args(arguments)
    try:
        written = release(options.output, options.ref)
    except ReleaseError as error:
        print(f"make_dist: {error}; nothing was written", file=sys.stderr)
        return 2
    for path in written:
        with zipfile.ZipFile(path) as archive:
            count = len(archive.namelist())
        print(f"{path.relative_to(ROOT) if path.is_relative_to(ROOT) else path}: {count} files, "
              f"{path.stat().st_size / 1e6:.1f} MB")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
