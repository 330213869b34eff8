# Both targets build .venv from nothing (Python 3.11+ is all they need).
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
BASE := $(VENV)/.installed-base

RL_VENV := .venv-rl
RL_BIN := $(RL_VENV)/bin
RL_STAMP := $(RL_VENV)/.installed
DOCS_STAMP := $(VENV)/.installed-docs

.PHONY: demo test test-rl lint bench docs clean

# The main job needs only the package; the tests need the extras too (gym, ray, rl).
$(BASE): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e .
	touch $(BASE)

$(STAMP): $(BASE)
	$(BIN)/python -m pip install --quiet -e ".[dev]"
	touch $(STAMP)

demo: $(BASE)
	$(BIN)/jointattention reproduce --preset paper --out runs/demo
	$(BIN)/jointattention report runs/demo
	@echo "open runs/demo/report.html; for the other commands: . $(VENV)/bin/activate"

# pytest-xdist spreads the tests over the cores (-n auto; each test keeps to its own folders).
test: $(STAMP)
	$(BIN)/ruff check src tests examples docs
	$(BIN)/python -m pytest -q -n auto

# The tests of Stable-Baselines3, in a venv of their own: PyTorch stays out of `make test`'s.
# torch 2.13.0 first: where the machine keeps a CPU build of it (pip's find-links), pip takes
# that one (about 0.7 GB) instead of PyPI's CUDA build (about 5 GB).
$(RL_STAMP): pyproject.toml
	$(PYTHON) -m venv $(RL_VENV)
	$(RL_BIN)/python -m pip install --quiet --upgrade pip
	$(RL_BIN)/python -m pip install --quiet "torch==2.13.0"
	$(RL_BIN)/python -m pip install --quiet -e ".[dev,rl]"
	touch $(RL_STAMP)

# One thread each: PyTorch trains these small policies faster on one thread than on two, and
# the tests run side by side (pytest-xdist).
test-rl: $(RL_STAMP)
	OMP_NUM_THREADS=1 $(RL_BIN)/python -m pytest -q -m rl -n auto

lint: $(STAMP)
	$(BIN)/ruff check src tests examples docs
	$(BIN)/ruff format --check src tests examples docs

bench: $(STAMP)
	$(BIN)/jointattention bench

# The manual (mkdocs.yml): docs/*.md, the tables the runs wrote (docs/results/) and the
# docstrings, into site/.
# --strict: a broken link, a missing included table or a docstring griffe cannot read fails.
$(DOCS_STAMP): $(BASE)
	$(BIN)/python -m pip install --quiet -e ".[docs]"
	touch $(DOCS_STAMP)

# Then no literal Sphinx role may be left in the pages (docs/griffe_roles.py rewrites them).
docs: $(DOCS_STAMP)
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --site-dir site
	! grep -rlE ':(py:)?(func|meth|class|mod|data|attr|exc|obj|const):(`|<code>)' site --include='*.html'

clean:
	rm -rf $(VENV) $(RL_VENV) runs build site src/*.egg-info
