# Two commands do all set-up on a fresh clone: `make run` and `make test` (uv is bootstrapped if missing).
# `make docs` builds the documentation site into site/.
SHELL := /bin/bash
export UV_PYTHON_DOWNLOADS := never
UV := $(shell command -v uv 2>/dev/null || echo .tools/bin/uv)
# uv itself: from PATH, else installed once into .tools/ with the machine's python3
UV_DEP := $(if $(filter .tools/bin/uv,$(UV)),.tools/bin/uv,)
PYTEST_ARGS ?= -n 2

.PHONY: run test lint docs bench bench-batch scenario pictures

.tools/bin/uv:
	python3 -m venv .tools
	.tools/bin/python -m pip install --quiet uv

run: | $(UV_DEP)
	$(UV) run omega-prime-visibility compile
	$(UV) run omega-prime-visibility run highway_merge.mcap --ego 0
	@echo "the command line: source .venv/bin/activate, then omega-prime-visibility --help"

lint: | $(UV_DEP)
	$(UV) run ruff check .
	$(UV) run ruff format --check .

test: lint docs | $(UV_DEP)
	$(UV) run pytest $(PYTEST_ARGS)

# the documentation site (docs/ -> site/), warnings as errors; open site/index.html
docs: | $(UV_DEP)
	NO_MKDOCS_2_WARNING=1 $(UV) run mkdocs build --strict --quiet

bench: | $(UV_DEP)
	$(UV) run python benchmarks/bench.py --long 30000
	$(UV) run python benchmarks/bench_sensors.py
	$(UV) run python benchmarks/pictures.py
	$(UV) run python benchmarks/agreement.py
	$(UV) run python benchmarks/first_call.py
	$(UV) run python benchmarks/bench_campaign.py
	$(UV) run python benchmarks/bench_choices.py --frames 300
	$(UV) run python benchmarks/bench_3d.py --quick

bench-batch: | $(UV_DEP)
	$(UV) run python benchmarks/bench_batch.py

scenario: | $(UV_DEP)
	$(UV) run python scenarios/highway_merge.py -o highway_merge.mcap

pictures: | $(UV_DEP)
	$(UV) run python scripts/make_pictures.py
