# microshadow — entry points. `make demo` and `make test` do all set-up on a fresh Debian 12 machine.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
OUT ?= out
CMAKE_FLAGS ?=

.PHONY: all deps configure build test demo bench asan fuzz install format clean help
SECONDS ?= 60
PREFIX ?= /usr/local

all: build

help:
	@echo "make demo   - install missing Debian packages, build, run the main job (writes $(OUT)/)"
	@echo "make test   - install missing Debian packages, build, run the whole test suite (ctest)"
	@echo "make build  - configure and build into $(BUILD_DIR)/ (CLI: $(BUILD_DIR)/bin/microshadow)"
	@echo "make bench  - build and run the Google Benchmark suite"
	@echo "make asan   - build with ASan+UBSan into build-asan/ and run the test suite there"
	@echo "make install PREFIX=P - build, then cmake --install into P (default /usr/local; docs/packaging.md)"
	@echo "make fuzz SECONDS=N - build the libFuzzer targets with clang into build-fuzz/, run each N s (default 60)"
	@echo "make format - clang-format every C++ source"

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

demo: build
	@bash scripts/demo.sh $(BUILD_DIR) $(OUT)

bench: build
	@$(BUILD_DIR)/bin/microshadow_bench --benchmark_min_time=0.05

asan:
	@$(MAKE) --no-print-directory test BUILD_DIR=build-asan BUILD_TYPE=RelWithDebInfo CMAKE_FLAGS="-DMSH_SANITIZE=ON -DMSH_BUILD_BENCH=OFF"

install: build
	@cmake --install $(BUILD_DIR) --prefix $(PREFIX)

fuzz:
	@bash scripts/fuzz.sh $(SECONDS) build-fuzz

format:
	@find include src tests bench -name '*.h' -o -name '*.cpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR) build-asan build-fuzz $(OUT)
