# Two commands do all set-up on a fresh clone: `make run` and `make test` (uv is bootstrapped if missing).
SHELL := /bin/bash
export UV_PYTHON_DOWNLOADS := never
UV := $(shell command -v uv 2>/dev/null || echo .tools/bin/uv)
PYTEST_ARGS ?= -n 2

.PHONY: run test lint bench scenario

.tools/bin/uv:
	python3 -m venv .tools
	.tools/bin/python -m pip install --quiet uv

$(UV):
	$(MAKE) .tools/bin/uv

run: | $(UV)
	$(UV) run omega-prime-visibility run highway_merge.mcap --ego 0

lint: | $(UV)
	$(UV) run ruff check .
	$(UV) run ruff format --check .

test: lint
	$(UV) run pytest $(PYTEST_ARGS)

bench: | $(UV)
	$(UV) run python benchmarks/bench.py

scenario: | $(UV)
	$(UV) run python scenarios/highway_merge.py -o highway_merge.mcap
