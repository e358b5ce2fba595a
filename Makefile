# Two commands on a fresh machine with Python 3.11 and make:
#   make demo   create .venv, install, run the main job on a small budget
#   make test   create .venv, install with test extras, run the whole suite
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test typecheck lint bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

demo: $(VENV)/.installed
	mkdir -p demo
	$(BIN)/locustjump model --out demo/locust.xml --force
	# the paper's stages on the small demo budget, without the monolithic
	# baseline: what results/demo-seed0 ships. On an idle 2-core VM 6.6 min
	# (about 2.7 of them rendering the videos; README, The demo). A second
	# `make demo` continues an interrupted reproduction
	$(BIN)/locustjump reproduce --budget demo --seed 0 --no-monolithic --out demo/reproduce

test: $(VENV)/.installed typecheck
	$(BIN)/ruff check src tests benchmarks scripts
	$(BIN)/lint-imports --no-cache
	$(BIN)/python -m pytest -q -rs  # -rs: say why a test was skipped

# mypy as [tool.mypy] in pyproject.toml says: strict on sim, evo and rundir
typecheck: $(VENV)/.installed
	$(BIN)/mypy

bench: $(VENV)/.installed
	$(BIN)/python benchmarks/throughput.py
	$(BIN)/python benchmarks/generation.py --behaviour kick
	$(BIN)/python benchmarks/generation.py --behaviour getup --generations 4 --warmup 1

clean:
	rm -rf $(VENV) demo
