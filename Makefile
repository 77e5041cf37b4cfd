# robcal — top-level entry points. Every target installs missing Debian packages first.
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

DEBIAN_PACKAGES = build-essential cmake libeigen3-dev libceres-dev libcli11-dev libyaml-cpp-dev \
  nlohmann-json3-dev libfmt-dev libgtest-dev libgmock-dev libbenchmark-dev pybind11-dev \
  python3-dev python3-numpy python3-pytest libjs-chart.js help2man bash-completion pkgconf \
  python3-pip python3-setuptools python3-wheel python3-yaml \
  liburdfdom-dev liborocos-kdl-dev

.PHONY: deps build test demo bench experiments format tidy clean browser-deps sanitize fuzz-long

deps:
	@bash scripts/install-deps.sh $(DEBIAN_PACKAGES)

browser-deps:
	@bash scripts/install-deps.sh chromium poppler-utils

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) $(CMAKE_FLAGS)

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

test: build browser-deps
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

demo: build
	$(BUILD)/robcal demo --out demo-out

bench: build
	mkdir -p bench/results
	$(BUILD)/robcal_bench --benchmark_repetitions=15 --benchmark_report_aggregates_only=true \
	  --benchmark_out=bench/results/latest.json --benchmark_out_format=json

experiments: build
	$(BUILD)/robcal experiments --out bench/experiments/results
	# Pose selection under effects the model does not contain (README results, issue 13 item 7).
	for effects in backlash,j6-periodic mass-error backlash,j6-periodic,mass-error; do \
	  $(BUILD)/robcal plan-study --task-box -500,-300,1100,1300,150,350 --effects $$effects \
	    --seeds 16 --counts 20,40 --candidates 2000 --task-count 200 --json \
	    > bench/experiments/results/plan-study-$$effects.json || exit 1; \
	done

# The library and the parsers' fuzzer built again with AddressSanitizer and
# UndefinedBehaviorSanitizer (-O1), the unit tests' objects of the normal build linked to them;
# then the unit tests and a longer fuzz run of every parser. A report or a leak fails (except
# urdfdom's own leak on looped URDFs: tests/fuzz/lsan.supp says why).
SANITIZER_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/fuzz/lsan.supp
sanitize: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) --target robcal_tests_asan robcal_fuzz_asan -j $(JOBS)
	$(SANITIZER_ENV) $(BUILD)/robcal_tests_asan --gtest_brief=1
	$(SANITIZER_ENV) $(BUILD)/robcal_fuzz_asan --iterations 2000 tests/fuzz

# The long fuzz run (issue 21): FUZZ_MINUTES (default 10) of mutations per parser with the
# library and the fuzzer built as for `make sanitize`; prints the executions per second of each
# parser; an input that fails is saved under fuzz-found/<parser>/ (move it to
# tests/fuzz/crashes/ once fixed). One parser: `make fuzz-long FUZZ_PARSER=rapid`.
FUZZ_MINUTES ?= 10
fuzz-long: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) --target robcal_fuzz_asan -j $(JOBS)
	$(SANITIZER_ENV) $(BUILD)/robcal_fuzz_asan --seconds $$(( $(FUZZ_MINUTES) * 60 )) \
	  --out fuzz-found $(if $(FUZZ_PARSER),--parser $(FUZZ_PARSER)) tests/fuzz

# clang-tidy with the project's checks (.clang-tidy) over the library and the CLI, in batches of a
# folder's files (scripts/tidy.py says why); any finding fails.
tidy: build
	@bash scripts/install-deps.sh clang-tidy
	python3 scripts/tidy.py $(BUILD) $(JOBS)

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD)
