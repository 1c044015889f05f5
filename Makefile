# rcb4hv developer commands. Every target creates .venv if it is missing.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test bench fuzz reliability clean

$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed-plot: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[plot]'
	touch $@

$(VENV)/.installed-dev: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[dev,plot]'
	touch $@ $(VENV)/.installed-plot

$(VENV)/.installed-bench: pyproject.toml $(VENV)/.installed-dev
	$(BIN)/python -m pip install --quiet -e '.[dev,plot,bench]'
	touch $@

demo: $(VENV)/.installed-plot
	$(BIN)/rcb4hv demo --output demo-servo-angles.png

test: $(VENV)/.installed-dev
	$(BIN)/ruff check src tests bench
	$(BIN)/mypy --strict src
	$(BIN)/pytest -q

bench: $(VENV)/.installed-bench
	$(BIN)/python -m bench.run

fuzz: $(VENV)/.installed-dev
	HYPOTHESIS_PROFILE=fuzz RCB4HV_FUZZ_EXAMPLES=20000 $(BIN)/pytest -q tests/reliability -k fuzz --timeout=0

reliability: $(VENV)/.installed-dev
	$(BIN)/python -m bench.reliability

clean:
	rm -rf $(VENV) .mypy_cache .pytest_cache .ruff_cache
