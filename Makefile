# Two commands: `make lab` (open the lessons) and `make test` (prove they all work).
# Both create .venv. `make lab` installs the student set (environment.txt); `make test` and the other
# developer targets the whole set (environment-dev.txt, which includes environment.txt). Each set is
# re-installed when its file (or pyproject.toml) changes. Before it creates anything, each checks the Python: one
# outside SUPPORTED_PYTHONS (or none) stops it with a one-line message. .venv is made again when its python no longer
# runs, is another version than it was made with (.venv/.python records which) or is not the one PYTHON names.
PYTHON ?= python3
# the Pythons the collection supports, oldest to newest (README's "Needs Python …" says the same; make lab and make
# test refuse any other; make test-pythons' PYTHONS below tests them all)
SUPPORTED_PYTHONS := 3.11 3.12 3.13
VENV   := .venv
BIN    := $(VENV)/bin
STUDENT_STAMP := $(VENV)/.installed-student
DEV_STAMP     := $(VENV)/.installed-dev
PYTHON_STAMP  := $(VENV)/.python
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

.PHONY: FORCE lab lab-instructor check test test-portable test-pythons execute exercises bench clean site nbgrader dist

# every install takes the locked versions; after changing a pin, `make test LOCK=` installs without the lock and
# `.venv/bin/python tools/lock.py` writes the new one (CONTRIBUTING.md)
LOCK ?= -c environment.lock

$(STUDENT_STAMP): environment.txt environment.lock pyproject.toml $(PYTHON_STAMP)
	$(PIP) $(LOCK) -r environment.txt
	touch $@

$(DEV_STAMP): environment-dev.txt environment.txt environment.lock pyproject.toml $(PYTHON_STAMP)
	$(PIP) $(LOCK) -r environment-dev.txt
	touch $@ $(STUDENT_STAMP)

# An interpreter as .venv/.python records it, "X.Y /its/real/path" (a venv's python answers with the Python
# it was made from)
PY_ID := import os, sys; sys.stdout.write("%d.%d %s\n" % (sys.version_info[0], sys.version_info[1], \
	os.path.realpath(getattr(sys, "_base_executable", sys.executable))))
# PYTHON named (command line or environment): .venv must be made by that one; else any working .venv of a supported
# version stays, whichever Python made it
PYTHON_NAMED := $(if $(filter file default,$(origin PYTHON)),,yes)
PY_RANGE := $(firstword $(SUPPORTED_PYTHONS))–$(lastword $(SUPPORTED_PYTHONS))
PY_GOAL  := $(firstword $(filter-out clean,$(MAKECMDGOALS)) lab)
# sh functions: `supported X.Y`; `empty_venv` removes what .venv holds but .venv/pythons/ (make test-pythons' venvs);
# `check_python` puts PYTHON's "X.Y /path" into $$asked or, when PYTHON is missing, does not run or is of another
# version, says so in one line (naming a supported pythonX.Y on the PATH if there is one) and exits 1
PY_SH := supported() { case " $(SUPPORTED_PYTHONS) " in *" $$1 "*) return 0;; esac; return 1; }; \
	empty_venv() { \
	  for entry in $(VENV)/* $(VENV)/.[!.]*; do case $$entry in $(VENV)/pythons) ;; *) rm -rf "$$entry";; esac; done; \
	}; \
	check_python() { \
	  where=`command -v $(PYTHON) 2>/dev/null` || where=; asked=; \
	  test -z "$$where" || asked=`$(PYTHON) -c '$(PY_ID)' 2>/dev/null` || asked=; \
	  if test -n "$$asked" && supported $${asked%% *}; then return 0; fi; \
	  hint=; for v in $(SUPPORTED_PYTHONS); do \
	    case `python$$v -c '$(PY_ID)' 2>/dev/null` in "$$v "*) hint=python$$v;; esac; done; \
	  if test -z "$$where"; then found="$(PYTHON) was not found"; \
	  elif test -z "$$asked"; then found="$(PYTHON) at $$where does not run"; \
	  else found="found $${asked%% *} at $$where"; fi; \
	  if test -n "$$hint"; then todo="run \`make $(PY_GOAL) PYTHON=$$hint\`"; \
	  else todo="install one and run \`make $(PY_GOAL) PYTHON=python$(lastword $(SUPPORTED_PYTHONS))\`"; fi; \
	  echo "needs Python $(PY_RANGE); $$found — $$todo" >&2; exit 1; \
	}

# Runs every time, before anything is installed. Keeps .venv when its python runs, is the version .venv/.python
# records, is supported and (PYTHON named) is PYTHON; else checks PYTHON, makes .venv again with it (keeping
# .venv/pythons/) and writes .venv/.python anew, so both sets are installed again. A venv that failed half-way
# (Debian without python3.X-venv) is removed, so the next run makes it again.
$(PYTHON_STAMP): FORCE
	@$(PY_SH); \
	have=`$(BIN)/python -c '$(PY_ID)' 2>/dev/null` || have=; made=`cat $@ 2>/dev/null` || made=; stale=; asked=; \
	if test -n "$$have"; then \
	  if test -n "$$made" && test "$${made%% *}" != "$${have%% *}"; then \
	    stale="it was made with Python $${made%% *}, its python is now $${have%% *}"; \
	  elif ! supported $${have%% *}; then stale="it was made with Python $${have%% *}"; fi; \
	elif test -f $(VENV)/pyvenv.cfg || test -h $(BIN)/python || test -e $(BIN)/python; then \
	  stale="its python does not run"; fi; \
	if test -n "$(PYTHON_NAMED)" || test -z "$$have" || test -n "$$stale"; then check_python; fi; \
	if test -n "$$have" && test -z "$$stale" && test -n "$$asked" && test "$$have" != "$$asked"; then \
	  stale="it was made by $${have#* } ($${have%% *}), PYTHON=$(PYTHON) is $${asked#* } ($${asked%% *})"; fi; \
	if test -n "$$have" && test -z "$$stale"; then \
	  test "$$made" = "$$have" || { printf '%s\n' "$$have" > $@ && touch -r $(VENV)/pyvenv.cfg $@; }; exit 0; fi; \
	if test -n "$$stale"; then \
	  test -f $(VENV)/pyvenv.cfg || { \
	    echo "$(VENV) is not a virtual environment (no pyvenv.cfg): remove it" >&2; exit 1; }; \
	  echo "making $(VENV) again: $$stale"; empty_venv; \
	fi; \
	echo "$(PYTHON) -m venv $(VENV)"; $(PYTHON) -m venv $(VENV) || { empty_venv; exit 1; }; \
	printf '%s\n' "$$asked" > $@

FORCE:

# JupyterLab's settings for this project (no news pop-up): tools/lab-settings/overrides.json; the server's (kernels
# with encrypted sockets, so none prints ipykernel's "running over TCP without encryption"):
# tools/lab-settings/jupyter_server_config.py. `make lab` is the
# students' route: the file browser lists the lessons and the exercise copies, not notebooks/solutions/ (Jupyter
# server's default hidden names plus "solutions"); `make lab-instructor` lists everything.
LAB_HIDDEN := "__pycache__", "*.pyc", "*.pyo", ".DS_Store", "*~", "*.so", "*.dylib"
LAB_START = mkdir -p $(VENV)/share/jupyter/lab/settings && \
	cp tools/lab-settings/overrides.json $(VENV)/share/jupyter/lab/settings/overrides.json && \
	$(BIN)/jupyter lab $(LAB_ROOT) --config=tools/lab-settings/jupyter_server_config.py \
	--ServerApp.root_dir=notebooks --LabApp.default_url=/lab/tree/00_start_here.ipynb

lab: $(STUDENT_STAMP)
	$(LAB_START) --ContentsManager.hide_globs='[$(LAB_HIDDEN), "solutions"]' $(LAB_ARGS)

lab-instructor: $(STUDENT_STAMP)
	$(LAB_START) --ContentsManager.hide_globs='[$(LAB_HIDDEN)]' $(LAB_ARGS)

# a student's check that one notebook runs top to bottom without an error (the student set alone):
# make check NOTEBOOK=notebooks/exercises/ex01_vector_loops_and_mobility.ipynb
check: $(STUDENT_STAMP)
	@test -n "$(NOTEBOOK)" || { echo "name the notebook: make check NOTEBOOK=notebooks/exercises/ex01_vector_loops_and_mobility.ipynb" >&2; exit 2; }
	$(BIN)/python -m pytest -p no:cacheprovider --nbval-lax --nbval-current-env -o addopts= $(NOTEBOOK)

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
