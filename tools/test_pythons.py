"""Test the collection under every Python it claims: ``make test-pythons`` (default 3.11 3.12 3.13).

Usage: python tools/test_pythons.py [X.Y ...]      (= make test-pythons PYTHONS="X.Y ...")

For each version, in a virtual environment of its own (``.venv/pythons/X.Y``; ``.venv`` itself when
it runs that version) with the whole pinned set (``environment-dev.txt``) installed:

* the **library**: ``tests/`` and the doctests of ``course_lib`` — everything except the tests of the
  tooling around it (website, browser, Binder, bundles, ``make lab``, nbgrader), which run under
  ``make test``'s Python;
* under the **newest** version asked for, also **every notebook** under strict nbval, as ``make test``
  runs them.

The interpreter for X.Y is ``pythonX.Y`` on the PATH, else pyenv's newest X.Y.*; a version found
nowhere fails the run with that message.  A summary line per version ends the run.
"""

from __future__ import annotations

import os
import pathlib
import shutil
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
REQUIREMENTS = [ROOT / "environment-dev.txt", ROOT / "environment.txt", ROOT / "environment.lock",
                ROOT / "pyproject.toml"]
# the tooling's tests: they check the site, the browser, Binder, the bundles, make lab and nbgrader
TOOLING_TESTS = ["tests/test_site.py", "tests/browser", "tests/test_binder.py", "tests/test_dist.py",
                 "tests/test_make_lab.py", "tests/test_nbgrader.py"]
NBVAL = ["--nbval", "--nbval-current-env", "--nbval-sanitize-with", "tests/sanitize.cfg",
         "--nbval-cell-timeout=600"]
PYTEST = ["-m", "pytest", "-q", "-rs", "-p", "xdist", "-n", "2", "--dist", "loadfile"]


def _version_of(executable: str) -> str | None:
    try:
        result = subprocess.run([executable, "-c", "import sys; print('%d.%d' % sys.version_info[:2])"],
                                capture_output=True, text=True, timeout=60)
    except OSError:
        return None
    return result.stdout.strip() if result.returncode == 0 else None


def find_python(version: str) -> str:
    """An interpreter of ``version`` (``3.12``): on the PATH, else pyenv's newest of that series."""
    on_path = shutil.which(f"python{version}")
    if on_path and _version_of(on_path) == version:
        return on_path
    pyenv = shutil.which("pyenv")
    roots = [os.environ.get("PYENV_ROOT", ""), str(pathlib.Path.home() / ".pyenv")]
    if pyenv:
        result = subprocess.run([pyenv, "root"], capture_output=True, text=True)
        roots.insert(0, result.stdout.strip())
    for root in filter(None, roots):
        candidates = sorted(pathlib.Path(root, "versions").glob(f"{version}.*/bin/python{version}"),
                            key=lambda path: [int(part) for part in path.parts[-3].split(".")
                                              if part.isdigit()])
        for candidate in reversed(candidates):
            if _version_of(str(candidate)) == version:
                return str(candidate)
    raise SystemExit(f"Python {version} was not found: no python{version} on the PATH and none in pyenv "
                     f"(install it, e.g. `pyenv install {version}`, or leave it out of PYTHONS)")


def environment(version: str, interpreter: str) -> pathlib.Path:
    """The venv for ``version`` with environment-dev.txt installed (re-installed when it changed)."""
    venv = ROOT / ".venv"
    if _version_of(str(venv / "bin" / "python")) != version:
        venv = ROOT / ".venv" / "pythons" / version
    stamp = venv / ".installed-dev"
    newest = max(path.stat().st_mtime for path in REQUIREMENTS)
    if stamp.exists() and stamp.stat().st_mtime >= newest:
        python = str(venv / "bin" / "python")
        where = subprocess.run([python, "-c", "import course_lib; print(course_lib.__file__)"],
                               cwd="/", capture_output=True, text=True).stdout.strip()
        if where and pathlib.Path(where).parent == ROOT / "course_lib":
            return venv
        # a venv made for another copy of the collection: course_lib from this folder, the rest as it is
        subprocess.run([python, "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
                        "--no-deps", "-e", "."], cwd=ROOT, check=True)
        return venv
    if not (venv / "bin" / "python").exists():
        venv.parent.mkdir(parents=True, exist_ok=True)
        subprocess.run([interpreter, "-m", "venv", str(venv)], check=True)
    started = time.monotonic()
    subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "--quiet",
                    "--disable-pip-version-check", "-c", "environment.lock", "-r", "environment-dev.txt"],
                   cwd=ROOT, check=True)
    print(f"[{version}] installed environment-dev.txt into {venv.relative_to(ROOT)} "
          f"in {time.monotonic() - started:.0f} s")
    stamp.touch()
    (venv / ".installed-student").touch()
    return venv


def run(version: str, venv: pathlib.Path, what: str, arguments: list[str]) -> tuple[bool, float]:
    started = time.monotonic()
    print(f"[{version}] {what}: {venv.relative_to(ROOT)}/bin/python {' '.join(arguments)}", flush=True)
    env = dict(os.environ, PYDEVD_DISABLE_FILE_VALIDATION="1")
    result = subprocess.run([str(venv / "bin" / "python"), *arguments], cwd=ROOT, env=env)
    return result.returncode == 0, time.monotonic() - started


def main(versions: list[str]) -> int:
    versions = versions or ["3.11", "3.12", "3.13"]
    newest = max(versions, key=lambda version: tuple(int(part) for part in version.split(".")))
    interpreters = {version: find_python(version) for version in versions}  # all found before any runs
    summary, ok = [], True
    for version in versions:
        venv = environment(version, interpreters[version])
        ignores = [f"--ignore={path}" for path in TOOLING_TESTS]
        passed, seconds = run(version, venv, "library", [*PYTEST, *ignores, "tests", "course_lib"])
        summary.append(f"[{version}] library: {'passed' if passed else 'FAILED'} in {seconds:.0f} s")
        ok &= passed
        if version == newest:
            passed, seconds = run(version, venv, "notebooks", [*PYTEST, *NBVAL, "notebooks"])
            summary.append(f"[{version}] notebooks: {'passed' if passed else 'FAILED'} in {seconds:.0f} s")
            ok &= passed
    print("\n".join(["test-pythons:", *summary]))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
