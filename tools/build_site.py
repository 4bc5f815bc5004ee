"""Build the course website, ``_build/html/``, from the committed notebooks: nothing is executed.

Usage: python tools/build_site.py            (= make site)

Steps:

1. **Stage** ``_build/source/``: ``site/_config.yml``; a landing page ``index.md`` that is the
   README's lesson map (its introduction and its *Lessons* section, exercises included); a
   ``_toc.yml`` listing every lesson (``notebooks/NN_*.ipynb``) and every student exercise copy
   (``notebooks/exercises/exNN_*.ipynb``; never the solutions); and a display copy of each notebook.
   The display copy differs from the committed file only where a page would otherwise load from
   outside the site: widget views are dropped (no widget manager is served; an explorer shows the
   static picture saved beside its view) and the player of a matplotlib animation loses the link to
   a CDN's icon font (the site's own Font Awesome draws the buttons).  Files are rewritten only when
   their content changes, so Sphinx rebuilds only what changed.
2. **Build** with Jupyter Book 1 (Sphinx, ``execute_notebooks: off``), MathJax copied into
   ``_static/mathjax`` from a pinned package.
3. **Publish the notebooks as committed**: each page's download link (``_sources/…ipynb``) serves
   the committed file, not the display copy.  MathJax keeps its one entry point (``mathjax_path``
   in the config) and everything that loads lazily (extensions, fonts, menu, accessibility, SVG
   output); the package's other combined entry points, never loaded, are left out.
4. **Check** that no page, stylesheet or script tag of the site loads anything from outside it.
"""

from __future__ import annotations

import copy
import json
import pathlib
import re
import shutil
import subprocess
import sys
import time

import nbformat
import yaml

ROOT = pathlib.Path(__file__).resolve().parent.parent
SITE_CONFIG = ROOT / "site" / "_config.yml"
BUILD = ROOT / "_build"
STAGE = BUILD / "source"
HTML = BUILD / "html"

WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
# matplotlib's to_jshtml() player links Font Awesome 4 from a CDN for its buttons
CDN_ICON_LINK = re.compile(r'<link rel="stylesheet"\s+href="https?://[^"]*font-awesome[^"]*"\s*/?>\s*')
# what makes a browser fetch a resource (links <a href> to elsewhere are fine: they load nothing)
OUTSIDE_LOADS = [
    re.compile(r"<script\b[^>]*\bsrc=[\"'](?:https?:)?//", re.I),
    re.compile(r"<link\b(?=[^>]*\brel=[\"']?(?:stylesheet|preload|modulepreload|icon|prefetch))"
               r"[^>]*\bhref=[\"'](?:https?:)?//", re.I),
    re.compile(r"<(?:img|iframe|audio|video|source|embed)\b[^>]*\bsrc=[\"'](?:https?:)?//", re.I),
    re.compile(r"@import\s+(?:url\()?[\"']?(?:https?:)?//", re.I),
    re.compile(r"url\([\"']?(?:https?:)?//", re.I),
]


class SiteError(RuntimeError):
    """The site cannot be built as promised (message says what and where)."""


def lesson_paths() -> list[pathlib.Path]:
    return sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))


def exercise_paths() -> list[pathlib.Path]:
    return sorted((ROOT / "notebooks" / "exercises").glob("ex[0-9][0-9]_*.ipynb"))


def page_paths() -> list[pathlib.Path]:
    """Every notebook that becomes a page, lessons first."""
    return lesson_paths() + exercise_paths()


def _relative(path: pathlib.Path) -> str:
    return path.relative_to(ROOT).as_posix()


def landing_page(readme: str) -> str:
    """The site's index page: the README's title, its first paragraph and its *Lessons* section.

    The README's links (``notebooks/….ipynb``) are kept as they are: the staged tree has the same
    layout, so they become links to the pages.
    """
    lines = readme.splitlines()
    if not lines or not lines[0].startswith("# "):
        raise SiteError("README.md must start with its '# ' title")
    title = lines[0]
    paragraphs, block, fenced = [], [], False
    for line in lines[1:]:
        if line.startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            continue
        if line.startswith("#"):
            break
        if line.strip():
            block.append(line)
        elif block:
            paragraphs.append(" ".join(block))
            block = []
    if not paragraphs:
        raise SiteError("README.md has no introductory paragraph before its first section")
    start = next((i for i, line in enumerate(lines) if line.strip() == "## Lessons"), None)
    if start is None:
        raise SiteError("README.md has no '## Lessons' section (the site's lesson map)")
    stop = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")), len(lines))
    lesson_map = "\n".join(lines[start:stop]).rstrip()
    missing = [_relative(path) for path in page_paths() if f"({_relative(path)})" not in lesson_map]
    if missing:  # the pages are built all the same (the table of contents lists every notebook)
        print(f"warning: README.md's lesson map does not link {', '.join(missing)}")
    how_to = (
        "Every page is a notebook shown with the outputs it was committed with. The download button "
        "at the top of a page (↓, then `.ipynb`) gives you the notebook itself; to run it you need "
        "`course_lib` and the packages of `environment.txt` (see *Start here*)."
    )
    licence = (
        "## Licence\n\nThe lesson text and figures are licensed CC-BY-4.0 (`LICENSE-content`); the code — "
        "`course_lib`, the tools and the tests — BSD-3-Clause (`LICENSE`)."
    )
    return "\n\n".join([title, paragraphs[0], how_to, lesson_map, licence]) + "\n"


def table_of_contents() -> str:
    """Jupyter Book's ``_toc.yml``: the landing page, then the lessons, then the exercises."""
    def chapters(paths):
        return "".join(f"      - file: {_relative(path)[: -len('.ipynb')]}\n" for path in paths)

    return (
        "# generated by tools/build_site.py from the notebooks present\n"
        "format: jb-book\nroot: index\nparts:\n"
        "  - caption: Lessons\n    chapters:\n" + chapters(lesson_paths())
        + "  - caption: Exercises\n    chapters:\n" + chapters(exercise_paths())
    )


def display_copy(notebook: nbformat.NotebookNode) -> nbformat.NotebookNode:
    """The notebook as the site shows it: nothing in it loads from outside the site.

    Widget views go (an output keeps its other representations, such as the explorer's
    ``image/png``; an output left with only the widget's text repr goes altogether), and the
    CDN icon-font link of matplotlib animation players goes.
    """
    shown = copy.deepcopy(notebook)
    shown.metadata.pop("widgets", None)
    for cell in shown.cells:
        if cell.cell_type != "code":
            continue
        outputs = []
        for output in cell.outputs:
            data = output.get("data")
            if data is not None and WIDGET_VIEW in data:
                data.pop(WIDGET_VIEW)
                if set(data) <= {"text/plain"}:
                    continue
            if data is not None and "text/html" in data:
                html = data["text/html"]
                html = "".join(html) if isinstance(html, list) else html
                data["text/html"] = CDN_ICON_LINK.sub("", html)
            outputs.append(output)
        cell.outputs = outputs
    return shown


def _write_if_changed(path: pathlib.Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def stage() -> list[pathlib.Path]:
    """Write ``_build/source/``; returns the staged notebooks."""
    STAGE.mkdir(parents=True, exist_ok=True)
    _write_if_changed(STAGE / "_config.yml", SITE_CONFIG.read_text(encoding="utf-8"))
    _write_if_changed(STAGE / "_toc.yml", table_of_contents())
    _write_if_changed(STAGE / "index.md", landing_page((ROOT / "README.md").read_text(encoding="utf-8")))
    staged = []
    for path in page_paths():
        target = STAGE / path.relative_to(ROOT)
        shown = display_copy(nbformat.read(path, as_version=4))
        _write_if_changed(target, nbformat.writes(shown) + "\n")
        staged.append(target)
    wanted = set(staged)
    for old in STAGE.glob("notebooks/**/*.ipynb"):  # a notebook renamed or removed since the last build
        if old not in wanted:
            old.unlink()
    return staged


def build() -> None:
    """Run Jupyter Book on the staged tree; the HTML lands in ``_build/html``."""
    jupyter_book = pathlib.Path(sys.executable).parent / "jupyter-book"
    command = [str(jupyter_book), "build", str(STAGE), "--path-output", str(ROOT), "--builder", "html"]
    result = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    log = result.stdout + result.stderr
    (BUILD / "site-build.log").write_text(log, encoding="utf-8")
    warnings = [line for line in log.splitlines() if "WARNING" in line]
    for line in warnings:
        print(line)
    if result.returncode != 0 or not (HTML / "index.html").exists():
        sys.stdout.write(log[-4000:])
        raise SiteError(f"jupyter-book build failed (exit code {result.returncode}): _build/site-build.log")


def publish_committed_notebooks() -> None:
    """Each page's download serves the committed notebook, not its display copy."""
    for path in page_paths():
        target = HTML / "_sources" / path.relative_to(ROOT)
        if not target.exists():
            raise SiteError(f"the build has no download copy of {_relative(path)} ({target} missing)")
        shutil.copyfile(path, target)


def mathjax_entry() -> str:
    """The MathJax component the pages load, as ``mathjax_path`` in ``site/_config.yml`` names it."""
    config = yaml.safe_load(SITE_CONFIG.read_text(encoding="utf-8"))
    path = config["sphinx"]["config"]["mathjax_path"]
    if "://" in path or not path.startswith("mathjax/"):
        raise SiteError(f"mathjax_path must name a file under _static/mathjax/, not {path!r}")
    return path.split("/", 1)[1]


def prune_mathjax() -> None:
    """Drop the combined MathJax components other than the one the pages load (none loads another)."""
    folder = HTML / "_static" / "mathjax"
    entry = folder / mathjax_entry()
    if not entry.is_file():
        raise SiteError(f"the site has no {entry.relative_to(HTML)}")
    for component in folder.glob("*.js"):
        if component.name.startswith(("tex-", "mml-", "node-main")) and component != entry:
            component.unlink()


def outside_loads(html_root: pathlib.Path = HTML) -> list[str]:
    """``file: snippet`` for every tag or stylesheet rule of the site that loads from outside it."""
    found = []
    for path in sorted(html_root.rglob("*")):
        if path.suffix not in {".html", ".css"} or not path.is_file():
            continue
        text = path.read_text(encoding="utf-8", errors="replace")
        for pattern in OUTSIDE_LOADS:
            for match in pattern.finditer(text):
                found.append(f"{path.relative_to(html_root)}: {text[match.start(): match.start() + 120]}")
    return found


def site_size(html_root: pathlib.Path = HTML) -> int:
    return sum(path.stat().st_size for path in html_root.rglob("*") if path.is_file())


def main() -> int:
    started = time.monotonic()
    staged = stage()
    build()
    publish_committed_notebooks()
    prune_mathjax()
    outside = outside_loads()
    if outside:
        raise SiteError("pages load from outside the site:\n  " + "\n  ".join(outside))
    pages = [path for path in HTML.rglob("*.html") if "_static" not in path.parts]
    summary = {
        "pages": len(pages), "notebook_pages": len(staged),
        "size_mb": round(site_size() / 1e6, 1), "seconds": round(time.monotonic() - started, 1),
    }
    print(f"site: {HTML.relative_to(ROOT)}/index.html  {json.dumps(summary)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
