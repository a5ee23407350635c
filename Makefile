# Two entry points: `make demo` renders the gallery, `make test` runs every test on whatever
# Vulkan device is present (Mesa's lavapipe on machines without a GPU).

CARGO ?= cargo

.PHONY: demo test deps

deps:
	@./scripts/ensure-deps.sh
	@./scripts/fetch-bunny.sh
	@./scripts/fetch-dwi.sh

test: deps
	$(CARGO) test --workspace

demo: deps
	$(CARGO) run --release -p tessera-cli -- demo --out out
