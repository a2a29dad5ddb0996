# dyntorsion: `make test` and `make paper` work on a fresh machine with Python >= 3.11.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
PY     := $(BIN)/python

# The runs past self-contact call OpenBLAS and NumPy loops whose rounding differs in the
# last bit from one processor family to another (dyntorsion.store.environment); the
# committed records were computed with OpenBLAS's Haswell kernels and NumPy's AVX2 loops,
# asked for here wherever the processor has AVX2, so that reruns reproduce them bit for bit
# (NumPy's AVX-512 groups are asked of the venv's NumPy: the make that creates the venv pins
# OpenBLAS only; every record keeps the environment it was computed in)
ifneq ($(shell grep -m1 -ow avx2 /proc/cpuinfo 2>/dev/null),)
ifeq ($(origin OPENBLAS_CORETYPE),undefined)
export OPENBLAS_CORETYPE := Haswell
endif
ifeq ($(origin NPY_DISABLE_CPU_FEATURES),undefined)
NPY_AVX512 := $(shell test -x $(PY) && $(PY) -c "from dyntorsion.store.environment import numpy_avx512_groups as g; print(g())" 2>/dev/null)
ifneq ($(NPY_AVX512),)
export NPY_DISABLE_CPU_FEATURES := $(NPY_AVX512)
endif
endif
endif

# one BLAS thread: threaded OpenBLAS splits its sums differently from run to run under load,
# and the runs past self-contact grow that last-bit difference into visible round-off
ifeq ($(origin OPENBLAS_NUM_THREADS),undefined)
export OPENBLAS_NUM_THREADS := 1
endif

# every long step says how long it took (bash's `time`, one line after the step)
SHELL := /bin/bash
export TIMEFORMAT := (that step took %0R s)

.PHONY: test test-all paper docs data data-studies data-contact bench bench-matched bench-bounds bench-plateau roundoff lint clean distclean site-check release-check

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

$(VENV)/.test-installed: pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[test,docs]'
	touch $@

$(VENV)/.lint-installed: pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[lint]'
	touch $@

$(VENV)/.docs-installed: pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[test,docs]'
	touch $@

## test: compile the kernels (once), every notebook of the site at quick fidelity, then the fast test suite (what CI runs)
test: $(VENV)/.test-installed
	time $(BIN)/dyntorsion warmup
	time DYNTORSION_FIDELITY=quick $(PY) -m sphinx -E -q -W --keep-going -j auto -b html docs docs/_build/quick
	time $(PY) -m pytest -m "not slow" -q -n $(JOBS) --dist loadfile

## test-all: every test, including the long `slow` ones, property tests at many examples
test-all: $(VENV)/.test-installed
	DYNTORSION_HYPOTHESIS=long $(PY) -m pytest -q -n $(JOBS) --dist loadfile

## paper: recompute missing or stale data, regenerate every figure (paper/figures) and
## the at-a-glance numbers (paper/numbers.json), and build the documentation site
paper: $(VENV)/.docs-installed data
	time $(PY) -m sphinx -E -W --keep-going -j auto -b html docs docs/_build/html
	@echo
	@echo "Site built: open docs/_build/html/index.html"

docs: paper

## data: the records the paper's figures read (Figs 8-10: the rate sweeps, the direct runs
## of Figs 8 and 9, the grid check; `--preset paper`); records already current are kept.
## JOBS local processes.  data-studies: every other record the site reads (the studies
## beyond the paper: accuracy ladders, the tolerance study's hold-outs, linear predictions,
## traces, the consistency map); its cost is on the Benchmarks page
JOBS ?= 2
## ON_STALE=error: stop at a stale record instead of recomputing it (missing ones are
## computed); the bench times `make data` so, with every record current
ON_STALE ?= recompute
data: $(VENV)/.test-installed
	time $(BIN)/dyntorsion sweep --preset paper --jobs $(JOBS) --no-fit --on-stale $(ON_STALE)

data-studies: data
	$(BIN)/dyntorsion sweep --preset all --jobs $(JOBS) --no-fit --on-stale $(ON_STALE)
	$(BIN)/dyntorsion linear --preset all --jobs $(JOBS) --quiet --on-stale $(ON_STALE)
	$(PY) -m dyntorsion.studies.traces --on-stale $(ON_STALE)
	$(PY) -m dyntorsion.studies.wave_convergence --on-stale $(ON_STALE)
	$(PY) -m dyntorsion.studies.after_onset --on-stale $(ON_STALE)
	$(PY) -m dyntorsion.studies.accuracy_runs --on-stale $(ON_STALE)
	$(PY) -m dyntorsion.studies.consistency --jobs $(JOBS) --on-stale $(ON_STALE)
	$(PY) -m dyntorsion.studies.tolerance_tables --on-stale $(ON_STALE)
	$(PY) -m dyntorsion.studies.consistency_tables --on-stale $(ON_STALE)
	$(PY) -m dyntorsion.studies.preset_endings --on-stale $(ON_STALE)

## site-check: open every page of the quick build (made by `make test`; built here when
## missing), or of SITE=docs/_build/html after `make docs`, in headless Chromium: fails on
## untypeset maths, requests leaving the site, broken images/links, Python errors and
## reprs, glue placeholders, row numbers/nan/-0 in tables, sideways overflow, and on the
## word budgets (narrative words per page and in total, long sentences: docs/site_budget.py;
## without a browser: python docs/site_check.py SITE --budgets).
## Screenshots: docs/_build/screens/.  Installs Debian's chromium when it is missing.
SITE ?= docs/_build/quick
$(VENV)/.site-installed: pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[test,docs,site]'
	touch $@

site-check: $(VENV)/.site-installed
	@command -v chromium >/dev/null || { apt-get update -q && apt-get install -y -q chromium; }
	@test -f $(SITE)/index.html || test "$(SITE)" != docs/_build/quick || \
	  DYNTORSION_FIDELITY=quick $(PY) -m sphinx -E -q -W --keep-going -j auto -b html docs $(SITE)
	@test -f $(SITE)/index.html || { echo "site-check: no site in $(SITE) (make docs)"; exit 1; }
	$(PY) docs/site_check.py $(SITE) --screens docs/_build/screens --self-test

## lint: ruff check, ruff format --check and the import contracts of pyproject.toml
## (import-linter: the layers of the package and no import circle within a folder)
LINTED := src tests benchmarks docs/conf.py docs/site_check.py docs/site_budget.py \
  docs/site_selftest.py
lint: $(VENV)/.lint-installed
	$(BIN)/ruff check $(LINTED)
	$(BIN)/ruff format --check $(LINTED)
	$(BIN)/lint-imports

## release-check: CITATION.cff valid, dependencies declared (deptry), then the wheel and the
## sdist built, checked, and the wheel installed in a new environment and tried outside the
## checkout (.ci/wheel-smoke)
$(VENV)/.release-installed: pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[release]'
	touch $@

release-check: $(VENV)/.release-installed
	$(BIN)/cffconvert --validate -i CITATION.cff
	$(BIN)/deptry src
	bash .ci/wheel-smoke

## bench: every file of benchmarks/ (timings printed beside a peer or a floor, never
## asserted; PyElastica, the `bench` extra, is the peer of the last two)
bench: $(VENV)/.bench-installed
	$(PY) benchmarks/bench_engine.py
	$(PY) benchmarks/bench_scenes.py
	OPENBLAS_NUM_THREADS=1 $(PY) benchmarks/bench_contact.py
	$(PY) benchmarks/bench_targets.py --make-data
	$(PY) benchmarks/bench_today.py
	$(PY) benchmarks/bench_compile.py
	$(PY) benchmarks/plectoneme_matched.py --print
	$(PY) benchmarks/bench_pyelastica.py

$(VENV)/.bench-installed: pyproject.toml | $(PY)
	$(PY) -m pip install --quiet -e '.[test,bench]'
	touch $@

## bench-matched: PyElastica's plectoneme scene in both codes on a ladder of grids, timed in
## one run on one core (the record keeps each run's wall time); writes data/bench/plectoneme_matched.json, which
## `make bench` prints
bench-matched: $(VENV)/.bench-installed
	OPENBLAS_NUM_THREADS=1 $(PY) benchmarks/plectoneme_matched.py

## bench-bounds: PyElastica's plectoneme scene in dyntorsion on 400 and 500 cells with a
## stiffer contact, against the overlap and link bounds -> data/bench/plectoneme_bounds.json
bench-bounds: $(VENV)/.test-installed
	$(PY) -m dyntorsion.studies.contact.plectoneme_bounds --jobs $(JOBS)

## bench-plateau: slow twisting under tension on a 4 m rod into a plectoneme several turns
## long (the torque plateau against the two-ply theory) -> data/bench/plectoneme_plateau.json
bench-plateau: $(VENV)/.test-installed
	$(PY) -m dyntorsion.studies.contact.plectoneme_plateau

## roundoff: runs of the contact records repeated with other arithmetic (OpenBLAS's and
## NumPy's own choice of kernels, a seed perturbed by 1e-10) -> data/contact/roundoff.json
roundoff: $(VENV)/.test-installed
	$(PY) -m dyntorsion.studies.contact.contact_roundoff --jobs $(JOBS)

## data-contact: the records past self-contact in data/contact and data/bench (hours on
## two cores; records already complete and current are kept, a partial one is resumed);
## bench-matched, bench-bounds, bench-plateau and roundoff make the others
CONTACT_RECORDS := contact_convergence contact_budget contact_six_seconds fig07_continued \
                   plectoneme_dyntorsion
data-contact: $(VENV)/.test-installed
	$(foreach m,$(CONTACT_RECORDS),$(PY) -m dyntorsion.studies.contact.$(m) --jobs $(JOBS) &&) true
	$(PY) -m dyntorsion.studies.contact.plectoneme_tension

clean:
	rm -rf docs/_build docs/jupyter_execute paper/figures .pytest_cache
	find . -name __pycache__ -type d -prune -not -path './$(VENV)/*' -exec rm -rf {} +

distclean: clean
	rm -rf $(VENV)
