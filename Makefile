# Thin wrapper: `make demo` and `make test` are README's Quick start.
BUILD ?= build
JOBS ?= $(shell nproc)

.PHONY: setup build demo test clean

setup:
	@bash scripts/setup.sh

build: setup
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	$(BUILD)/sablier run scenes/crater/quick.scene --out out/crater

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) -LE bench

clean:
	rm -rf $(BUILD)
