"""The repository's address, one setting, and the links made from it.

Usage: python tools/repository.py            print the address and the links made from it
       python tools/repository.py --write    bring README.md, CITATION.cff and the lessons in line with it
       python tools/repository.py --check    exit 1 if README.md, CITATION.cff or a lesson disagree with it

The address is ``[project.urls] Repository`` in ``pyproject.toml``; the environment variable
``COURSE_REPOSITORY_URL`` overrides it for one command (empty: no address), as the website's tests do.
Everything that links to the repository takes the address from here: the website's launch buttons and
repository, source and issue links (tools/build_site.py), the README's block of links in *Run it
elsewhere* (between the ``repository-links`` comments), ``repository-code`` in CITATION.cff and the set-up
cell that opens every lesson (:data:`SETUP_CELL`): where ``course_lib`` is missing (Colab) it installs it with
pip from ``git+ADDRESS@BRANCH``.  With no address, none of them shows a link, and nothing stands in for one
(the set-up cell then says which command installs ``course_lib``).

The branch the links point at is ``[tool.course] branch`` (default ``main``), or ``COURSE_REPOSITORY_BRANCH``
for one command: a git branch name of plain segments (letters, digits, ``-``, ``_``, ``.``, separated by
``/``; not starting with ``-`` or ``.``, no ``..``, not ending in ``.lock``), anything else refused by name.

A JupyterHub is a second, optional address (``[tool.course] jupyterhub-url``, or
``COURSE_JUPYTERHUB_URL``): with both set, the website also shows an nbgitpuller link that clones the
repository into the hub and opens the page there.

Both addresses are checked before anything is made from them: ``https://HOST[:PORT]/PATH`` with a host of
letters, digits, dots and hyphens, a port from 1 to 65535, a path of plain segments (letters, digits,
``-``, ``_``, ``.``; not ``.`` or ``..``), and no credentials, query, fragment, spaces or control
characters.  Anything else is refused with a message naming the setting and its value, and nothing is
written.  Where an address is written it is escaped all the same: percent-encoded in Markdown links,
a quoted (JSON) string in CITATION.cff, and ``--check`` compares with exactly what ``--write`` writes
(and reads CITATION.cff back as YAML).
"""

from __future__ import annotations

import json
import os
import pathlib
import re
import sys
import tomllib
import urllib.parse
from dataclasses import dataclass

ROOT = pathlib.Path(__file__).resolve().parent.parent
PYPROJECT = ROOT / "pyproject.toml"
README = ROOT / "README.md"
CITATION = ROOT / "CITATION.cff"
ENV, HUB_ENV, BRANCH_ENV = "COURSE_REPOSITORY_URL", "COURSE_JUPYTERHUB_URL", "COURSE_REPOSITORY_BRANCH"
BRANCH = "main"  # the default branch setting
_SEGMENT = r"[A-Za-z0-9_][A-Za-z0-9._-]*"
BRANCH_NAME = re.compile(rf"(?!.*\.\.)(?!.*\.lock(?:/|$)){_SEGMENT}(?:/{_SEGMENT})*", re.ASCII)
FIRST_LESSON = "notebooks/00_start_here.ipynb"
README_START = "<!-- repository-links: made by tools/repository.py -->"
README_END = "<!-- /repository-links -->"
CITATION_KEY = re.compile(r"^repository-code:.*\n", re.M)
LESSONS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
#: Every notebook that opens with the set-up cell: the lessons, the exercise sets and their student copies.
WITH_SETUP = LESSONS + sorted((ROOT / "notebooks" / "solutions").glob("ex*.ipynb")) + sorted(
    (ROOT / "notebooks" / "exercises").glob("ex*.ipynb"))

#: The first code cell of every lesson (its address line made by :func:`setup_cell`): nothing happens where
#: course_lib is installed; elsewhere (Colab) it says so and installs it from the repository, or, with no
#: address set, stops with the command that installs it.
SETUP_CELL = """\
# Colab, or any kernel without the course's library: this cell says so, and installs it from the collection's
# repository when the collection has an address (else it names the command to run). Where course_lib is
# installed (the course's own environment), it does nothing.
import importlib.util
import subprocess
import sys

# where pip gets course_lib: the collection's repository (written by tools/repository.py; "" when it has none)
COURSE_LIB_SOURCE = ""
if importlib.util.find_spec("course_lib") is None:
    if not COURSE_LIB_SOURCE:
        raise ModuleNotFoundError(
            "course_lib is not installed in this kernel. In a terminal, in the collection's top folder "
            f"(the one holding environment.txt), run\\n    \\"{sys.executable}\\" -m pip install -c "
            "environment.lock -r environment.txt\\nthen restart the kernel and run this lesson again.")
    print(f"course_lib is not installed in this kernel: installing it from {COURSE_LIB_SOURCE} …")
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", COURSE_LIB_SOURCE], check=True)
    importlib.invalidate_caches()
    print("course_lib is installed.")"""
# the set-up cell's address line as it stands in the notebook's JSON (one string of its "source" list)
_SETUP_LINE = re.compile(r'^(\s*")COURSE_LIB_SOURCE = \\"[^"\\]*\\"', re.M)


class RepositoryError(ValueError):
    """The address is not one the links can be made from (message says why)."""


REPOSITORY_SETTING, HUB_SETTING, BRANCH_SETTING = ("the repository's address", "the JupyterHub's address",
                                                   "the repository's branch")
_LABEL = r"[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}[A-Za-z0-9])?"
ADDRESS = re.compile(rf"https://(?P<host>{_LABEL}(?:\.{_LABEL})*)(?::(?P<port>[1-9][0-9]{{0,4}}))?"
                     r"(?P<path>(?:/[A-Za-z0-9._-]+)*)", re.ASCII)
# what may stand in a Markdown link's target as it is (everything else is percent-encoded)
_MARKDOWN_SAFE = "/:?=&%#~+,;@!$*"


def _pyproject() -> dict:
    try:
        return tomllib.loads(PYPROJECT.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as error:
        raise RepositoryError(f"pyproject.toml is not valid TOML: {error}") from None


def _shown(url: str) -> str:
    """``url`` as a message shows it: quoted, escapes visible, credentials (user, password, token) hidden."""
    return repr(re.sub(r"(?<=://)[^/@]*@", "***@", url))


def _https(url: str, what: str) -> str:
    """``url`` checked and in its one form (no trailing ``/`` or ``.git``), or RepositoryError."""
    if not isinstance(url, str):
        raise RepositoryError(f"{what} must be a string, not {url!r}")
    given = url
    url = url.strip().rstrip("/").removesuffix(".git")
    match = ADDRESS.fullmatch(url)
    if not match:
        if "@" in url.split("?")[0].split("#")[0]:
            why = "must carry no credentials (user:password@)"
        elif any(ord(c) < 33 or c == "\x7f" for c in url):
            why = "must not contain spaces or control characters"
        else:
            why = ("must be an https:// address: a host of letters, digits, dots and hyphens, an optional "
                   "port, a path of plain segments, no query or fragment")
        raise RepositoryError(f"{what} {why}, not {_shown(given)}")
    if match["port"] and not 1 <= int(match["port"]) <= 65535:
        raise RepositoryError(f"{what} has a port out of 1–65535, not {_shown(given)}")
    if any(segment in {".", ".."} for segment in match["path"].split("/")):
        raise RepositoryError(f"{what} must have no . or .. segments, not {_shown(given)}")
    return url


def repository_url(environ=os.environ) -> str | None:
    """The repository's address, or None when it is not set."""
    if ENV in environ:
        url, where = environ[ENV], ENV
    else:
        where = "[project.urls] Repository in pyproject.toml"
        url = _pyproject()["project"].get("urls", {}).get("Repository", "")
    return _https(url, f"{REPOSITORY_SETTING} ({where})") if not isinstance(url, str) or url.strip() else None


def jupyterhub_url(environ=os.environ) -> str | None:
    """The JupyterHub's address, or None when it is not set."""
    if HUB_ENV in environ:
        url, where = environ[HUB_ENV], HUB_ENV
    else:
        where = "[tool.course] jupyterhub-url in pyproject.toml"
        url = _pyproject().get("tool", {}).get("course", {}).get("jupyterhub-url", "")
    return checked_hub(url, where) if not isinstance(url, str) or url.strip() else None


def repository_branch(environ=os.environ) -> str:
    """The branch the links point at: ``COURSE_REPOSITORY_BRANCH``, else ``[tool.course] branch``, else
    main."""
    if BRANCH_ENV in environ:
        return checked_branch(environ[BRANCH_ENV], BRANCH_ENV)
    branch = _pyproject().get("tool", {}).get("course", {}).get("branch", BRANCH)
    return checked_branch(branch, "[tool.course] branch in pyproject.toml")


def checked_branch(branch, where: str = "") -> str:
    """``branch`` if it is a plain git branch name (see the module's text), else :class:`RepositoryError`."""
    if not isinstance(branch, str) or not BRANCH_NAME.fullmatch(branch):
        setting = f"{BRANCH_SETTING} ({where})" if where else BRANCH_SETTING
        raise RepositoryError(f"{setting} must be a git branch name of plain segments (letters, digits, "
                              f"'-', '_', '.', separated by '/'); got {branch!r}")
    return branch


def checked_hub(url: str, where: str = "") -> str:
    """The JupyterHub's address checked (as the repository's; a hub may have no path)."""
    return _https(url, f"{HUB_SETTING} ({where})" if where else HUB_SETTING)


def markdown_url(url: str) -> str:
    """``url`` fit for a Markdown link's target or autolink: ``()<>[]``, quotes, backslashes, spaces and
    anything else that could end the link are percent-encoded (a checked address has none of them)."""
    return urllib.parse.quote(url, safe=_MARKDOWN_SAFE)


@dataclass(frozen=True)
class Links:
    """Every link made from the repository's address (None: that service does not take this host)."""

    repository: str
    issues: str
    source: str  # the folder of the lessons on the default branch
    binder: str | None
    colab: str | None
    host: str
    path: str  # "owner/name"
    branch: str = BRANCH

    def notebook_source(self, notebook: str) -> str:
        return f"{self.repository}/blob/{self.branch}/{notebook}"

    def colab_notebook(self, notebook: str) -> str | None:
        return f"{self.colab}/blob/{self.branch}/{notebook}" if self.colab else None


def links(url: str, branch: str | None = None) -> Links:
    """The links made from ``url`` (https://github.com/OWNER/NAME, a GitLab address, or another host), to
    ``branch`` (default: the branch setting, :func:`repository_branch`)."""
    url = _https(url, REPOSITORY_SETTING)
    branch = repository_branch() if branch is None else checked_branch(branch)
    parts = urllib.parse.urlsplit(url)
    path = parts.path.strip("/")
    if path.count("/") < 1:
        raise RepositoryError(f"{REPOSITORY_SETTING} must name an owner and a repository, not {_shown(url)}")
    host = parts.hostname
    lab = urllib.parse.quote(f"lab/tree/{FIRST_LESSON}", safe="")
    if host == "github.com":
        binder = f"https://mybinder.org/v2/gh/{path}/{branch}?urlpath={lab}"
        colab = f"https://colab.research.google.com/github/{path}"
    elif host == "gitlab.com":
        binder = f"https://mybinder.org/v2/gl/{urllib.parse.quote(path, safe='')}/{branch}?urlpath={lab}"
        colab = None
    else:
        binder = f"https://mybinder.org/v2/git/{urllib.parse.quote(url, safe='')}/{branch}?urlpath={lab}"
        colab = None
    issues = f"{url}/issues" if host in {"github.com", "gitlab.com"} else url
    return Links(repository=url, issues=issues, source=f"{url}/tree/{branch}/notebooks", binder=binder,
                 colab=colab, host=host, path=path, branch=branch)


def readme_block(url: str | None) -> str:
    """The README's block of links (empty without an address)."""
    if url is None:
        return ""
    made = links(url)
    lines = [f"Repository: <{markdown_url(made.repository)}> · issues: <{markdown_url(made.issues)}>"]
    if made.binder:
        lines.append(f"[Launch on Binder]({markdown_url(made.binder)}) (JupyterLab at lesson 00)")
    if made.colab:
        lines.append(f"[Lesson 00 on Colab]({markdown_url(made.colab_notebook(FIRST_LESSON))})")
    return "\n".join(f"- {line}" for line in lines) + "\n"


def expected_readme(text: str, url: str | None) -> str:
    start, end = text.find(README_START), text.find(README_END)
    if start < 0 or end < start:
        raise RepositoryError(f"README.md has no {README_START} … {README_END} block")
    return text[: start + len(README_START)] + "\n" + readme_block(url) + text[end:]


def expected_citation(text: str, url: str | None) -> str:
    text = CITATION_KEY.sub("", text)
    if url is None:
        return text
    url = links(url).repository  # checked: an address the links are made from
    line = f"repository-code: {json.dumps(url)}\n"  # a JSON string is a double-quoted YAML scalar
    anchor = re.search(r"^license:", text, re.M)
    return text[: anchor.start()] + line + text[anchor.start():] if anchor else text + line


def setup_cell(url: str | None) -> str:
    """The lessons' set-up cell (:data:`SETUP_CELL`) installing from ``url``'s repository (None: none)."""
    return SETUP_CELL.replace('COURSE_LIB_SOURCE = ""', f'COURSE_LIB_SOURCE = "{pip_source(url)}"', 1)


def pip_source(url: str | None) -> str:
    """What pip installs course_lib from: ``git+ADDRESS@BRANCH``, or "" without an address."""
    if url is None:
        return ""
    made = links(url)
    return f"git+{made.repository}@{made.branch}"


def expected_lesson(text: str, url: str | None, name: str = "the lesson") -> str:
    """A lesson's JSON ``text`` with its set-up cell installing from ``url`` (only that line changes, so the
    file stays as JupyterLab saves it); RepositoryError when the lesson has no set-up cell."""
    found = _SETUP_LINE.findall(text)
    if len(found) != 1:
        raise RepositoryError(f"{name} has {len(found)} set-up lines (COURSE_LIB_SOURCE = ...), not one: "
                              "its first code cell is tools/repository.py's SETUP_CELL")
    # a checked address and branch hold no quote or backslash: the JSON string needs no escaping
    return _SETUP_LINE.sub(lambda match: f'{match[1]}COURSE_LIB_SOURCE = \\"{pip_source(url)}\\"', text)


def expected_files(url: str | None) -> dict[pathlib.Path, str]:
    """README.md, CITATION.cff and the lessons as they follow ``url``: what ``--write`` writes and ``--check``
    wants."""
    files = {README: expected_readme(README.read_text(encoding="utf-8"), url),
             CITATION: expected_citation(CITATION.read_text(encoding="utf-8"), url)}
    for lesson in WITH_SETUP:
        files[lesson] = expected_lesson(lesson.read_text(encoding="utf-8"), url, lesson.name)
    return files


def citation_problem(text: str, url: str | None) -> str | None:
    """What is wrong with CITATION.cff read as YAML (None: valid, and repository-code is ``url``)."""
    try:
        import yaml
    except ImportError:  # pragma: no cover - PyYAML is in the development set
        return None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as error:
        return f"CITATION.cff is not valid YAML: {' '.join(str(error).split())}"
    if not isinstance(data, dict):
        return "CITATION.cff is not a YAML mapping"
    if data.get("repository-code") != url:
        return f"CITATION.cff: repository-code reads {data.get('repository-code')!r}, not {url!r}"
    return None


def disagreements(url: str | None) -> list[str]:
    """What in README.md and CITATION.cff does not follow the address (empty: they agree)."""
    found = []
    expected = expected_files(url)
    if expected[README] != README.read_text(encoding="utf-8"):
        found.append("README.md: the repository-links block (python tools/repository.py --write)")
    citation = CITATION.read_text(encoding="utf-8")
    if expected[CITATION] != citation:
        found.append("CITATION.cff: repository-code (python tools/repository.py --write)")
    else:
        problem = citation_problem(citation, url)
        if problem:
            found.append(problem)
    return found


def main(arguments: list[str]) -> int:
    try:
        url = repository_url()
        hub = jupyterhub_url()
        repository_branch()  # checked too: every link is made from it
        expected = expected_files(url)  # everything is made and checked before anything is written
        problem = citation_problem(expected[CITATION], url) if "--write" in arguments else None
        if problem:
            raise RepositoryError(f"{problem} once written; nothing was written")
    except RepositoryError as error:
        print(f"repository: {error}", file=sys.stderr)
        return 2
    if "--write" in arguments:
        for path, text in expected.items():
            if path.read_text(encoding="utf-8") != text:
                path.write_text(text, encoding="utf-8")
    if "--check" in arguments:
        found = disagreements(url)
        for line in found:
            print(line)
        return 1 if found else 0
    print(f"repository: {url or '(not set)'}")
    if url:
        for name, value in vars(links(url)).items():
            print(f"  {name}: {value}")
    print(f"jupyterhub: {hub or '(not set)'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
