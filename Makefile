# Two commands: `make lab` (open the lessons) and `make test` (prove they all work).
# Both create .venv and install environment.txt when it is missing or out of date.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
# JupyterLab refuses to run as root unless told; containers and CI often are root
LAB_ROOT := $(if $(filter 0,$(shell id -u)),--allow-root,)
export PYDEVD_DISABLE_FILE_VALIDATION := 1
# The portable pass: numpy and OpenBLAS on their baseline kernels and another hash seed, so the committed
# outputs are checked as a student's different CPU computes them (x86-64; elsewhere only the seed changes)
PORTABLE_ENV := PYTHONHASHSEED=1 $(if $(filter x86_64,$(shell uname -m)),\
	NPY_DISABLE_CPU_FEATURES="X86_V3 X86_V4 AVX512_ICL AVX512_SPR" OPENBLAS_CORETYPE=Prescott,)
NBVAL := --nbval --nbval-current-env --nbval-sanitize-with tests/sanitize.cfg --nbval-cell-timeout=600

.PHONY: lab test test-portable execute exercises bench clean site nbgrader

$(STAMP): environment.txt pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -r environment.txt
	touch $(STAMP)

# JupyterLab's settings for this project (no news pop-up): tools/lab-settings/overrides.json
lab: $(STAMP)
	mkdir -p $(VENV)/share/jupyter/lab/settings
	cp tools/lab-settings/overrides.json $(VENV)/share/jupyter/lab/settings/overrides.json
	$(BIN)/jupyter lab $(LAB_ROOT) --ServerApp.root_dir=notebooks --LabApp.default_url=/lab/tree/00_start_here.ipynb $(LAB_ARGS)

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/python -m pytest -rs -p xdist -n 2 --dist loadfile $(NBVAL)

test-portable: $(STAMP)
	$(PORTABLE_ENV) $(BIN)/python -m pytest -rs -p xdist -n 2 --dist loadfile $(NBVAL) notebooks

execute: $(STAMP)
	$(BIN)/python tools/execute_notebooks.py $(NOTEBOOKS)

exercises: $(STAMP)
	$(BIN)/python tools/make_exercises.py

bench: $(STAMP)
	for script in benchmarks/bench_*.py; do echo "== $$script"; $(BIN)/python $$script || exit 1; done

clean:
	rm -rf $(VENV)

# the course website, _build/html/index.html, from the committed outputs (nothing is executed)
site: $(STAMP)
	$(BIN)/python tools/build_site.py

# an nbgrader course source, nbgrader/source/exNN/, from notebooks/solutions/ (README: For instructors)
nbgrader: $(STAMP)
	$(BIN)/python tools/export_nbgrader.py
