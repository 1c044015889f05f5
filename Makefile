# rcb4hv developer commands. Every target creates .venv if it is missing.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test docs package bench fuzz reliability sensitivity samples gait-plots screenshots clean

$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed-plot: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[plot,sim]'
	touch $@

$(VENV)/.installed-dev: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[dev,plot,docs,sim,gait,scale,test]'
	touch $@ $(VENV)/.installed-plot

$(VENV)/.installed-bench: pyproject.toml $(VENV)/.installed-dev
	$(BIN)/python -m pip install --quiet -e '.[dev,plot,bench]'
	touch $@

demo: $(VENV)/.installed-plot
	$(BIN)/rcb4hv demo --output demo-servo-angles.png

# everything a fresh machine needs is set up here, the browser included (tools/ensure-browser
# installs Chromium if it is missing); RCB4HV_SKIP_BROWSER=1 skips the browser tests, and the
# pytest summary says so
test: $(VENV)/.installed-dev
	tools/ensure-browser $(BIN)/python
	$(BIN)/python tools/unasync.py --check
	$(BIN)/ruff check src tests bench tools
	$(BIN)/mypy --strict src
	$(BIN)/pytest -q
	$(MAKE) --no-print-directory docs package

# the documentation site, strictly: a broken link or reference fails the build
docs: $(VENV)/.installed-dev
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --quiet --site-dir .build/site

# wheel + sdist, then the wheel alone in a fresh venv: `rcb4hv --version` and the demo run
package: $(VENV)/.installed-dev
	rm -rf .build/dist .build/venv
	$(BIN)/python -m build --no-isolation --outdir .build/dist . >/dev/null
	$(PY) -m venv .build/venv
	.build/venv/bin/python -m pip install --quiet "$$(ls .build/dist/*.whl)[plot]"
	.build/venv/bin/rcb4hv --version
	.build/venv/bin/python -m rcb4hv --version
	cd .build && venv/bin/rcb4hv demo --speed 4 --output demo.png >/dev/null
	test -s .build/demo.png && tar tzf .build/dist/*.tar.gz | grep -q 'src/rcb4hv/aio/client.py'
	@echo "package: wheel and sdist built; the wheel runs rcb4hv --version and the demo"

bench: $(VENV)/.installed-bench
	$(BIN)/python -m bench.run

# browser screenshots of every page (headless Chromium) copied to docs/ for the README
screenshots: $(VENV)/.installed-dev
	rm -rf build/screenshots
	tools/ensure-browser $(BIN)/python
	# Japanese motion names need a CJK font (Debian's IPA Gothic); without one they draw as boxes
	fc-list | grep -qi ipa || ! command -v apt-get >/dev/null || apt-get install -y -q fonts-ipafont-gothic
	$(BIN)/pytest -q tests/ui/test_browser.py tests/ui/test_browser3d.py tests/ui/test_posing_browser.py tests/ui/test_flow_editor_browser.py
	mkdir -p docs
	cp build/screenshots/servos.png build/screenshots/remote.png build/screenshots/project.png docs/
	cp build/screenshots/program-panel.png docs/
	cp build/screenshots/3d-view.png build/screenshots/3d-preview.png docs/
	cp build/screenshots/posing-handles.png build/screenshots/posing-balance.png docs/

fuzz: $(VENV)/.installed-dev
	HYPOTHESIS_PROFILE=fuzz RCB4HV_FUZZ_EXAMPLES=20000 $(BIN)/pytest -q tests/reliability -k fuzz --timeout=0

reliability: $(VENV)/.installed-dev
	$(BIN)/python -m bench.reliability

# which physics verdicts flip when a chosen constant changes (~10 CPU-minutes; docs/physics.md)
# SENSITIVITY_EXTRA=DIR adds every .h4p below DIR (e.g. local copies of Kondo's samples)
sensitivity: $(VENV)/.installed-dev
	nice -n 10 $(BIN)/python -m bench.sensitivity $(if $(SENSITIVITY_EXTRA),--extra $(SENSITIVITY_EXTRA))

# labelled outcomes of every .h4p below SAMPLES (local copies of Kondo's sample projects, kept
# outside the repository): a table per project and a summary (~1-10 CPU-minutes a project)
samples: $(VENV)/.installed-dev
	@test -n "$(SAMPLES)" || (echo "usage: make samples SAMPLES=DIR [NO_SLIP=1]" && false)
	mkdir -p build
	nice -n 10 $(BIN)/python tools/sample_outcomes.py --jobs 2 $(if $(NO_SLIP),--no-slip) $(SAMPLES) > build/samples.md
	sed -n '/^## Summary/,$$p' build/samples.md

clean:
	rm -rf $(VENV) .build .mypy_cache .pytest_cache .ruff_cache build/screenshots

# the plots of docs/gait.md: a generated walk's CoM and ZMP, fall probability against stride
gait-plots: $(VENV)/.installed-dev
	nice -n 10 $(BIN)/python -m bench.gait_plots --out docs
