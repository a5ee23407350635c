# Two entry points: `make demo` renders the gallery, `make test` runs every test on whatever
# Vulkan device is present (Mesa's lavapipe on machines without a GPU).

CARGO ?= cargo

.PHONY: demo test deps

deps:
	@./scripts/ensure-deps.sh
	@./scripts/fetch-bunny.sh
	@./scripts/fetch-dwi.sh
	@./scripts/fetch-frog.sh

# Tests a device cannot run are reported as skipped by name; the list is printed at the end.
SKIP_LOG := $(CURDIR)/target/skipped-tests.txt

test: deps
	@mkdir -p target && rm -f $(SKIP_LOG)
	TESSERA_SKIP_LOG=$(SKIP_LOG) $(CARGO) test --workspace
	TESSERA_SKIP_LOG=$(SKIP_LOG) ./scripts/test-python.sh
	@./scripts/report-skips.sh $(SKIP_LOG)

demo: deps
	$(CARGO) run --release -p tessera-cli -- demo --out out
