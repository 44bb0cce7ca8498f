# persistri: the two commands of the README.
#   make demo   create .venv, install, run the main job, write results to out/
#   make test   create .venv, install with the dev extras, run every check
#               (on the compiled twin too, where there is a C compiler)
PY      ?= python3
VENV    := .venv
BIN     := $(VENV)/bin
# Hypothesis profile: `ci` (thorough) when CI is set, `dev` (quick) otherwise.
PROFILE ?= $(if $(CI),ci,dev)
export HYPOTHESIS_PROFILE := $(PROFILE)

.PHONY: demo test install install-dev links typecheck pytest compiled twin-build pytest-twin proofs docs clean

$(BIN)/python:
	@$(PY) -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else "persistri needs Python 3.11 or newer; set PY=python3.11")'
	$(PY) -m venv $(VENV)
	@$(BIN)/python -m pip install -q --upgrade pip "setuptools>=77" wheel >$(VENV)/install.log 2>&1 \
		|| (cat $(VENV)/install.log; exit 1)

# The library and the `adapters` extra (immutables, pyrsistent: small wheels), which the demo's map
# benchmark compares persistri with.  pip's and setuptools' chatter (the strict editable install's
# notice) goes to a log, shown only if the install fails.
$(VENV)/.installed: pyproject.toml | $(BIN)/python
	@echo "installing persistri[adapters] into $(VENV) (log: $(VENV)/install.log)"
	@$(BIN)/python -m pip install -q -e ".[adapters]" --config-settings editable_mode=strict \
		>$(VENV)/install.log 2>&1 || (cat $(VENV)/install.log; exit 1)
	@touch $@

# lidar ships the second real DEM of `persistri experiments fig11` (lidar/data/dem.tif); only the
# file is used, so none of its (heavy, geospatial) dependencies are installed.
$(VENV)/.installed-dev: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[dev]" --config-settings editable_mode=strict
	$(BIN)/python -m pip install -q --no-deps "lidar==0.8.4"
	touch $@ $(VENV)/.installed

# A strict editable install is a tree of links made at install time: refresh it
# so that modules added since are importable (and visible to mypy).
links: | $(BIN)/python
	@$(BIN)/python -m pip install -q --no-deps --no-build-isolation -e . --config-settings editable_mode=strict \
		>$(VENV)/links.log 2>&1 || (cat $(VENV)/links.log; exit 1)

install: $(VENV)/.installed links
# `make test` installs once, then runs its checks in sub-makes with SKIP_INSTALL set.
ifdef SKIP_INSTALL
install-dev: ;
else
install-dev: $(VENV)/.installed-dev links
endif

demo: install
	$(BIN)/persistri demo --out out

typecheck: install-dev
	$(BIN)/mypy -p persistri
	$(BIN)/mypy tests/typing/consumer.py proofs tools
	$(BIN)/python tests/typing/check_rejections.py

pytest: install-dev
	$(BIN)/python -m pytest -n 2 -p no:cacheprovider --durations=15
	$(BIN)/python -m pytest -q -p no:cacheprovider --doctest-modules --doctest-glob='*.md' README.md docs --pyargs persistri.spec persistri.impl

# The compiled twin (tools/compiled_twin.py, docs/performance.md): the same source with the
# bulldozer's loop and its predicate kernel compiled by mypyc, in $(TWIN).  Built only on a machine
# with a C compiler and Python headers (persistri itself needs neither); where it is built, the
# test suite runs on it (below).
TWIN := build/compiled

compiled: install-dev
	$(BIN)/python tools/compiled_twin.py $(TWIN)

# Build the twin if this machine can (exit 2 from the builder: no C compiler or headers, so no twin).
twin-build: install-dev
	@$(BIN)/python tools/compiled_twin.py $(TWIN); status=$$?; \
	if [ $$status -eq 2 ]; then echo "twin-build: skipped, the compiled twin needs a C compiler and Python headers"; exit 0; fi; \
	exit $$status

# The suite on the twin, at the quick hypothesis profile: the thorough search of examples runs on the
# interpreted build (`pytest`); the twin is the same source compiled, and its run checks every test of
# compiled code on it (tests marked build_independent, whose subject the twin does not compile, are left out
# by tests/conftest.py).
pytest-twin: twin-build
	@$(BIN)/python tools/compiled_twin.py $(TWIN) >/dev/null; status=$$?; \
	if [ $$status -eq 2 ]; then echo "pytest-twin: skipped, no compiled twin on this machine"; exit 0; fi; \
	if [ $$status -ne 0 ]; then exit $$status; fi; \
	PYTHONPATH=$(TWIN) PERSISTRI_TWIN=1 HYPOTHESIS_PROFILE=dev $(BIN)/python -m pytest -n 2 -p no:cacheprovider -q

proofs: install-dev
	$(BIN)/python -m proofs

# The teaching reference: redraw its pictures from real runs (checking what they show),
# then build the site with warnings as errors (not --quiet: it silences the warnings --strict
# counts).  Its examples run in the doctest step above.
docs: install-dev
	$(BIN)/python docs/figures.py
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

# The single-threaded checks (mypy, the proofs' sympy part, the twin's compilation, the docs) run two at a
# time, each one's output printed whole when it ends; then the two pytest runs, each on both cores.
test: install-dev
	@$(MAKE) --no-print-directory SKIP_INSTALL=1 -j2 --output-sync=target typecheck proofs twin-build docs
	@$(MAKE) --no-print-directory SKIP_INSTALL=1 pytest pytest-twin
	@echo "make test: all checks passed"

clean:
	rm -rf $(VENV) out build site .mypy_cache .pytest_cache .hypothesis
