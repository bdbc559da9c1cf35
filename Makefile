# The two commands a user needs: `make demo` and `make test`. Both install missing Debian
# packages first (scripts/install-deps.sh), then build Release into build/.
BUILD ?= build
# nproc counts OMP_THREAD_LIMIT (exported below as 1), so it is asked without it.
JOBS ?= $(shell env -u OMP_THREAD_LIMIT -u OMP_NUM_THREADS nproc)
BCASSIM_DATA ?= ../shared/data
export BCASSIM_DATA
# CHOLMOD's supernodal kernels ask for 4 OpenMP threads; the parallelism is ours (sigma points,
# ctest -j), so each process keeps to one.
OMP_THREAD_LIMIT ?= 1
export OMP_THREAD_LIMIT

.PHONY: all deps configure build test lint demo bench fuzz sanitize tsan ci clean

all: build

deps:
	@bash scripts/install-deps.sh

# A unity build (sources compiled in batches of 8, as the sanitized build does) halves the time
# from a clean clone: 8.9 against 17.6 minutes on 2 cores. UNITY=OFF compiles file by file (faster
# rebuilds after a change to one source).
UNITY ?= ON
configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=$(UNITY) > $(BUILD).configure.log 2>&1 || (cat $(BUILD).configure.log; exit 1)

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

test: build
	@cd $(BUILD) && ctest --output-on-failure -j$(JOBS) --timeout 1500

# Tidy habits: every C++ file formatted as .clang-format says, and clang-tidy's bug-finding checks
# (.clang-tidy) clean on every source of src/, warnings as errors (about 30 minutes on 2 cores;
# LINT_SINCE=<git revision> checks only the sources changed since it).
LINT_SINCE ?=
lint: configure
	@bash scripts/check-format.sh
	@bash scripts/run-clang-tidy.sh $(BUILD) $(if $(LINT_SINCE),$$(git diff --name-only --diff-filter=d $(LINT_SINCE) -- 'src/*.cpp'))

# The demo needs only the program: building the tests too would double its time.
demo: configure
	@cmake --build $(BUILD) -j$(JOBS) --target bcassim
	@bash scripts/demo.sh $(BUILD)

bench: build
	@bash scripts/bench.sh $(BUILD)

# Fuzzing: every reader's libFuzzer target (fuzz/; clang-14 with AddressSanitizer and UBSan, built
# in build-sanitize/, which `make sanitize` shares) runs for FUZZ_SECONDS seconds each; any crash,
# hang or leak fails it.
FUZZ_SECONDS ?= 60
fuzz: deps
	@FUZZ_SECONDS=$(FUZZ_SECONDS) JOBS=$(JOBS) bash fuzz/run-fuzzers.sh

# The ctest suite again, built with clang's AddressSanitizer and UBSan (build-sanitize/).
sanitize: deps
	@JOBS=$(JOBS) bash scripts/sanitize.sh

# The tests of the rooms whose threads are ours under ThreadSanitizer (gcc, build-tsan/), to show
# them race-free: live/ (the asynchronous engine) and stream/ (the OpenIGTLink server's network
# thread). Only those: the other rooms run in TBB and OpenMP,
# whose system libraries are not built with TSan, so it would report their synchronisation as
# races (false positives), and the whole suite under TSan would take hours on 2 cores.
tsan: deps
	@cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=Release -DBCASSIM_TSAN=ON -DBCASSIM_BUILD_TESTS=ON \
	  -DBCASSIM_BUILD_BENCH=OFF > build-tsan.configure.log 2>&1 || (cat build-tsan.configure.log; exit 1)
	@cmake --build build-tsan -j$(JOBS) --target test_live test_stream
	@TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" build-tsan/tests/test_live
	@TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" build-tsan/tests/test_stream

# What CI runs (.ci/run): the tests, the formatting, every fuzz target for 30 s, the sanitizer
# suite, and the live engine and the OpenIGTLink server under ThreadSanitizer (a few minutes).
ci: test
	@bash scripts/check-format.sh
	@$(MAKE) --no-print-directory fuzz FUZZ_SECONDS=30
	@$(MAKE) --no-print-directory sanitize
	@$(MAKE) --no-print-directory tsan

clean:
	rm -rf $(BUILD) $(BUILD).configure.log build-sanitize \
	  build-sanitize.configure.log build-tsan build-tsan.configure.log out
