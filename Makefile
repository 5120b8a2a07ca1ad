# Quick start: `make train` (train the default configuration) and `make test` (the whole suite).
# Both install missing Debian packages, configure and build in Release into build/ first.
CONFIG ?= configs/hide_and_seek.yaml
RUN_ID ?= default-$(shell date +%Y%m%d-%H%M%S)
CTEST_ARGS ?=

.PHONY: build train test test-fast clean

build:
	./scripts/setup.sh

# MAX_STEPS=N shortens the run (rlt train --max-steps N)
MAX_STEPS ?=

# trains, then evaluates the policies and records a replay (scripts/train_and_report.sh)
train: build
	./scripts/train_and_report.sh $(CONFIG) $(RUN_ID) $(if $(MAX_STEPS),--max-steps $(MAX_STEPS))

test: build
	cd build && ctest --output-on-failure $(CTEST_ARGS)

# everything but the learning tests
test-fast: build
	cd build && ctest --output-on-failure -LE learning $(CTEST_ARGS)

clean:
	rm -rf build
