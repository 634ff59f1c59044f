# The two commands of README's Quick start: `make run` and `make test`.
# Both install missing Debian packages (tools/install-deps.sh), then configure and build (Release, Ninja).
BUILD_DIR ?= build
JOBS ?= $(shell nproc)

.PHONY: all deps configure build test run station clean

all: build

deps:
	@tools/install-deps.sh

$(BUILD_DIR)/build.ninja: | deps
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release

configure: deps $(BUILD_DIR)/build.ninja

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

run: build
	tools/run.sh

station: build
	tools/run.sh --station

clean:
	rm -rf $(BUILD_DIR) out
