# Two commands do all set-up on a fresh clone: `make run` and `make test` (uv is bootstrapped if missing).
# `make docs` builds the documentation site into site/.
SHELL := /bin/bash
export UV_PYTHON_DOWNLOADS := never
# uv's build of the package leaves the kernels to `make run`'s compile, in the environment itself (a build compiles
# them in its own environment, whose numba may not be the lock's: build_support/build_kernels.py)
export OMEGA_PRIME_VISIBILITY_BUILD_KERNELS := 0
UV := $(shell command -v uv 2>/dev/null || echo .tools/bin/uv)
# uv itself: from PATH, else installed once into .tools/ with the machine's python3
UV_DEP := $(if $(filter .tools/bin/uv,$(UV)),.tools/bin/uv,)
PYTEST_ARGS ?= -n 2

.PHONY: run test lint docs bench bench-batch scenario pictures

.tools/bin/uv:
	python3 -m venv .tools
	.tools/bin/python -m pip install --quiet uv

# the environment, installed once per change of the dependencies; later commands run in it without syncing again
.venv/.installed: pyproject.toml uv.lock | $(UV_DEP)
	@echo "installing into .venv/ and compiling its Python files once (the first time: a minute or two)"
	$(UV) sync --compile-bytecode
	@touch $@

run: .venv/.installed
	$(UV) run --no-sync omega-prime-visibility compile
	$(UV) run --no-sync omega-prime-visibility run highway_merge.mcap --ego 0
	@echo "the command line: source .venv/bin/activate, then omega-prime-visibility --help"

lint: .venv/.installed
	$(UV) run --no-sync ruff check .
	$(UV) run --no-sync ruff format --check .

test: lint docs
	@$(UV) run --no-sync python -m compileall -q omega_prime_visibility  # (bytecode: the tests start many processes)
	$(UV) run --no-sync pytest $(PYTEST_ARGS)

# the documentation site (docs/ -> site/), warnings as errors; open site/index.html
docs: .venv/.installed
	NO_MKDOCS_2_WARNING=1 $(UV) run --no-sync mkdocs build --strict --quiet

bench: .venv/.installed
	$(UV) run --no-sync python benchmarks/bench.py --long 30000
	$(UV) run --no-sync python benchmarks/bench_sensors.py
	$(UV) run --no-sync python benchmarks/pictures.py
	$(UV) run --no-sync python benchmarks/agreement.py
	$(UV) run --no-sync python benchmarks/first_call.py
	$(UV) run --no-sync python benchmarks/bench_campaign.py
	$(UV) run --no-sync python benchmarks/bench_choices.py --frames 300
	$(UV) run --no-sync python benchmarks/bench_3d.py --quick
	$(UV) run --no-sync python benchmarks/bench_urban.py
	$(UV) run --no-sync python benchmarks/bench_reader.py
	$(UV) run --no-sync python benchmarks/bench_imaging.py
	$(UV) run --no-sync python benchmarks/bench_export.py
	$(UV) run --no-sync python benchmarks/bench_highd.py

bench-batch: .venv/.installed
	$(UV) run --no-sync python benchmarks/bench_batch.py

scenario: .venv/.installed
	$(UV) run --no-sync python scenarios/highway_merge.py -o highway_merge.mcap

pictures: .venv/.installed
	$(UV) run --no-sync python scripts/make_pictures.py
