# Two commands: `make lab` (open the lessons) and `make test` (prove they all work).
# Both create .venv. `make lab` installs the student set (environment.txt); `make test` and the other
# developer targets the whole set (environment-dev.txt, which includes environment.txt). Each set is
# re-installed when its file (or pyproject.toml) changes.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STUDENT_STAMP := $(VENV)/.installed-student
DEV_STAMP     := $(VENV)/.installed-dev
PIP := $(BIN)/python -m pip install --quiet --disable-pip-version-check
# JupyterLab refuses to run as root unless told; containers and CI often are root
LAB_ROOT := $(if $(filter 0,$(shell id -u)),--allow-root,)
export PYDEVD_DISABLE_FILE_VALIDATION := 1
# The portable pass: numpy and OpenBLAS on their baseline kernels and another hash seed, so the committed
# outputs are checked as a student's different CPU computes them (x86-64; elsewhere only the seed changes)
PORTABLE_ENV := PYTHONHASHSEED=1 $(if $(filter x86_64,$(shell uname -m)),\
	NPY_DISABLE_CPU_FEATURES="X86_V3 X86_V4 AVX512_ICL AVX512_SPR" OPENBLAS_CORETYPE=Prescott,)
NBVAL := --nbval --nbval-current-env --nbval-sanitize-with tests/sanitize.cfg --nbval-cell-timeout=600
# make test-pythons: the versions it tests (each in a venv of its own, .venv/pythons/X.Y)
PYTHONS ?= 3.11 3.12 3.13

.PHONY: lab test test-portable test-pythons execute exercises bench clean site nbgrader dist

$(STUDENT_STAMP): environment.txt pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(PIP) -r environment.txt
	touch $@

$(DEV_STAMP): environment-dev.txt environment.txt pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(PIP) -r environment-dev.txt
	touch $@ $(STUDENT_STAMP)

# JupyterLab's settings for this project (no news pop-up): tools/lab-settings/overrides.json
lab: $(STUDENT_STAMP)
	mkdir -p $(VENV)/share/jupyter/lab/settings
	cp tools/lab-settings/overrides.json $(VENV)/share/jupyter/lab/settings/overrides.json
	$(BIN)/jupyter lab $(LAB_ROOT) --ServerApp.root_dir=notebooks --LabApp.default_url=/lab/tree/00_start_here.ipynb $(LAB_ARGS)

test: $(DEV_STAMP)
	$(BIN)/ruff check .
	$(BIN)/python -m pytest -rs -p xdist -n 2 --dist loadfile $(NBVAL)

test-portable: $(DEV_STAMP)
	$(PORTABLE_ENV) $(BIN)/python -m pytest -rs -p xdist -n 2 --dist loadfile $(NBVAL) notebooks

# the library's tests and doctests under every Python in PYTHONS, every notebook under the newest
test-pythons:
	$(PYTHON) tools/test_pythons.py $(PYTHONS)

execute: $(DEV_STAMP)
	$(BIN)/python tools/execute_notebooks.py $(NOTEBOOKS)

exercises: $(DEV_STAMP)
	$(BIN)/python tools/make_exercises.py

bench: $(STUDENT_STAMP)
	for script in benchmarks/bench_*.py; do echo "== $$script"; $(BIN)/python $$script || exit 1; done

# what the other targets make; nbgrader/nbgrader_config.py (tracked) stays
clean:
	rm -rf $(VENV) _build dist
	rm -rf nbgrader/source nbgrader/release nbgrader/submitted nbgrader/autograded nbgrader/feedback
	rm -f nbgrader/gradebook.db nbgrader/.nbgrader.log

# the course website, _build/html/index.html, and the whole course as one PDF, _build/html/course.pdf,
# from the committed outputs (nothing is executed)
site: $(DEV_STAMP)
	$(BIN)/python tools/build_site.py

# an nbgrader course source, nbgrader/source/exNN/, from notebooks/solutions/ (README: For instructors)
nbgrader: $(DEV_STAMP)
	$(BIN)/python tools/export_nbgrader.py

# the release's two bundles in dist/: the students' (lessons, exercises, course_lib) and the instructors'
# (everything tracked); needs only git and Python
dist:
	$(PYTHON) tools/make_dist.py
