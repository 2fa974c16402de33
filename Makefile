# starnav: the README's two commands (`make demo`, `make test`) do all set-up themselves.
JOBS ?= $(shell nproc)
BUILD ?= build
GDAL ?= ON
CMAKE_FLAGS ?=
CMAKE_COMMON = -DSTARNAV_WITH_GDAL=$(GDAL) $(CMAKE_FLAGS)
SHARED ?= $(abspath ../shared)

.PHONY: all deps build demo test bench bench-full asan fuzz fuzz-replay format install-check clean

all: build

deps:
	@STARNAV_WITH_GDAL=$(GDAL) scripts/install-deps.sh core

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_COMMON) >/dev/null
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	@scripts/demo.sh $(BUILD)/bin/starnav

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS) --timeout 900

bench: build
	@scripts/bench.sh $(BUILD)

bench-full: build
	@STARNAV_BENCH_FULL=1 scripts/bench.sh $(BUILD)

# The tests under AddressSanitizer + UndefinedBehaviorSanitizer (Debug with -O1 to keep it quick).
asan: deps
	@cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSTARNAV_SANITIZE=ON -DSTARNAV_BUILD_BENCH=OFF $(CMAKE_COMMON) >/dev/null
	@cmake --build build-asan -j $(JOBS)
	@cd build-asan && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --output-on-failure -j $(JOBS) --timeout 1800

# libFuzzer targets, built with Debian's clang-16. FUZZ_SECONDS per target (default 300).
FUZZ_SECONDS ?= 300
fuzz:
	@scripts/install-deps.sh fuzz
	@scripts/fuzz.sh run $(FUZZ_SECONDS)

# Replays the kept corpora and every saved crasher (CI runs this).
fuzz-replay:
	@scripts/install-deps.sh fuzz
	@scripts/fuzz.sh replay

# Installs into a scratch prefix and builds examples/consumer against the installed package.
install-check: build
	@scripts/install-check.sh $(BUILD)

format:
	@scripts/install-deps.sh all
	@find src apps tests bench fuzz examples -name '*.cpp' -o -name '*.hpp' | xargs clang-format -i

clean:
	rm -rf build build-asan build-fuzz build-nogdal
