# The two commands of README's Quick start: `make run` and `make test`.
# Both install missing Debian packages (tools/install-deps.sh), then configure and build (Release, Ninja).
# `make run` installs and builds only what the pipeline runs (tools/install-deps.sh --run, the CMake target
# `pipeline`: the programs of config/pipeline*.toml and of tools/run.sh); `make test` installs and builds
# the rest (every target: test binaries in build/tests/, benchmarks, the CGAL oracle).
BUILD_DIR ?= build
JOBS ?= $(shell nproc)

.PHONY: all deps run-deps configure build pipeline test run station clean

all: build

deps:
	@tools/install-deps.sh

run-deps:
	@tools/install-deps.sh --run

$(BUILD_DIR)/build.ninja: | run-deps
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release

# After `make run` the test-only packages may be new (the JDK for lcm-spy, CGAL): configure again so
# that CMake finds them.
configure: deps $(BUILD_DIR)/build.ninja
	cmake -S . -B $(BUILD_DIR) >/dev/null

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

pipeline: run-deps $(BUILD_DIR)/build.ninja
	cmake --build $(BUILD_DIR) -j $(JOBS) --target pipeline

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

run: pipeline
	tools/run.sh

station: pipeline
	tools/run.sh --station

clean:
	rm -rf $(BUILD_DIR) out
