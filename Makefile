# starnav: the README's two commands (`make demo`, `make test`) do all set-up themselves.
JOBS ?= $(shell nproc)
BUILD ?= build
GDAL ?= ON
PCL ?= ON
CMAKE_FLAGS ?=
CMAKE_COMMON = -DSTARNAV_WITH_GDAL=$(GDAL) -DSTARNAV_WITH_PCL=$(PCL) $(CMAKE_FLAGS)
SHARED ?= $(abspath ../shared)
# One clang build serves the sanitizer tests and the fuzz-corpus replay (docs/ci.md).
SAN_BUILD ?= build-san
NOGDAL_BUILD ?= build-nogdal
CMAKE_BUILD = JOBS=$(JOBS) scripts/cmake-build.sh
CTEST = ctest --output-on-failure --progress -j $(JOBS)

.PHONY: all deps build demo test pip-check bench bench-full asan san-build fuzz fuzz-replay nogdal-check format \
  install install-check clean

all: build

# make bench and bench-full install the benchmarks' peers too (OMPL): the target-specific value
# reaches deps through build.
DEPS_SET ?= core
bench bench-full: DEPS_SET = bench
deps:
	@STARNAV_WITH_GDAL=$(GDAL) STARNAV_WITH_PCL=$(PCL) scripts/install-deps.sh $(DEPS_SET)

build: deps
	@$(CMAKE_BUILD) $(BUILD) "-DCMAKE_BUILD_TYPE=Release $(CMAKE_COMMON)"

demo: build
	@scripts/demo.sh $(BUILD)/bin/starnav

# Every test but the slow pip install of the Python package (make pip-check).
test: build
	@cd $(BUILD) && $(CTEST) --timeout 900 -LE '^pip$$'

# pip install --no-build-isolation --no-index of a copy of the checkout into a scratch venv
# (docs/python.md): builds the library again, a few minutes.
pip-check: build
	@cd $(BUILD) && $(CTEST) --timeout 1800 -L '^pip$$'

bench: build
	@scripts/bench.sh $(BUILD)

bench-full: build
	@STARNAV_BENCH_FULL=1 scripts/bench.sh $(BUILD)

# The sanitizer build: clang-16, AddressSanitizer + UndefinedBehaviorSanitizer on everything, -O1
# with line tables, assertions on (scripts/san-build.sh); the tests and the fuzz-corpus replay.
san-build:
	@STARNAV_WITH_PCL=OFF scripts/install-deps.sh fuzz
	@JOBS=$(JOBS) scripts/san-build.sh $(SAN_BUILD) "$(CMAKE_COMMON)"

# The tests under AddressSanitizer + UndefinedBehaviorSanitizer.
asan: san-build
	@cd $(SAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  $(CTEST) --timeout 1800

# Fuzzing every parser, FUZZ_SECONDS per target (default 300), in build-fuzz/ (the sanitizer
# build's configuration plus libFuzzer's coverage instrumentation of the library).
FUZZ_SECONDS ?= 300
fuzz:
	@STARNAV_WITH_PCL=OFF scripts/install-deps.sh fuzz
	@scripts/fuzz.sh run $(FUZZ_SECONDS)

# Replays the kept corpora and every saved crasher (CI runs this).
fuzz-replay: san-build
	@FUZZ_BUILD_DIR=$(SAN_BUILD) scripts/fuzz.sh replay

# Without GDAL (docs/ci.md, "The build without GDAL"; CI checks it in make asan, whose tree has no
# GDAL): configured with -DSTARNAV_WITH_GDAL=OFF (no plugin, GeoTIFF refused with one error line),
# the library, the CLI and the two test executables that read map files (test_io: every reader and
# load_map; test_cli: the CLI on every map format, GeoTIFF included) built at -O1 and run. Nothing
# else in starnav touches GDAL. PCL is off too: nothing there uses it.
nogdal-check:
	@STARNAV_WITH_GDAL=OFF STARNAV_WITH_PCL=OFF scripts/install-deps.sh core
	@$(CMAKE_BUILD) $(NOGDAL_BUILD) "-DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O1 -DSTARNAV_WITH_GDAL=OFF \
	  -DSTARNAV_WITH_PCL=OFF -DSTARNAV_BUILD_BENCH=OFF $(CMAKE_FLAGS)" starnav_cli test_io test_cli
	@cd $(NOGDAL_BUILD) && $(CTEST) --timeout 900 -L '^(io|cli)$$'

# Installs the CLI, the library, its headers, the CMake package, a pkg-config file, the plugins and
# the viewer's page under PREFIX (default /usr/local; `make install PREFIX=$HOME/.local`).
PREFIX ?= /usr/local
install: build
	@cmake --install $(BUILD) --prefix $(PREFIX)

# Installs into a scratch prefix and builds examples/consumer against the installed package.
install-check: build
	@scripts/install-check.sh $(BUILD)

format:
	@scripts/install-deps.sh all
	@find src apps tests bench fuzz examples -name '*.cpp' -o -name '*.hpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) $(SAN_BUILD) $(NOGDAL_BUILD) build-fuzz
