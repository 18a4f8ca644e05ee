# Thin wrapper: `make demo` and `make test` are README's Quick start.
BUILD ?= build
JOBS ?= $(shell nproc)

.PHONY: setup build demo test gallery gallery-update clean

setup:
	@bash scripts/setup.sh

# the program and its libraries; `make test` adds the tests, examples and benchmarks to the same
# build folder (SABLIER_BUILD_TESTS), reusing what `make build` compiled
build: setup
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DSABLIER_BUILD_TESTS=OFF >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	$(BUILD)/sablier run scenes/crater/quick.scene --out out/crater

test: setup
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DSABLIER_BUILD_TESTS=ON >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) -LE bench

# every thesis figure of docs/gallery.md, full size, into out/gallery/
gallery: build
	scripts/gallery.sh --sablier $(BUILD)/sablier out/gallery

# the ctest `gallery`'s references (reduced size), after an intended change of the figures
gallery-update: build
	scripts/gallery.sh --reduced --sablier $(BUILD)/sablier $(BUILD)/gallery-update
	$(BUILD)/sablier diff tests/gallery/reference $(BUILD)/gallery-update --update

clean:
	rm -rf $(BUILD)
