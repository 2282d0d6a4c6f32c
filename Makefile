# hairkit top-level commands. Everything real lives in CMake; this file only gives
# the short commands the README promises: make demo, make test, make bench, make asan,
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

.PHONY: all deps build demo test bench asan install clean

all: build

deps:
	@bash scripts/install-deps.sh

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > $(BUILD).configure.log 2>&1 || \
		{ cat $(BUILD).configure.log; exit 1; }
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	$(HAIRKIT) run examples/default/setup.txt -o demo.png
	@echo "demo: wrote demo.png (the default head: about 124,000 strands grown and rendered)"

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(HAIRKIT) bench

install: build
	cmake --install $(BUILD) --prefix "$(PREFIX)"

asan: deps
	@cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DHK_SANITIZE=ON $(CMAKE_FLAGS) \
		> $(ASAN_BUILD).configure.log 2>&1 || { cat $(ASAN_BUILD).configure.log; exit 1; }
	@cmake --build $(ASAN_BUILD) -j $(JOBS)
	@cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
		UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) $(BUILD).configure.log $(ASAN_BUILD).configure.log
