# Two commands on a fresh machine with Python 3.11 and make:
#   make demo   create .venv, install what the demo needs (extra video), run
#               the main job on a small budget
#   make test   create .venv, install with test extras, run the whole suite
#   make docs   build the documentation site into site/ (strict: a broken
#               link or API reference fails)
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test typecheck docs bench mutation clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# one stamp per set of extras: the demo needs neither the test tools nor Ray
$(VENV)/.demo-installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[video]'
	touch $@

$(VENV)/.test-installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

$(VENV)/.docs-installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[docs]'
	touch $@

demo: $(VENV)/.demo-installed
	mkdir -p demo
	$(BIN)/locustjump model --out demo/locust.xml --force
	# the paper's stages on the small demo budget, without the monolithic
	# baseline: what results/demo-seed0 ships. On an idle 2-core VM 6.6 min
	# (about 2.7 of them rendering the videos; docs/results.md, The demo). A second
	# `make demo` continues an interrupted reproduction
	$(BIN)/locustjump reproduce --budget demo --seed 0 --no-monolithic --out demo/reproduce

test: $(VENV)/.test-installed $(VENV)/.docs-installed typecheck  # test_docs.py: the site, strict
	$(BIN)/ruff check src tests benchmarks scripts
	$(BIN)/ruff format --check src tests benchmarks scripts
	$(BIN)/lint-imports --no-cache
	# -rs: say why a test was skipped; on as many workers as cores, at most 4
	# (pytest-xdist), each test file on one worker (its module fixtures made once;
	# not loadgroup: xdist 3.8 under pytest 9 ignores its groups)
	$(BIN)/python -m pytest -q -rs -n auto --maxprocesses 4 --dist loadfile

# mypy as [tool.mypy] in pyproject.toml says: strict on every module, script
# and benchmark
typecheck: $(VENV)/.test-installed
	$(BIN)/mypy

bench: $(VENV)/.demo-installed
	$(BIN)/python benchmarks/throughput.py
	$(BIN)/python benchmarks/generation.py --behaviour kick
	$(BIN)/python benchmarks/generation.py --behaviour getup --generations 4 --warmup 1

docs: $(VENV)/.docs-installed
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict  # into site/

$(VENV)/.mutation-installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[test,mutation]'
	touch $@

# mutmut on the core modules, one at a time, each against its focused tests;
# writes docs/mutation.md (under an hour on 2 cores: not part of `make test`)
mutation: $(VENV)/.mutation-installed
	$(BIN)/python scripts/mutation.py

clean:
	rm -rf $(VENV) demo site
