# nbgrader's configuration for this course directory (nbgrader/): run nbgrader commands from here.
# `make nbgrader` (tools/export_nbgrader.py) writes source/exNN/ from notebooks/solutions/.
c = get_config()  # noqa: F821 (provided by nbgrader when it loads this file)

# what a student finds in place of each solution block (the task's hint stays above it)
c.ClearSolutions.code_stub = {
    "python": "# Your answer here (replace the next line).\nraise NotImplementedError()",
}
c.ClearSolutions.text_stub = "Your answer here."
# the derivations run sympy: allow a slow machine more than the default 30 s per cell
c.ExecutePreprocessor.timeout = 300
# students and assignments are added to the gradebook as they appear
c.CourseDirectory.db_url = "sqlite:///gradebook.db"
