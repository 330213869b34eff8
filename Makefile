# Both targets build .venv from nothing (Python 3.11+ is all they need).
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test lint bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[dev]"
	touch $(STAMP)

demo: $(STAMP)
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
