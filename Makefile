# ik7r: every target sets up a local .venv first; nothing else is needed.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
# the kernels compiled ahead of time into an extension module (ik7r._kernels.aot), so that no
# first call compiles and a new process answers without importing numba: built once with the
# installation and again when a kernel source changes (75-80 CPU s in one process, 1-2 minutes).
# When the build fails (no C compiler), numba's JIT compiles the kernels on first use instead.
COMPILED := $(VENV)/.compiled
KERNELS  := $(wildcard src/ik7r/_kernels/*.py) src/ik7r/robot/family.py \
            src/ik7r/geometry/rotations.py src/ik7r/geometry/configs.py

.PHONY: demo test bench lint docs typecheck clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test,docs]"
	touch $(STAMP)

$(COMPILED): $(STAMP) $(KERNELS)
	-$(BIN)/python -m ik7r._kernels.aot --if-stale
	touch $(COMPILED)

demo: $(COMPILED)
	$(BIN)/ik7r demo

# ruff, the static types of the public API, every test (with the code of the README, the docs
# pages and the docstrings), then the documentation site with warnings as errors
# (ruff and mypy run while the compiled kernels are built, two jobs)
# pytest runs in TEST_JOBS processes (pytest-xdist), each test file whole in one of them
# (--dist loadfile: a module's fixtures are computed once); the site is built beside them. See
# docs/development.md, "Checks", for the times measured.
TEST_JOBS ?= 2
test: $(STAMP)
	@$(MAKE) --no-print-directory -j2 lint typecheck $(COMPILED)
	@# the site is built while pytest runs; its output is printed after, and either failing
	@# fails the target
	@mkdir -p docs/_build; \
	$(BIN)/python -m sphinx -b html -W --keep-going -q docs docs/_build/html > docs/_build/sphinx.log 2>&1 & \
	sphinx=$$!; \
	$(BIN)/python -m pytest -n $(TEST_JOBS) --dist loadfile --durations=15; tests=$$?; \
	wait $$sphinx; site=$$?; \
	echo "sphinx -b html -W (built beside pytest):"; cat docs/_build/sphinx.log; \
	test $$tests -eq 0 -a $$site -eq 0

# the documentation site, offline, into docs/_build/html (the gallery's figures are drawn here)
docs: $(COMPILED)
	$(BIN)/python -m sphinx -b html -q docs docs/_build/html

typecheck: $(STAMP)
	$(BIN)/python -m mypy

bench: $(COMPILED)
	$(BIN)/python benchmarks/run.py
	$(BIN)/python benchmarks/edges.py
	$(BIN)/python benchmarks/film.py

lint: $(STAMP)
	$(BIN)/ruff check src tests $(wildcard benchmarks) $(wildcard examples) docs/conf.py docs/_ext

clean:
	rm -rf $(VENV) build src/ik7r/_kernels/_compiled*.so src/ik7r/_kernels/_compiled.json src/*.egg-info .pytest_cache .mypy_cache docs/_build docs/auto_examples docs/api/generated docs/_generated
