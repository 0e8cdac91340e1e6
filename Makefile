# lvcl: `make run` installs what is missing, builds and renders the paper's
# kitchen with the light volume; `make test` runs the test suite. Everything
# built lands in build/.

CC ?= cc
CXX ?= c++
BUILD := build
# The ICD folder of the OpenCL implementations lvcl checks its kernels on.
VENDORS := $(BUILD)/opencl-vendors
# libFuzzer harnesses (tests/fuzz/fuzz_<name>.c).
FUZZERS := $(BUILD)/fuzz/fuzz_gltf $(BUILD)/fuzz/fuzz_options
CFLAGS ?= -O2 -g
CXXFLAGS ?= -O2 -g
WARN := -Wall -Wextra -Wno-missing-field-initializers -Wno-format-truncation
# CI builds with WERROR=1: a warning fails the build.
ifneq ($(WERROR),)
WARN += -Werror
endif
ALL_CFLAGS := -std=c11 -D_POSIX_C_SOURCE=200809L $(WARN) $(CFLAGS)
ALL_CXXFLAGS := -std=c++17 $(WARN) $(CXXFLAGS)
LIBS := -lOpenCL -lOpenImageIO -lOpenImageIO_Util -ltinygltf -lstb -lstdc++ -lm -lpthread

# Debian packages lvcl needs to build and run.
DEBIAN_PACKAGES := build-essential pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers \
	libopenimageio-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libglm-dev oclgrind python3-venv clang \
	libopenmpi-dev openmpi-bin

# host/<layer>/ and host/<layer>/<part>/; host/tools/ and host/embed/ build programs of their own,
# and host/mpi/ is lvcl-mpi's alone (build/lvcl keeps no MPI dependency).
HOST_DIRS := $(filter-out host/tools/ host/embed/ host/mpi/,$(wildcard host/*/))
HOST_C := $(filter-out host/app/main.c,$(wildcard $(addsuffix *.c,$(HOST_DIRS)) $(addsuffix */*.c,$(HOST_DIRS))))
HOST_CXX := $(wildcard $(addsuffix *.cpp,$(HOST_DIRS)) $(addsuffix */*.cpp,$(HOST_DIRS)))
HOST_H := $(wildcard $(addsuffix *.h,$(HOST_DIRS)) $(addsuffix */*.h,$(HOST_DIRS)))
KERNELS := $(wildcard kernels/*.h kernels/*/*.h kernels/*.cl kernels/*/*.cl)
GEN_C := $(BUILD)/gen/kernel_source.c $(BUILD)/gen/scene_cornell.c $(BUILD)/gen/scene_furnace.c \
         $(BUILD)/gen/scene_kitchen.c

# The library of everything but main(), shared by lvcl, the tests and the benchmarks.
define objects_in
$(patsubst host/%.c,$(1)/obj/%.o,$(HOST_C)) $(patsubst host/%.cpp,$(1)/obj/%.o,$(HOST_CXX)) \
	$(patsubst $(BUILD)/gen/%.c,$(1)/obj/gen/%.o,$(GEN_C))
endef
LIB_OBJS := $(call objects_in,$(BUILD))

# tests/<layer>/test_<name>.c builds $(BUILD)/tests/test_<name>, linked with
# the other .c files of its folder (the support the folder's tests share).
TEST_SOURCES := $(wildcard tests/*/test_*.c)
TEST_BINS := $(addprefix $(BUILD)/tests/,$(basename $(notdir $(TEST_SOURCES))))

.PHONY: all run test test-asan deps references clean format
# Keep the generated scene arrays, which only pattern rules name, between
# builds. (A bare .SECONDARY: would make every target secondary, and make
# then skipped a missing stamp such as bench-embree-yes.)
.SECONDARY: $(GEN_C)
all: $(BUILD)/lvcl $(BUILD)/lvcl-mpi $(BUILD)/lvcl-compare $(BUILD)/lvcl-bench $(TEST_BINS) $(VENDORS)/.stamp $(FUZZERS)
	@# A test program whose source has gone or moved would still run.
	@rm -f $(filter-out $(TEST_BINS),$(wildcard $(BUILD)/tests/test_*))

# ---- set-up ----
# Installs whichever of the Debian packages $(1) are missing (apt-get, as
# root or through sudo), or names them and stops.
define install_debian_packages
	@missing=""; for p in $(1); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "make: installing Debian packages:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=""; elif command -v sudo >/dev/null; then SUDO=sudo; \
	  else echo "make: error: missing packages:$$missing; install them as root (apt-get install$$missing)"; exit 1; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null \
	  || { echo "make: error: apt-get could not install:$$missing"; exit 1; }; \
	fi
endef

deps: $(BUILD)/.deps-ok
# Again when the list here changes.
$(BUILD)/.deps-ok: Makefile
	$(call install_debian_packages,$(DEBIAN_PACKAGES))
	@mkdir -p $(BUILD) && touch $@

# Three OpenCL implementations to check the kernels on (docs/devices.md):
# $(VENDORS) is an ICD folder that lvcl points the loader at, with the
# machine's own implementations, Intel's CPU runtime (PyPI opencl-rt, in a
# venv in the build tree) and the Oclgrind simulator (Debian). Without
# pip's registry the tests that need Intel's runtime skip, saying so.
INTEL_OPENCL := $(BUILD)/intel-opencl
INTEL_OPENCL_VERSION := 2021.2.0
OCLGRIND_ICD := /usr/lib/oclgrind/liboclgrind-rt-icd.so
$(VENDORS)/.stamp: | $(BUILD)/.deps-ok
	@rm -rf $(VENDORS) && mkdir -p $(VENDORS)
	@for f in /etc/OpenCL/vendors/*.icd; do [ -e "$$f" ] && ln -s "$$f" $(VENDORS)/; done; true
	@[ -e $(INTEL_OPENCL)/lib/libintelocl.so ] || { echo "make: installing Intel's CPU OpenCL runtime (PyPI opencl-rt)"; \
	  python3 -m venv $(INTEL_OPENCL) && $(INTEL_OPENCL)/bin/pip install -q opencl-rt==$(INTEL_OPENCL_VERSION); } \
	  || echo "make: warning: Intel's CPU OpenCL runtime could not be installed; the tests that need it will skip"
	@[ ! -e $(INTEL_OPENCL)/lib/libintelocl.so ] || echo "$(abspath $(INTEL_OPENCL))/lib/libintelocl.so" > $(VENDORS)/intel-cpu.icd
	@[ ! -e $(OCLGRIND_ICD) ] || echo $(OCLGRIND_ICD) > $(VENDORS)/oclgrind.icd
	@touch $@

# ---- build ----
$(BUILD)/embed: host/embed/embed.c
	@mkdir -p $(@D)
	$(CC) -std=c11 -O2 $(WARN) -o $@ $<

$(BUILD)/gen/kernel_source.c: kernels/lvcl.cl $(KERNELS) $(BUILD)/embed
	@mkdir -p $(@D)
	$(BUILD)/embed source lvcl_kernel_source $< > $@

$(BUILD)/gen/scene_%.c: scenes/%.gltf $(BUILD)/embed
	@mkdir -p $(@D)
	$(BUILD)/embed bytes lvcl_scene_$* $< > $@

$(BUILD)/obj/%.o: host/%.c $(HOST_H) kernels/shared_types.h | $(BUILD)/.deps-ok
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

$(BUILD)/obj/%.o: host/%.cpp $(HOST_H) kernels/shared_types.h | $(BUILD)/.deps-ok
	@mkdir -p $(@D)
	$(CXX) $(ALL_CXXFLAGS) -c -o $@ $<

$(BUILD)/obj/gen/%.o: $(BUILD)/gen/%.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

$(BUILD)/liblvcl.a: $(LIB_OBJS)
	rm -f $@ && ar rcs $@ $^

$(BUILD)/lvcl: host/app/main.c $(BUILD)/liblvcl.a
	$(CC) $(ALL_CFLAGS) -o $@ $^ $(LIBS)

# lvcl over MPI ranks (docs/distributed.md); Open MPI's flags from pkg-config,
# read when the rule runs (the package may have been installed by this make).
MPI_SOURCES := $(wildcard host/mpi/*.c)
$(BUILD)/lvcl-mpi: $(MPI_SOURCES) $(wildcard host/mpi/*.h) $(HOST_H) $(BUILD)/liblvcl.a
	$(CC) $(ALL_CFLAGS) $$(pkg-config --cflags mpi-c) -o $@ $(MPI_SOURCES) $(BUILD)/liblvcl.a $(LIBS) \
	  $$(pkg-config --libs mpi-c)

$(BUILD)/lvcl-%: host/tools/%.c $(BUILD)/liblvcl.a
	$(CC) $(ALL_CFLAGS) -o $@ $^ $(LIBS)

$(BUILD)/gen/test_kernel_source.c: tests/kernels/unit_tests.cl tests/kernels/test_args.h $(KERNELS) $(BUILD)/embed
	@mkdir -p $(@D)
	$(BUILD)/embed source lvcl_test_kernel_source $< > $@

TEST_SUPPORT := tests/harness.c $(BUILD)/gen/test_kernel_source.c
TEST_HEADERS := tests/check.h tests/harness.h tests/kernels/test_args.h $(HOST_H) kernels/shared_types.h
# $(1): tests/<layer>/test_<name>.c; $(2): the other .c files of its folder.
define test_program
$(BUILD)/tests/$(basename $(notdir $(1))): $(1) $(2) $(wildcard $(dir $(1))*.h) $(TEST_HEADERS) $(TEST_SUPPORT) $(BUILD)/liblvcl.a
	@mkdir -p $$(@D)
	$$(CC) $$(ALL_CFLAGS) -o $$@ $(1) $(2) $$(TEST_SUPPORT) $$(BUILD)/liblvcl.a $$(LIBS)
endef
$(foreach t,$(TEST_SOURCES),$(eval $(call test_program,$(t),$(filter-out $(dir $(t))test_%,$(wildcard $(dir $(t))*.c)))))

# ---- use ----
# The paper's kitchen with the light volume: out/kitchen.exr and .png, and
# how long each part took (about 20 s on two cores; the first run also
# compiles the kernels).
run: $(BUILD)/lvcl
	$(BUILD)/lvcl --spp 32 kitchen

# make test T=NAME runs one test (tests/run.sh takes the same names).
test: all
	@tests/run.sh $(BUILD) $(T)

# Every test program and the command-line tests under AddressSanitizer and
# UBSan, in a build tree of their own. Only PoCL's devices take part:
# Intel's runtime crashes inside its own compiler (clBuildProgram) when the
# host is built with ASan; the oclgrind command preloads its runtime, which
# ASan refuses ("ASan runtime does not come first"), and the fuzzers are
# sanitized builds already. Leaks are suppressed only inside the OpenCL stack.
# lvcl-mpi is left out: its ranks die at start under ASan inside Open MPI's
# runtime, and Open MPI's plug-ins leak from modules unloaded before the
# leak check; tests/render/test_cluster.c runs the render layer's
# distributed paths here, over threads.
ASAN_FLAGS := -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
test-asan: $(BUILD)/.deps-ok
	$(MAKE) BUILD=$(BUILD)/asan CFLAGS="$(ASAN_FLAGS)" CXXFLAGS="$(ASAN_FLAGS)" \
	  $(BUILD)/asan/lvcl $(BUILD)/asan/lvcl-compare $(BUILD)/asan/lvcl-bench \
	  $(addprefix $(BUILD)/asan/tests/,$(notdir $(TEST_BINS)))
	@OCL_ICD_VENDORS=/etc/OpenCL/vendors ASAN_OPTIONS=detect_leaks=1 \
	  LSAN_OPTIONS=suppressions=tests/asan/lsan.supp:print_suppressions=0 \
	  tests/run.sh $(BUILD)/asan --asan $(T)

# ---- fuzzing: libFuzzer harnesses built by Debian's clang with ASan and UBSan ----
# make fuzz runs each for FUZZ_SECONDS on a corpus in the build tree seeded
# with the embedded and test scenes; a crash is saved there as crash-*,
# to be added to tests/data/fuzz/<fuzzer>/ as a regression file. make test
# runs each briefly (tests/app/fuzz_tests.sh).
FUZZ_FLAGS := -O1 -g -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
FUZZ_LINK := -O1 -g -fsanitize=fuzzer,address,undefined -fno-omit-frame-pointer
FUZZ_SECONDS ?= 60
FUZZ_GLTF_OBJS := $(patsubst host/%,$(BUILD)/fuzz/obj/%.o,$(basename host/scene/scene.c host/scene/materials.c \
	host/scene/camera.c host/util/status.c $(wildcard host/scene/gltf/*.cpp)))
$(BUILD)/fuzz/obj/%.o: host/%.c $(HOST_H) kernels/shared_types.h | $(BUILD)/.deps-ok
	@mkdir -p $(@D)
	clang -std=c11 -D_POSIX_C_SOURCE=200809L $(FUZZ_FLAGS) -c -o $@ $<
$(BUILD)/fuzz/obj/%.o: host/%.cpp $(HOST_H) kernels/shared_types.h | $(BUILD)/.deps-ok
	@mkdir -p $(@D)
	clang++ -std=c++17 $(FUZZ_FLAGS) -c -o $@ $<
$(BUILD)/fuzz/fuzz_gltf: tests/fuzz/fuzz_gltf.c $(FUZZ_GLTF_OBJS)
	clang -std=c11 $(FUZZ_LINK) -o $@ $^ -ltinygltf -lstb -lstdc++ -lm
$(BUILD)/fuzz/fuzz_options: tests/fuzz/fuzz_options.c $(BUILD)/fuzz/obj/app/options.o $(BUILD)/fuzz/obj/util/status.o
	clang -std=c11 $(FUZZ_LINK) -o $@ $^ -lm

.PHONY: fuzz
fuzz: $(FUZZERS)
	@FUZZ_TEST_SECONDS=$(FUZZ_SECONDS) FUZZ_WORK_DIR=$(BUILD)/fuzz tests/app/fuzz_tests.sh $(BUILD)

# ---- references (Mitsuba 3 from PyPI, in a venv inside the build tree) ----
VENV := $(BUILD)/venv
REFDIR := tests/reference
.PHONY: venv scenes validate-converter
# Mitsuba's LLVM variant needs libLLVM 16 or later (with PoCL's older one
# alone it aborts); python3 -m venv needs python3-venv.
$(VENV)/.stamp: $(REFDIR)/requirements.txt
	$(call install_debian_packages,python3-venv libllvm19)
	python3 -m venv $(VENV)
	$(VENV)/bin/pip install -q -r $(REFDIR)/requirements.txt
	touch $@
venv: $(VENV)/.stamp

# The embedded scenes are generated by the project's own scripts and checked in.
scenes:
	python3 scenes/make_scenes.py
	python3 scenes/make_kitchen.py smooth scenes/kitchen.gltf

# The rippled kitchen (500,000 triangles per tile, about 140 million placed;
# not checked in): make kitchen-rippled, then build/scenes/kitchen-rippled.glb.
RIPPLED_KITCHEN := $(BUILD)/scenes/kitchen-rippled.glb
.PHONY: kitchen-rippled
kitchen-rippled: $(RIPPLED_KITCHEN)
$(RIPPLED_KITCHEN): scenes/make_kitchen.py scenes/make_scenes.py
	@mkdir -p $(dir $@)
	python3 scenes/make_kitchen.py rippled $@

# Regenerates the checked-in references (about 28 minutes on 2 cores).
references: $(VENV)/.stamp
	$(VENV)/bin/python $(REFDIR)/render_reference.py scenes/cornell.gltf $(REFDIR)/cornell.exr \
	  --spp 16384 --width 256 --height 256 --pass-spp 512
	$(VENV)/bin/python $(REFDIR)/render_reference.py scenes/furnace.gltf $(REFDIR)/furnace.exr \
	  --spp 4096 --width 64 --height 64 --pass-spp 1024
	$(VENV)/bin/python $(REFDIR)/render_reference.py scenes/glass-table.gltf $(REFDIR)/glass-table.exr \
	  --spp 40960 --width 256 --height 256 --pass-spp 512
	$(VENV)/bin/python $(REFDIR)/render_reference.py scenes/kitchen.gltf $(REFDIR)/kitchen.exr \
	  --spp 32768 --width 160 --height 120 --pass-spp 512

# Renders the shared references' scenes with the converter and compares, to
# show the converter agrees with the independent one (needs ../shared).
validate-converter: $(VENV)/.stamp
	for s in cornell cornell-spheres; do \
	  $(VENV)/bin/python $(REFDIR)/render_reference.py ../shared/reference/$$s.glb $(BUILD)/$$s.check.exr \
	    --spp 512 --width 256 --height 256 && \
	  $(VENV)/bin/python $(REFDIR)/compare.py $(BUILD)/$$s.check.exr ../shared/reference/$$s.mitsuba.exr || exit 1; \
	done

clean:
	rm -rf $(BUILD) out

# Applies .clang-format to every C, C++ and OpenCL C source.
FORMATTED := $(shell find host kernels tests bench -name '*.[ch]' -o -name '*.cpp' -o -name '*.cl' | grep -v '^tests/data/')
format:
	$(call install_debian_packages,clang-format-15)
	clang-format-15 -i --style=file $(FORMATTED)

# ---- benchmarks ----
# lvcl-bench rays: ray throughput on the workloads of bench/RAYS.md (shared
# notes), and the same rays through Embree 3 (Debian's libembree-dev, which
# make bench installs) with the ratios. lvcl-bench built without Embree
# says "embree": null.
.PHONY: bench
EMBREE_HEADER := /usr/include/embree3/rtcore.h
BENCH_SOURCES := bench/main.c bench/common.c bench/rays.c bench/wavefront.c
BENCH_HEADERS := bench/bench.h bench/rays.h bench/kernels/rays_args.h bench/kernels/wavefront_args.h
BENCH_FLAGS :=
BENCH_LIBS :=
ifneq ($(wildcard $(EMBREE_HEADER)),)
BENCH_SOURCES += bench/embree_compare.c
BENCH_FLAGS += -DLVCL_HAVE_EMBREE -fopenmp
BENCH_LIBS += -lembree3
endif

$(BUILD)/gen/bench_kernel_source.c: bench/kernels/rays.cl bench/kernels/rays_args.h $(KERNELS) $(BUILD)/embed
	@mkdir -p $(@D)
	$(BUILD)/embed source lvcl_bench_kernel_source $< > $@

$(BUILD)/gen/wavefront_kernel_source.c: bench/kernels/wavefront.cl bench/kernels/wavefront_args.h $(KERNELS) $(BUILD)/embed
	@mkdir -p $(@D)
	$(BUILD)/embed source lvcl_wavefront_kernel_source $< > $@

# A stamp named for whether Embree is there, so lvcl-bench is rebuilt when
# it comes or goes.
BENCH_EMBREE_STAMP := $(BUILD)/gen/bench-embree-$(if $(wildcard $(EMBREE_HEADER)),yes,no)
$(BENCH_EMBREE_STAMP):
	@mkdir -p $(@D) && rm -f $(BUILD)/gen/bench-embree-* && touch $@

BENCH_GEN := $(BUILD)/gen/bench_kernel_source.c $(BUILD)/gen/wavefront_kernel_source.c
$(BUILD)/lvcl-bench: $(BENCH_SOURCES) $(BENCH_HEADERS) $(HOST_H) $(BENCH_GEN) $(BUILD)/liblvcl.a $(BENCH_EMBREE_STAMP)
	$(CC) $(ALL_CFLAGS) $(BENCH_FLAGS) -o $@ $(BENCH_SOURCES) $(BENCH_GEN) $(BUILD)/liblvcl.a \
	  $(LIBS) $(BENCH_LIBS)

# A ~1M-triangle scene made by the project's own generator (not checked in).
BIG_SCENE := $(BUILD)/bench/big_room.glb
$(BIG_SCENE): bench/make_big_scene.py scenes/make_scenes.py
	@mkdir -p $(@D)
	python3 bench/make_big_scene.py $@

# The package first, then a new make: the Embree test above reads the disk
# when the Makefile is read.
bench:
	$(call install_debian_packages,libembree-dev)
	@$(MAKE) --no-print-directory bench-rays

.PHONY: bench-rays
bench-rays: $(BUILD)/lvcl-bench $(BIG_SCENE)
	@mkdir -p $(BUILD)/bench
	$(BUILD)/lvcl-bench rays cornell | tee $(BUILD)/bench/rays_cornell.jsonl
	$(BUILD)/lvcl-bench rays kitchen | tee $(BUILD)/bench/rays_kitchen.jsonl
	$(BUILD)/lvcl-bench rays $(BIG_SCENE) | tee $(BUILD)/bench/rays_big_room.jsonl
