# hairkit top-level commands. Everything real lives in CMake; this file only gives
# the short commands the README promises: make demo, make test, make bench, make asan,
# make fuzz, make format, make format-check,
# make install PREFIX=DIR (DESTDIR=... is honoured, as cmake --install does).

BUILD      ?= build
ASAN_BUILD ?= build-asan
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)
PREFIX     ?= /usr/local
CMAKE_FLAGS ?=

ifeq ($(HK_WERROR),1)
CMAKE_FLAGS += -DHK_WERROR=ON
endif

HAIRKIT := ./$(BUILD)/hairkit

# make fuzz: every libFuzzer harness of tests/fuzz for FUZZ_SECONDS each (clang).
FUZZ_BUILD   ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZERS      := obj hair hairstyle collision visuality setup motion helicoid simulation import \
                tfx usc ply objlines usda plymesh

.PHONY: all deps build demo test bench asan install fuzz format format-check clean

all: build

deps:
	@bash scripts/install-deps.sh

# The build and the tests show a few lines of progress; their whole output goes to
# $(BUILD)/build.log and $(BUILD)/test.log and is shown when they fail (scripts/quiet.sh).
build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > $(BUILD).configure.log 2>&1 || \
		{ cat $(BUILD).configure.log; exit 1; }
	@bash scripts/quiet.sh build $(BUILD)/build.log cmake --build $(BUILD) -j $(JOBS)
	@echo "build: made $(HAIRKIT) (try $(HAIRKIT) --help)"

demo: build
	@$(HAIRKIT) run examples/default/setup.txt -o demo.png
	@echo "demo: made $(CURDIR)/demo.png (the default head: about 124,000 strands grown and rendered)"

test: build
	@bash scripts/quiet.sh -C $(BUILD) test $(BUILD)/test.log ctest --output-on-failure -j $(JOBS)
	@sed -n "/tests passed/,\$$p" $(BUILD)/test.log | grep -vE "^$$|^Label Time|sec\*proc" | sed "s/^/test: /"

bench: build
	$(HAIRKIT) bench

install: build
	cmake --install $(BUILD) --prefix "$(PREFIX)"

# ASAN_CC=clang builds the sanitized tests with clang (whose UBSan checks more, e.g.
# offsets applied to null pointers); the default is the system's cc. ASAN_CTEST_ARGS
# (default: none, every test) are given to ctest, e.g. "-LE validation", and
# ASAN_CMAKE_FLAGS (default: none) to cmake after CMAKE_FLAGS, e.g. "-DHK_SHARED=OFF".
# A test whose only fault is LeakSanitizer's tracer crashing at its exit is run once
# more (scripts/asan-retry-tracer.sh says why).
asan:
	@bash scripts/install-deps.sh $(if $(filter clang%,$(ASAN_CC)),--fuzz)
	@$(if $(ASAN_CC),CC=$(ASAN_CC)) cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DHK_SANITIZE=ON \
		$(CMAKE_FLAGS) $(ASAN_CMAKE_FLAGS) > $(ASAN_BUILD).configure.log 2>&1 || { cat $(ASAN_BUILD).configure.log; exit 1; }
	@cmake --build $(ASAN_BUILD) -j $(JOBS)
	@cd $(ASAN_BUILD) && export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
		LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp \
		UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 && \
		{ ctest --output-on-failure -j $(JOBS) $(ASAN_CTEST_ARGS) || \
		  bash $(CURDIR)/scripts/asan-retry-tracer.sh $(ASAN_CTEST_ARGS); }

# New inputs that find new code go to $(FUZZ_BUILD)/corpus/NAME (tests/fuzz/corpus/NAME
# holds the seeds); a crash stops with its input saved as $(FUZZ_BUILD)/crash-... Not
# with HK_WERROR: clang warns where it cannot vectorise an OpenMP simd loop (-Wpass-failed).
fuzz:
	@bash scripts/install-deps.sh --fuzz
	@CC=clang cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=Debug -DHK_FUZZ=ON -DHK_TESTS=OFF -DHK_WERROR=OFF \
		> $(FUZZ_BUILD).configure.log 2>&1 || { cat $(FUZZ_BUILD).configure.log; exit 1; }
	@cmake --build $(FUZZ_BUILD) -j $(JOBS) --target fuzzers
	@for f in $(FUZZERS); do \
		mkdir -p $(FUZZ_BUILD)/corpus/$$f; \
		echo "fuzz_$$f: $(FUZZ_SECONDS) s"; \
		UBSAN_OPTIONS=print_stacktrace=1 ./$(FUZZ_BUILD)/fuzz_$$f -max_total_time=$(FUZZ_SECONDS) \
			-artifact_prefix=$(FUZZ_BUILD)/ $(FUZZ_BUILD)/corpus/$$f tests/fuzz/corpus/$$f \
			> $(FUZZ_BUILD)/fuzz_$$f.log 2>&1 || { tail -n 60 $(FUZZ_BUILD)/fuzz_$$f.log; exit 1; }; \
		grep -h '^#[0-9]*.*DONE' $(FUZZ_BUILD)/fuzz_$$f.log | tail -n 1; \
	done

# make format: formats every C file with .clang-format (scripts/format.sh);
# make format-check: fails on any file that make format would change (run by .ci/run).
format:
	@bash scripts/install-deps.sh --format
	@bash scripts/format.sh

format-check:
	@bash scripts/install-deps.sh --format
	@bash scripts/format.sh --check

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(FUZZ_BUILD) $(BUILD).configure.log $(ASAN_BUILD).configure.log \
		$(FUZZ_BUILD).configure.log
