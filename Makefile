# The two commands a newcomer needs: `make demo` and `make test`. PRESET picks the CMake preset
# (release, relwithdebinfo, debug, asan (-O1, sanitizers); optimised builds as a packager does, -O3, no tests);
# `make test PRESET=asan` runs the tests under the sanitizers.
PRESET ?= release
MAKEFLAGS += --no-print-directory
BUILD_DIR := build/$(PRESET)
X2CAR := $(BUILD_DIR)/apps/x2car/x2car

.PHONY: all setup configure build test demo bench camera-accuracy coverage format format-check clean

all: build

setup:
	@scripts/setup

configure: setup
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build --preset $(PRESET)

test: build
	@ctest --preset $(PRESET)

demo: build
	@scripts/demo $(X2CAR)

# The benchmarks are not part of `make test`'s build; this adds them to the preset's build.
bench: setup
	@cmake --preset $(PRESET) -DX2CAR_BUILD_BENCH=ON >/dev/null
	@cmake --build --preset $(PRESET)
	@scripts/bench $(BUILD_DIR)

# Issue 14's camera accuracy table (scripts/camera-accuracy): simulated drives x presets; long.
camera-accuracy: setup
	@cmake --preset $(PRESET) -DX2CAR_BUILD_BENCH=ON >/dev/null
	@cmake --build --preset $(PRESET) --target x2car x2car_camera_accuracy
	@scripts/camera-accuracy $(BUILD_DIR)

# The standard errors' coverage checks (bench/coverage.hpp): many simulated runs per sensor.
coverage: setup
	@cmake --preset $(PRESET) -DX2CAR_BUILD_BENCH=ON >/dev/null
	@cmake --build --preset $(PRESET)
	@scripts/coverage $(BUILD_DIR)

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

format-check:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format --dry-run -Werror

clean:
	@rm -rf build

# ---- fuzzing (fuzz/README.md): clang + libFuzzer, one target at a time for FUZZ_SECONDS each ----
FUZZ_SECONDS ?= 600
.PHONY: fuzz fuzz-build
fuzz-build:
	@scripts/setup fuzz
	@cmake --preset fuzz >/dev/null
	@cmake --build --preset fuzz
fuzz: fuzz-build
	@FUZZ_SECONDS=$(FUZZ_SECONDS) fuzz/run $(FUZZ_TARGETS)
