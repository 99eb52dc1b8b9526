# sylva — every target creates .venv and installs what it needs.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: install demo test lint bench docs clean

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e ".[dev]"
	touch $(STAMP)

install: $(STAMP)

## The main job on the built-in examples (the kernels compiled ahead on all cores).
demo: $(STAMP)
	$(BIN)/sylva warmup
	$(BIN)/sylva demo

## The whole test suite (lint first; the kernels compiled ahead on all cores), the tests on
## all cores (pytest-xdist: whole modules per worker, the slowest first, tests/conftest.py).
## Serially: make test PYTEST_ARGS=
PYTEST_ARGS ?= -n auto --maxprocesses 8 --dist loadfile --no-loadscope-reorder
test: $(STAMP)
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/sylva warmup
	$(BIN)/python -m pytest -q $(PYTEST_ARGS)

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks

bench: $(STAMP)
	$(BIN)/python benchmarks/derive.py

## The documentation site in docs/_build/html (offline; warnings are errors).
$(VENV)/.installed-docs: pyproject.toml $(STAMP)
	$(BIN)/python -m pip install -q -e ".[docs]"
	touch $@

docs: $(VENV)/.installed-docs
	$(BIN)/python -m sphinx -W --keep-going -q -b html docs docs/_build/html

clean:
	rm -rf $(VENV) build dist docs/_build src/*.egg-info .pytest_cache .ruff_cache .hypothesis
