# radscene — `make demo` and `make test` are all a fresh machine needs (Python >= 3.11).
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-stamp

.PHONY: demo test validate bench lint clean lowtran atmosphere-db docs schema

$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e '.[dev]'
	@touch $(STAMP)

demo: $(STAMP)  ## render the bundled demo scene into out/demo
	$(BIN)/radscene render src/radscene/examples/demo.yaml -o out/demo --overwrite

test: $(STAMP)  ## the test suite (unit, system, regression, validation), minus slow cases
	$(BIN)/python -m pytest -q -n 2 -m "not slow"

validate: $(STAMP)  ## every test, the long validations included
	$(BIN)/python -m pytest -q

bench: $(STAMP)  ## benchmarks; figures go to docs/benchmarks.md by hand
	$(BIN)/python benchmarks/bench_render.py --warmup --repeat 5
	$(BIN)/python benchmarks/bench_sensor.py
	$(BIN)/python benchmarks/bench_brdf.py
	$(BIN)/python benchmarks/bench_thermal.py
	$(BIN)/python benchmarks/bench_thermal.py --day --nodes 10  # the target: a day at 60 s <= 10 s
	$(BIN)/python benchmarks/bench_thermal_exposure.py
	$(BIN)/python benchmarks/bench_hyperspectral.py
	$(BIN)/python benchmarks/bench_background.py
	$(BIN)/python benchmarks/bench_motion.py
	$(BIN)/python benchmarks/bench_motion.py --refit
	$(BIN)/python benchmarks/bench_realtime.py
	$(BIN)/python benchmarks/bench_volumes.py

lowtran: $(STAMP)  ## build LOWTRAN7 for the `lowtran` atmosphere engine (needs gfortran)
	$(BIN)/radscene atmosphere build-lowtran --check

atmosphere-db: $(STAMP)  ## rebuild the shipped atmospheric database (6S; LOWTRAN after `make lowtran`)
	$(BIN)/radscene atmosphere build default -o src/radscene/data/atmosphere/default.nc

$(VENV)/.docs-stamp: $(STAMP) pyproject.toml
	$(BIN)/python -m pip install -q -e '.[dev,docs]'
	@touch $@

docs: $(VENV)/.docs-stamp  ## the documentation site into site/ (MkDocs, strict: any warning fails)
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --site-dir site

schema: $(STAMP)  ## the JSON schema of scene files, for editors (see docs/editor.md)
	$(BIN)/radscene schema -o scene.schema.json

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks scripts

clean:
	rm -rf out build dist site .pytest_cache .ruff_cache
