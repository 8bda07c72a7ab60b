# ik7r: every target sets up a local .venv first; nothing else is needed.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: demo test bench lint docs typecheck clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test,docs]"
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/ik7r demo

# ruff, the static types of the public API, every test (with the code of the README, the docs
# pages and the docstrings), then the documentation site with warnings as errors
test: $(STAMP)
	$(BIN)/ruff check src tests $(wildcard benchmarks) $(wildcard examples) docs/conf.py docs/_ext
	$(BIN)/python -m mypy
	$(BIN)/python -m pytest
	$(BIN)/python -m sphinx -b html -W --keep-going -q docs docs/_build/html

# the documentation site, offline, into docs/_build/html (the gallery's figures are drawn here)
docs: $(STAMP)
	$(BIN)/python -m sphinx -b html -q docs docs/_build/html

typecheck: $(STAMP)
	$(BIN)/python -m mypy

bench: $(STAMP)
	$(BIN)/python benchmarks/run.py
	$(BIN)/python benchmarks/edges.py
	$(BIN)/python benchmarks/film.py

lint: $(STAMP)
	$(BIN)/ruff check src tests $(wildcard benchmarks) $(wildcard examples) docs/conf.py docs/_ext

clean:
	rm -rf $(VENV) build src/*.egg-info .pytest_cache .mypy_cache docs/_build docs/auto_examples docs/api/generated docs/_generated
