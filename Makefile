# The entry points people type. The real build is CMakeLists.txt; this file
# drives it, building into build/ so that `ctest --test-dir build` works.
#
#   make            configure (RelWithDebInfo: -O2 -g) and build into build/
#   make deps       install the missing Debian packages (apt-get)
#   make test       deps + build + every test except the soak label
#   make demo       deps + build + drape_table for alpha 0, 0.5, 0.8 and 1:
#                   pictures and the contact sheet in $(BUILD)/demo/
#   make video      deps + ffmpeg + build + videos of the drape and removal
#                   (table and sphere at alpha 0, 0.5, 0.8; cotton against
#                   wool) into $(BUILD)/video/, side by side per experiment
#   make sanitize   build into build-san/ with ASan + UBSan and run the tests
#   make bench      deps + build + run every build/examples/bench_* program,
#                   and bench_workprecision --cotton
#   make fuzz       build the libFuzzer harnesses (clang, ASan + UBSan) into
#                   build-fuzz/ and run each for FUZZ_SECONDS (default 60)
#   make docs       regenerate the generated docs (docs/api.md from the public
#                   headers, docs/benchmarks.md from the benchmarks' CSVs)
#   make install    install into PREFIX (default /usr/local)
#   make format     lay out the C sources as .clang-format says (clang-format -i;
#                   .ci/format-check checks it)
#   make clean      remove build/ and build-san/

PREFIX ?= /usr/local
BUILD ?= build
SAN_BUILD ?= build-san
CMAKE ?= cmake
CTEST ?= ctest
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CTEST_ARGS ?= --output-on-failure -j2 -LE soak

DEPS := libode-dev libccd-dev cmake pkg-config libosmesa6-dev libpng-dev libglfw3-dev \
        xvfb xauth gnuplot-nox clang libclang-rt-dev valgrind clang-format \
        libfreetype-dev fonts-dejavu-core
# Only `make video` needs these (the demos' --video pipes frames to ffmpeg).
VIDEO_DEPS := ffmpeg
VIDEO_DIR ?= $(BUILD)/video
VIDEO_GRID ?= 41
VIDEO_SIZE ?= 480x360
SAN_FLAGS := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
BENCHES := $(patsubst examples/%.c,$(BUILD)/examples/%,$(wildcard examples/bench_*.c))

# The CMake-generated makefiles would otherwise print every directory change.
MAKEFLAGS += --no-print-directory

# Targets run one after another (deps before build); the parallelism is
# inside the CMake build.
.NOTPARALLEL:
.PHONY: all build deps video-deps test demo video sanitize bench install clean fuzz docs format

all: build

$(BUILD)/CMakeCache.txt:
	$(CMAKE) -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo

build: $(BUILD)/CMakeCache.txt
	$(CMAKE) --build $(BUILD) -j $(JOBS)

# Install the missing Debian packages of a list. `dpkg -s` exits 0 for a
# removed package whose configuration remains, so the status line is what
# counts.
define apt_install
	@if ! command -v dpkg >/dev/null 2>&1; then \
	    echo "make $@: not a Debian system; install by hand: $(1)"; exit 0; \
	fi; \
	missing=; \
	for p in $(1); do \
	    dpkg -s $$p 2>/dev/null | grep -q '^Status: install ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	    sudo=; [ "$$(id -u)" -eq 0 ] || sudo=sudo; \
	    echo "make $@: installing$$missing"; \
	    $$sudo env DEBIAN_FRONTEND=noninteractive apt-get update -q && \
	    $$sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $$missing; \
	fi
endef

deps:
	$(call apt_install,$(DEPS))

video-deps:
	$(call apt_install,$(VIDEO_DEPS))

test: deps build
	$(CTEST) --test-dir $(BUILD) $(CTEST_ARGS)

demo: deps build
	@rm -f $(BUILD)/demo/drape_table.csv
	$(BUILD)/examples/drape_table --alpha 0,0.5,0.8,1 --out $(BUILD)/demo --csv $(BUILD)/demo/drape_table.csv
	@echo "contact sheet: $(BUILD)/demo/drape_table.png"

# Each demo records every run (<out>/<tag>.mp4); ffmpeg then puts a demo's
# runs side by side, each labelled in its top-left corner.
VIDEO_RUN = --video --no-images --grid $(VIDEO_GRID) --size $(VIDEO_SIZE)
video: deps video-deps build
	$(BUILD)/examples/drape_table --alpha 0,0.5,0.8 $(VIDEO_RUN) --out $(VIDEO_DIR)/drape_table
	$(BUILD)/examples/drape_sphere --alpha 0,0.5,0.8 $(VIDEO_RUN) --out $(VIDEO_DIR)/drape_sphere
	$(BUILD)/examples/fabrics $(VIDEO_RUN) --out $(VIDEO_DIR)/fabrics
	@set -e; cd $(VIDEO_DIR); \
	for d in drape_table drape_sphere; do \
	    ffmpeg -v error -nostdin -y -i $$d/alpha0.mp4 -i $$d/alpha0.5.mp4 -i $$d/alpha0.8.mp4 \
	        -filter_complex hstack=inputs=3 -pix_fmt yuv420p $$d.mp4; \
	done; \
	for e in table press; do \
	    ffmpeg -v error -nostdin -y -i fabrics/$$e/cotton.mp4 -i fabrics/$$e/wool.mp4 \
	        -filter_complex hstack=inputs=2 -pix_fmt yuv420p fabrics_$$e.mp4; \
	done
	@echo "videos: $(VIDEO_DIR)/drape_table.mp4, drape_sphere.mp4 (alpha 0 | 0.5 | 0.8)," \
	    "fabrics_table.mp4, fabrics_press.mp4 (cotton | wool)"

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
	@echo "== $(BUILD)/examples/bench_workprecision --cotton"; $(BUILD)/examples/bench_workprecision --cotton

# libFuzzer: each test/fuzz_<name>.c defines LLVMFuzzerTestOneInput (its
# main(), the CTest driver, is left out with -DODECLOTH_LIBFUZZER) and is
# built with the core's sources, all instrumented, then run for a bounded
# time from its seeds in test/corpus/<name>/ (new inputs it finds go to
# build-fuzz/corpus_<name>/, crashes to build-fuzz/). Non-zero on a crash.
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_CC ?= clang
FUZZ_FLAGS := -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
              -fno-omit-frame-pointer -DODECLOTH_LIBFUZZER
FUZZERS := $(patsubst test/fuzz_%.c,%,$(wildcard test/fuzz_*.c))
# What each harness is built with besides itself (default: the core).
FUZZ_INC = -Icore/include -Icore/src -Iplugin/include -Iplugin/src -Iexamples/common -Itest
FUZZ_SRC_default := $(wildcard core/src/*.c)
FUZZ_SRC_options := examples/common/options.c examples/common/cli.c $(FUZZ_SRC_default) $(wildcard plugin/src/*.c)
FUZZ_LIBS_options = $$(pkg-config --cflags --libs ode ccd)
FUZZ_SRC_plugin_state := $(FUZZ_SRC_default) $(wildcard plugin/src/*.c)
FUZZ_LIBS_plugin_state = $(FUZZ_LIBS_options)

fuzz: deps
	@mkdir -p $(FUZZ_BUILD)
	@set -e; $(foreach f,$(FUZZERS), \
	    echo "== fuzz_$(f): building with $(FUZZ_CC)"; \
	    $(FUZZ_CC) $(FUZZ_FLAGS) $(FUZZ_INC) $(or $(FUZZ_SRC_$(f)),$(FUZZ_SRC_default)) test/fuzz_$(f).c \
	        $(FUZZ_LIBS_$(f)) -lm -o $(FUZZ_BUILD)/fuzz_$(f); \
	    mkdir -p $(FUZZ_BUILD)/corpus_$(f); \
	    echo "== fuzz_$(f): running for $(FUZZ_SECONDS) s"; \
	    $(FUZZ_BUILD)/fuzz_$(f) -max_total_time=$(FUZZ_SECONDS) -timeout=20 -rss_limit_mb=2048 \
	        -print_final_stats=1 -artifact_prefix=$(FUZZ_BUILD)/ \
	        $(FUZZ_BUILD)/corpus_$(f) test/corpus/$(f);)

# Each docs/NAME.md written by docs/gen/NAME.sh (sh + awk only); test/docs/check.sh
# fails when a committed one differs from what its script writes now.
GENERATED_DOCS := api benchmarks
docs:
	@set -e; for d in $(GENERATED_DOCS); do sh docs/gen/$$d.sh . > docs/$$d.md.tmp; \
	    mv docs/$$d.md.tmp docs/$$d.md; echo "wrote docs/$$d.md"; done

# The prefix is given at configure time too, so that GNUInstallDirs picks the
# layout for it (lib/<multiarch> under /usr on Debian).
install: $(BUILD)/CMakeCache.txt
	$(CMAKE) -S . -B $(BUILD) -DCMAKE_INSTALL_PREFIX=$(PREFIX)
	$(CMAKE) --build $(BUILD) -j $(JOBS)
	$(CMAKE) --install $(BUILD)

format: deps
	.ci/format-check --fix

clean:
	rm -rf $(BUILD) $(SAN_BUILD)
