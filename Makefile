# webline: the two set-up commands are `make run` (main job on the built-in line) and
# `make test` (the test suite). Both create .venv and install webline first.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: run test lint bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e ".[dev]"
	touch $(STAMP)

run: $(STAMP)
	$(BIN)/webline run hswl --scenario speed-change --out out/hswl

test: $(STAMP)
	$(BIN)/python -m pytest -q

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks examples
	$(BIN)/mypy
	$(BIN)/python tests/unit/test_layers.py

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_hswl.py

clean:
	rm -rf $(VENV) out
