# Both targets build .venv from nothing (Python 3.11+ is all they need).
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
BASE := $(VENV)/.installed-base

.PHONY: demo test lint bench clean

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

test: $(STAMP)
	$(BIN)/ruff check src tests examples docs
	$(BIN)/python -m pytest -q

lint: $(STAMP)
	$(BIN)/ruff check src tests examples docs
	$(BIN)/ruff format --check src tests examples docs

bench: $(STAMP)
	$(BIN)/jointattention bench

clean:
	rm -rf $(VENV) runs build src/*.egg-info
