# The entry points people type. The real build is CMakeLists.txt; this file
# drives it, building into build/ so that `ctest --test-dir build` works.
#
#   make            configure (RelWithDebInfo: -O2 -g) and build into build/
#   make deps       install the missing Debian packages (apt-get)
#   make test       deps + build + every test except the soak label
#   make demo       deps + build + drape_table for alpha 0, 0.5, 0.8 and 1:
#                   pictures and the contact sheet in $(BUILD)/demo/
#   make sanitize   build into build-san/ with ASan + UBSan and run the tests
#   make bench      deps + build + run every build/examples/bench_* program
#   make install    install into PREFIX (default /usr/local)
#   make clean      remove build/ and build-san/

PREFIX ?= /usr/local
BUILD ?= build
SAN_BUILD ?= build-san
CMAKE ?= cmake
CTEST ?= ctest
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CTEST_ARGS ?= --output-on-failure -j2 -LE soak

DEPS := libode-dev libccd-dev cmake pkg-config libosmesa6-dev libpng-dev gnuplot-nox
SAN_FLAGS := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
BENCHES := $(patsubst examples/%.c,$(BUILD)/examples/%,$(wildcard examples/bench_*.c))

# The CMake-generated makefiles would otherwise print every directory change.
MAKEFLAGS += --no-print-directory

# Targets run one after another (deps before build); the parallelism is
# inside the CMake build.
.NOTPARALLEL:
.PHONY: all build deps test demo sanitize bench install clean

all: build

$(BUILD)/CMakeCache.txt:
	$(CMAKE) -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo

build: $(BUILD)/CMakeCache.txt
	$(CMAKE) --build $(BUILD) -j $(JOBS)

# `dpkg -s` exits 0 for a removed package whose configuration remains, so
# the status line is what counts.
deps:
	@if ! command -v dpkg >/dev/null 2>&1; then \
	    echo "make deps: not a Debian system; install by hand: $(DEPS)"; exit 0; \
	fi; \
	missing=; \
	for p in $(DEPS); do \
	    dpkg -s $$p 2>/dev/null | grep -q '^Status: install ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	    sudo=; [ "$$(id -u)" -eq 0 ] || sudo=sudo; \
	    echo "make deps: installing$$missing"; \
	    $$sudo env DEBIAN_FRONTEND=noninteractive apt-get update -q && \
	    $$sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $$missing; \
	fi

test: deps build
	$(CTEST) --test-dir $(BUILD) $(CTEST_ARGS)

demo: deps build
	@rm -f $(BUILD)/demo/drape_table.csv
	$(BUILD)/examples/drape_table --alpha 0,0.5,0.8,1 --out $(BUILD)/demo --csv $(BUILD)/demo/drape_table.csv
	@echo "contact sheet: $(BUILD)/demo/drape_table.png"

# A separate tree, so the sanitized objects never mix with the normal ones.
# The flags also reach the link lines (CMake passes C flags to the linker).
sanitize: deps
	$(CMAKE) -S . -B $(SAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	    -DCMAKE_C_FLAGS="$(SAN_FLAGS)"
	$(CMAKE) --build $(SAN_BUILD) -j $(JOBS)
	UBSAN_OPTIONS=print_stacktrace=1 $(CTEST) --test-dir $(SAN_BUILD) $(CTEST_ARGS)

bench: deps build
	@$(if $(BENCHES),,echo "no benchmarks (examples/bench_*.c) yet")
	@set -e; for b in $(BENCHES); do echo "== $$b"; $$b; done

# The prefix is given at configure time too, so that GNUInstallDirs picks the
# layout for it (lib/<multiarch> under /usr on Debian).
install: $(BUILD)/CMakeCache.txt
	$(CMAKE) -S . -B $(BUILD) -DCMAKE_INSTALL_PREFIX=$(PREFIX)
	$(CMAKE) --build $(BUILD) -j $(JOBS)
	$(CMAKE) --install $(BUILD)

clean:
	rm -rf $(BUILD) $(SAN_BUILD)
