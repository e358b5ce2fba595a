# Two commands on a fresh machine with Python 3.11 and make:
#   make demo   create .venv, install, run the main job on a small budget
#   make test   create .venv, install with test extras, run the whole suite
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test lint bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@

demo: $(VENV)/.installed
	mkdir -p demo
	$(BIN)/locustjump model --out demo/locust.xml --force
	$(BIN)/locustjump rules --out demo/rules --force
	# a second `make demo` resumes (a finished run: nothing to do) instead of clobbering
	$(BIN)/locustjump train kick --population 50 --generations 30 --out demo/kick \
		$$(test -f demo/kick/config.toml && echo --resume)
	$(BIN)/locustjump evaluate demo/kick

test: $(VENV)/.installed
	$(BIN)/ruff check src tests benchmarks scripts
	$(BIN)/python -m pytest -q

bench: $(VENV)/.installed
	$(BIN)/python benchmarks/throughput.py
	$(BIN)/python benchmarks/generation.py --behaviour kick

clean:
	rm -rf $(VENV) demo
