# railcontact: set-up and main jobs.  Each target creates .venv on first use, with
# the exact package versions of requirements.lock (`make lock` updates that file).
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
LOCK   := requirements.lock
STAMP  := $(VENV)/.installed

# Numba's on-disk cache, one folder per state of the package's sources: a kernel
# cached before a function it calls (in another module) changed is never reused
SRC_HASH := $(shell find railcontact -name '*.py' | LC_ALL=C sort | xargs cat | sha1sum | cut -c1-12)
export NUMBA_CACHE_DIR := $(CURDIR)/$(VENV)/numba-cache/$(SRC_HASH)

.PHONY: demo test test-random bench api lock clone-check clean

$(STAMP): pyproject.toml $(LOCK)
	rm -rf $(VENV)
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -c $(LOCK) pip setuptools
	$(BIN)/python -m pip install --quiet --no-build-isolation -c $(LOCK) -e ".[test]"
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/railcontact demo --out demo_output

test: $(STAMP)
	@find $(VENV)/numba-cache -mindepth 1 -maxdepth 1 ! -name $(SRC_HASH) -exec rm -rf {} + 2>/dev/null || true
	$(BIN)/python -m pytest -q

# the suite in a random order (a check that no test depends on another's state)
test-random: $(STAMP)
	$(BIN)/python -m pytest --random-order-bucket=global

bench: $(STAMP)
	$(BIN)/python benchmarks/run_all.py

# the API reference from the docstrings (pdoc), in docs/api/index.html
api: $(STAMP)
	$(BIN)/python scripts/api_reference.py docs/api

# re-resolve the newest registry versions into requirements.lock
lock:
	rm -rf .lock-venv
	$(PYTHON) -m venv .lock-venv
	.lock-venv/bin/python -m pip install --quiet --upgrade pip setuptools
	.lock-venv/bin/python -m pip install --quiet ".[test]"
	{ echo "# Exact versions for make demo/test/bench; regenerate with 'make lock'."; \
	  echo "# Resolved with $$(.lock-venv/bin/python --version) on $$(uname -sm)."; \
	  .lock-venv/bin/python -m pip freeze --all | grep -v '^railcontact' | LC_ALL=C sort -f; } > $(LOCK)
	rm -rf .lock-venv build

# what CI runs: a clean clone of HEAD with ../shared beside it, then make test
clone-check:
	scripts/clone-check

clean:
	rm -rf $(VENV) demo_output .pytest_cache docs/api
