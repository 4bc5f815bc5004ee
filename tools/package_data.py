"""Write what course_lib ships from the lessons and the student set: a lesson then runs where its folder is
not at hand.

Usage: python tools/package_data.py            write both files
       python tools/package_data.py --check    exit 1 (saying which) if either is not what it would write

- ``course_lib/checks/worked_answers.json``: every lesson's worked answers (the ```python and ```text blocks
  folded in ``<details>``), read by ``run_worked_answer`` where the lesson file is not in the working folder
  (Colab, a kernel started elsewhere, the lesson run as a ``.py`` script).
- ``course_lib/environment.txt``: the ``name==version`` pins of ``environment.txt``, which lesson 00's set-up
  check compares with where the collection's ``environment.txt`` is not beside the lessons (Colab, a hub).

Both are package data (``[tool.setuptools.package-data]`` in pyproject.toml), so ``pip install`` from the
repository carries them.  Run this after changing a lesson's worked answer or a pin:
``tests/test_run_anywhere.py`` fails, naming this command, while either file is stale.
"""

from __future__ import annotations

import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from course_lib.checks.worked import WORKED_ANSWERS_FILE, packaged_answers  # noqa: E402

LESSONS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
ENVIRONMENT = ROOT / "environment.txt"
TESTED_VERSIONS = ROOT / "course_lib" / "environment.txt"
COMMAND = "python tools/package_data.py"


def worked_answers_text() -> str:
    """The JSON of every lesson's worked answers (lessons without one left out), as the file holds it."""
    answers = {name: found for name, found in packaged_answers(LESSONS).items() if found}
    return json.dumps(answers, indent=1, ensure_ascii=False, sort_keys=True) + "\n"


def tested_versions_text() -> str:
    """The pins of environment.txt (its ``name==version`` lines), under a header saying where from."""
    pins = [line.strip() for line in ENVIRONMENT.read_text(encoding="utf-8").splitlines()
            if "==" in line and not line.lstrip().startswith("#")]
    header = ("# The versions this course_lib was tested with: the pins of the collection's\n"
              f"# environment.txt, copied by {COMMAND}. Lesson 00 compares with them where\n"
              "# environment.txt is not at hand.\n")
    return header + "".join(f"{pin}\n" for pin in pins)


def expected() -> dict[pathlib.Path, str]:
    return {WORKED_ANSWERS_FILE: worked_answers_text(), TESTED_VERSIONS: tested_versions_text()}


def stale() -> list[pathlib.Path]:
    """The package data files that differ from what :func:`expected` makes (or are missing)."""
    return [path for path, text in expected().items()
            if not path.is_file() or path.read_text(encoding="utf-8") != text]


def main(arguments: list[str]) -> int:
    if "--check" in arguments:
        found = stale()
        for path in found:
            print(f"{path.relative_to(ROOT)} is out of date: run {COMMAND}")
        return 1 if found else 0
    for path, text in expected().items():
        if not path.is_file() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")
            print(f"wrote {path.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
