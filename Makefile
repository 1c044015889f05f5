# rcb4hv developer commands. Every target creates .venv if it is missing.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test bench fuzz reliability screenshots clean

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

# browser screenshots of every page (headless Chromium) copied to docs/ for the README
screenshots: $(VENV)/.installed-dev
	rm -rf build/screenshots
	RCB4HV_REQUIRE_BROWSER=1 $(BIN)/pytest -q tests/ui/test_browser.py
	mkdir -p docs
	cp build/screenshots/servos.png build/screenshots/remote.png build/screenshots/project.png docs/

fuzz: $(VENV)/.installed-dev
	HYPOTHESIS_PROFILE=fuzz RCB4HV_FUZZ_EXAMPLES=20000 $(BIN)/pytest -q tests/reliability -k fuzz --timeout=0

reliability: $(VENV)/.installed-dev
	$(BIN)/python -m bench.reliability

clean:
	rm -rf $(VENV) .mypy_cache .pytest_cache .ruff_cache build/screenshots
