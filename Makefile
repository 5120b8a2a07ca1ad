# Quick start: `make train` (train the default configuration) and `make test` (the whole suite).
# Both install missing Debian packages, configure and build in Release into build/ first.
CONFIG ?= configs/cartpole_ppo.yaml
RUN_ID ?= default-$(shell date +%Y%m%d-%H%M%S)
CTEST_ARGS ?=

.PHONY: build train test test-fast clean

build:
	./scripts/setup.sh

train: build
	./build/apps/rlt train $(CONFIG) --run-id $(RUN_ID)

test: build
	cd build && ctest --output-on-failure $(CTEST_ARGS)

# everything but the learning tests
test-fast: build
	cd build && ctest --output-on-failure -LE learning $(CTEST_ARGS)

clean:
	rm -rf build
