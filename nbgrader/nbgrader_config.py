# nbgrader's configuration for this course directory (nbgrader/): run nbgrader commands from here.
# `make nbgrader` (tools/export_nbgrader.py) writes source/exNN/ from notebooks/solutions/.
import functools
import pathlib
import shutil
from importlib.util import find_spec

from nbconvert.preprocessors import CSSHTMLHeaderPreprocessor, Preprocessor
from nbgrader.coursedir import CourseDirectory
from nbgrader.preprocessors import GetGrades
from traitlets import Bool

import nbgrader

c = get_config()  # noqa: F821 (provided by nbgrader when it loads this file)
COURSE = pathlib.Path(__file__).resolve().parent

# the course's name in nbgrader's exchange (release_assignment, collect, release_feedback need one);
# the exchange itself is the hub's, /srv/nbgrader/exchange unless c.Exchange.root says otherwise
c.CourseDirectory.course_id = "mechanism-kinematics"
# what a student finds in place of each solution block (the task's hint stays above it)
c.ClearSolutions.code_stub = {
    "python": "# Your answer here (replace the next line).\nraise NotImplementedError()",
}
c.ClearSolutions.text_stub = "Your answer here."
# the derivations run sympy: allow a slow machine more than the default 30 s per cell
c.ExecutePreprocessor.timeout = 300
# students and assignments are added to the gradebook as they appear
c.CourseDirectory.db_url = "sqlite:///gradebook.db"

# Feedback that typesets offline: nbgrader's feedback template, with MathJax 3 in each page and in
# feedback/mathjax/ (templates/feedback_offline/mathjax.html.j2) instead of a CDN, and long messages wrapped.
MATHJAX_PACKAGE = "sphinx-mathjax-offline"  # on PyPI: MathJax 3's files, the same the course website uses
MATHJAX_ENTRY = "tex-svg.js"


class LocalMathJax(Preprocessor):
    """Puts a copy of MathJax 3 in feedback/mathjax/ (once), where a page loads what MathJax loads lazily; the
    combined component itself is in each page (:func:`course_mathjax`), so a page fetched alone into a
    student's folder (through the hub) still typesets offline."""

    enabled = Bool(True)

    def preprocess(self, nb, resources):
        coursedir = CourseDirectory(config=self.config)
        page_folder = coursedir.format_path(coursedir.feedback_directory, resources["nbgrader"]["student"],
                                            resources["nbgrader"]["assignment"])
        target = pathlib.Path(page_folder).parent.parent / "mathjax"  # "../../mathjax/" from a page
        if not (target / MATHJAX_ENTRY).is_file():
            spec = find_spec(MATHJAX_PACKAGE)
            if spec is None:
                self.log.warning("%s is not installed: the feedback's formulas stay LaTeX (pip install %s)",
                                 MATHJAX_PACKAGE, MATHJAX_PACKAGE)
                return nb, resources
            source = pathlib.Path(spec.origin).parent / "static" / "mathjax"
            # one combined component is loaded; the others are left out, what it loads lazily is kept
            others = [path.name for path in source.glob("*.js")
                      if path.name.startswith(("tex-", "mml-", "node-main")) and path.name != MATHJAX_ENTRY]
            shutil.copytree(source, target, ignore=shutil.ignore_patterns(*others), dirs_exist_ok=True)
        return nb, resources


@functools.cache
def course_mathjax(_: object = None) -> str:
    """MathJax's combined component as text, for the page itself (the template's ``course_mathjax`` filter);
    "" where the package is missing or the text could not stand in a ``<script>`` element."""
    spec = find_spec(MATHJAX_PACKAGE)
    if spec is None:
        return ""
    entry = pathlib.Path(spec.origin).parent / "static" / "mathjax" / MATHJAX_ENTRY
    script = entry.read_text(encoding="utf-8")
    return "" if "</script" in script.lower() else script


c.GenerateFeedback.preprocessors = [GetGrades, CSSHTMLHeaderPreprocessor, LocalMathJax]
c.HTMLExporter.template_name = "feedback_offline"
c.HTMLExporter.filters = {"course_mathjax": course_mathjax}
c.HTMLExporter.extra_template_basedirs = [
    str(COURSE / "templates"),
    str(pathlib.Path(nbgrader.__file__).parent / "server_extensions" / "formgrader" / "templates"),
]
