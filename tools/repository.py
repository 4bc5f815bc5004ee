"""The repository's address, one setting, and the links made from it.

Usage: python tools/repository.py            print the address and the links made from it
       python tools/repository.py --write    bring README.md and CITATION.cff in line with it
       python tools/repository.py --check    exit 1 if README.md or CITATION.cff disagree with it

The address is ``[project.urls] Repository`` in ``pyproject.toml``; the environment variable
``COURSE_REPOSITORY_URL`` overrides it for one command (empty: no address), as the website's tests do.
Everything that links to the repository takes the address from here: the website's launch buttons and
repository, source and issue links (tools/build_site.py), the README's block of links in *Run it
elsewhere* (between the ``repository-links`` comments) and ``repository-code`` in CITATION.cff.  With no
address, none of them shows a link, and nothing stands in for one.

A JupyterHub is a second, optional address (``[tool.course] jupyterhub-url``, or
``COURSE_JUPYTERHUB_URL``): with both set, the website also shows an nbgitpuller link that clones the
repository into the hub and opens the page there.
"""

from __future__ import annotations

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
ENV, HUB_ENV = "COURSE_REPOSITORY_URL", "COURSE_JUPYTERHUB_URL"
BRANCH = "main"
FIRST_LESSON = "notebooks/00_start_here.ipynb"
README_START = "<!-- repository-links: made by tools/repository.py -->"
README_END = "<!-- /repository-links -->"
CITATION_KEY = re.compile(r"^repository-code:.*\n", re.M)


class RepositoryError(ValueError):
    """The address is not one the links can be made from (message says why)."""


def _pyproject() -> dict:
    return tomllib.loads(PYPROJECT.read_text(encoding="utf-8"))


def _https(url: str, what: str) -> str:
    url = url.strip().rstrip("/")
    parts = urllib.parse.urlsplit(url)
    if parts.scheme != "https" or not parts.hostname or parts.query or parts.fragment:
        raise RepositoryError(f"{what} must be an https:// address without query or fragment, not {url!r}")
    return url.removesuffix(".git")


def repository_url(environ=os.environ) -> str | None:
    """The repository's address, or None when it is not set."""
    if ENV in environ:
        url = environ[ENV]
    else:
        url = _pyproject()["project"].get("urls", {}).get("Repository", "")
    return _https(url, "the repository's address") if url.strip() else None


def jupyterhub_url(environ=os.environ) -> str | None:
    """The JupyterHub's address, or None when it is not set."""
    if HUB_ENV in environ:
        url = environ[HUB_ENV]
    else:
        url = _pyproject().get("tool", {}).get("course", {}).get("jupyterhub-url", "")
    return _https(url, "the JupyterHub's address") if url.strip() else None


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

    def notebook_source(self, notebook: str) -> str:
        return f"{self.repository}/blob/{BRANCH}/{notebook}"

    def colab_notebook(self, notebook: str) -> str | None:
        return f"{self.colab}/blob/{BRANCH}/{notebook}" if self.colab else None


def links(url: str) -> Links:
    """The links made from ``url`` (https://github.com/OWNER/NAME, a GitLab address, or another host)."""
    url = _https(url, "the repository's address")
    parts = urllib.parse.urlsplit(url)
    path = parts.path.strip("/")
    if path.count("/") < 1:
        raise RepositoryError(f"the repository's address must name an owner and a repository, not {url!r}")
    host = parts.hostname
    lab = urllib.parse.quote(f"lab/tree/{FIRST_LESSON}", safe="")
    if host == "github.com":
        binder = f"https://mybinder.org/v2/gh/{path}/{BRANCH}?urlpath={lab}"
        colab = f"https://colab.research.google.com/github/{path}"
    elif host == "gitlab.com":
        binder = f"https://mybinder.org/v2/gl/{urllib.parse.quote(path, safe='')}/{BRANCH}?urlpath={lab}"
        colab = None
    else:
        binder = f"https://mybinder.org/v2/git/{urllib.parse.quote(url, safe='')}/{BRANCH}?urlpath={lab}"
        colab = None
    issues = f"{url}/issues" if host in {"github.com", "gitlab.com"} else url
    return Links(repository=url, issues=issues, source=f"{url}/tree/{BRANCH}/notebooks", binder=binder,
                 colab=colab, host=host, path=path)


def readme_block(url: str | None) -> str:
    """The README's block of links (empty without an address)."""
    if url is None:
        return ""
    made = links(url)
    lines = [f"Repository: <{made.repository}> · issues: <{made.issues}>"]
    if made.binder:
        lines.append(f"[Launch on Binder]({made.binder}) (JupyterLab at lesson 00)")
    if made.colab:
        lines.append(f"[Lesson 00 on Colab]({made.colab_notebook(FIRST_LESSON)})")
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
    line = f'repository-code: "{url}"\n'
    anchor = re.search(r"^license:", text, re.M)
    return text[: anchor.start()] + line + text[anchor.start():] if anchor else text + line


def disagreements(url: str | None) -> list[str]:
    """What in README.md and CITATION.cff does not follow the address (empty: they agree)."""
    found = []
    readme = README.read_text(encoding="utf-8")
    if expected_readme(readme, url) != readme:
        found.append("README.md: the repository-links block (python tools/repository.py --write)")
    citation = CITATION.read_text(encoding="utf-8")
    if expected_citation(citation, url) != citation:
        found.append("CITATION.cff: repository-code (python tools/repository.py --write)")
    return found


def main(arguments: list[str]) -> int:
    url = repository_url()
    if "--write" in arguments:
        README.write_text(expected_readme(README.read_text(encoding="utf-8"), url), encoding="utf-8")
        CITATION.write_text(expected_citation(CITATION.read_text(encoding="utf-8"), url), encoding="utf-8")
    if "--check" in arguments:
        found = disagreements(url)
        for line in found:
            print(line)
        return 1 if found else 0
    print(f"repository: {url or '(not set)'}")
    if url:
        for name, value in vars(links(url)).items():
            print(f"  {name}: {value}")
    print(f"jupyterhub: {jupyterhub_url() or '(not set)'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
