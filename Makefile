# webline: the two set-up commands are `make run` (main job on the built-in line) and
# `make test` (the test suite). Both create .venv and install webline first (with every extra:
# `.[dev]`). `make docs` builds the documentation site into site/ (warnings are errors).
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: run test lint bench docs clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e ".[dev]"
	touch $(STAMP)

# `webline warm` compiles the simulation loops of runs and sweeps once (a minute or two the first
# time, about a second after): the run below and the user's next commands only load them.
run: $(STAMP)
	$(BIN)/webline warm
	$(BIN)/webline run hswl --scenario speed-change --out out/hswl

# The suite runs on every core (pytest-xdist, one test file per worker so that a file's
# fixtures are built once) after `webline warm` compiled the shared loops once (the workers then
# load them instead of each compiling them), then the tests marked `serial` (timed or
# signal-sensitive) alone;
# both parts always run and either failing fails the target.
test: $(STAMP)
	$(BIN)/webline warm
	status=0; \
	$(BIN)/python -m pytest -q -n auto --dist loadfile -m "not serial" || status=1; \
	$(BIN)/python -m pytest -q -m serial || status=1; \
	exit $$status

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks examples
	$(BIN)/mypy
	$(BIN)/python tests/unit/test_layers.py

docs: $(STAMP)
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --site-dir site

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_hswl.py

clean:
	rm -rf $(VENV) out site
