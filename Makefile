# ins-errors: the two set-up commands are `make derive` and `make test`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
# The install is redone when the packaging files' contents change, not their dates: a fresh
# clone (every file dated now) beside a virtual environment restored from a CI cache keeps it.
INSTALL_INPUTS := pyproject.toml setup.py
STAMP  := $(VENV)/.installed-$(shell $(PYTHON) -c "import hashlib, sys; print(hashlib.sha256(b''.join(open(f, 'rb').read() for f in sys.argv[1:])).hexdigest()[:16])" $(INSTALL_INPUTS))

# Python's byte-compiled modules are kept inside the virtual environment (so `make clean`
# removes them and the source tree stays free of __pycache__ folders), and they are kept
# even where the shell sets PYTHONDONTWRITEBYTECODE: without them every run of the suite
# compiles the package and pytest rewrites every test file again (about a fifth of a warm
# `make test`). Child processes (CLI runs, Dask workers) inherit both settings.
export PYTHONPYCACHEPREFIX := $(abspath $(VENV))/pycache
unexport PYTHONDONTWRITEBYTECODE

.PHONY: derive test bench lint clean venv

$(STAMP):
	rm -f $(VENV)/.installed*
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

venv: $(STAMP)

## Regenerate generated/ from the model definitions and print a summary.
derive: $(STAMP)
	$(PY) -m derive

## Install into .venv (first time) and run the test suite, its files spread over up to
## four cores (pytest-xdist; each file's tests stay in one process, which shares their
## fixtures and compiled loops).
test: $(STAMP)
	$(PY) -m pytest -q -n auto --maxprocesses 4 --dist loadfile

## Speed figures (printed, never asserted).
bench: $(STAMP)
	$(PY) -m benchmarks

lint: $(STAMP)
	$(PY) -m ruff check .

## Remove the virtual environment, build files and this checkout's compiled loops.
clean:
	if [ -x $(PY) ]; then $(PY) -m ins_errors.cli cache clear --checkout; fi
	rm -rf $(VENV) build *.egg-info
