# lvcl: `make run` installs what is missing, builds and renders the default
# scene; `make test` runs the test suite. Everything built lands in build/.

CC ?= cc
CXX ?= c++
BUILD := build
CFLAGS ?= -O2 -g
CXXFLAGS ?= -O2 -g
WARN := -Wall -Wextra -Wno-missing-field-initializers -Wno-format-truncation
ALL_CFLAGS := -std=c11 -D_POSIX_C_SOURCE=200809L $(WARN) $(CFLAGS)
ALL_CXXFLAGS := -std=c++17 $(WARN) $(CXXFLAGS)
LIBS := -lOpenCL -lOpenImageIO -lOpenImageIO_Util -ltinygltf -lstdc++ -lm

# Debian packages lvcl needs to build and run.
DEBIAN_PACKAGES := build-essential pocl-opencl-icd ocl-icd-opencl-dev opencl-c-headers \
	libopenimageio-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libglm-dev

HOST_C := $(filter-out host/main.c,$(wildcard host/*.c))
HOST_CXX := $(wildcard host/*.cpp)
KERNELS := $(wildcard kernels/*.h kernels/*.cl)
GEN_C := $(BUILD)/gen/kernel_source.c $(BUILD)/gen/scene_cornell.c $(BUILD)/gen/scene_furnace.c

# The library of everything but main(), shared by lvcl, the tests and the benchmarks.
define objects_in
$(patsubst host/%.c,$(1)/obj/%.o,$(HOST_C)) $(patsubst host/%.cpp,$(1)/obj/%.o,$(HOST_CXX)) \
	$(patsubst $(BUILD)/gen/%.c,$(1)/obj/gen/%.o,$(GEN_C))
endef
LIB_OBJS := $(call objects_in,$(BUILD))

TEST_SOURCES := $(wildcard tests/test_*.c)
TEST_BINS := $(patsubst tests/%.c,$(BUILD)/tests/%,$(TEST_SOURCES))

.PHONY: all run test test-asan deps references clean
all: $(BUILD)/lvcl $(TEST_BINS)

# ---- set-up ----
deps: $(BUILD)/.deps-ok
$(BUILD)/.deps-ok:
	@missing=""; for p in $(DEBIAN_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "make: installing Debian packages:$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=""; elif command -v sudo >/dev/null; then SUDO=sudo; \
	  else echo "make: error: missing packages:$$missing; install them as root (apt-get install$$missing)"; exit 1; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null \
	  || { echo "make: error: apt-get could not install:$$missing"; exit 1; }; \
	fi
	@mkdir -p $(BUILD) && touch $@

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

$(BUILD)/obj/%.o: host/%.c host/*.h kernels/shared_types.h | $(BUILD)/.deps-ok
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

$(BUILD)/obj/%.o: host/%.cpp host/*.h kernels/shared_types.h | $(BUILD)/.deps-ok
	@mkdir -p $(@D)
	$(CXX) $(ALL_CXXFLAGS) -c -o $@ $<

$(BUILD)/obj/gen/%.o: $(BUILD)/gen/%.c
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

$(BUILD)/liblvcl.a: $(LIB_OBJS)
	ar rcs $@ $^

$(BUILD)/lvcl: host/main.c $(BUILD)/liblvcl.a
	$(CC) $(ALL_CFLAGS) -o $@ $^ $(LIBS)

$(BUILD)/tests/%: tests/%.c tests/check.h $(BUILD)/liblvcl.a
	@mkdir -p $(@D)
	$(CC) $(ALL_CFLAGS) -Ihost -o $@ $< $(BUILD)/liblvcl.a $(LIBS)

# ---- use ----
run: $(BUILD)/lvcl
	$(BUILD)/lvcl cornell

test: all
	@tests/run.sh $(BUILD)

# The bad-input and import tests under AddressSanitizer and UBSan, in a
# build tree of their own.
ASAN_FLAGS := -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
test-asan: $(BUILD)/.deps-ok
	$(MAKE) BUILD=$(BUILD)/asan CFLAGS="$(ASAN_FLAGS)" CXXFLAGS="$(ASAN_FLAGS)" \
	  $(BUILD)/asan/lvcl $(BUILD)/asan/tests/test_gltf_import
	@ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=tests/asan/lsan.supp \
	  tests/run.sh $(BUILD)/asan --asan

# Regenerates the Mitsuba references in tests/reference/ (slow; needs PyPI).
references: $(BUILD)/lvcl
	tests/reference/make_references.sh $(BUILD)

clean:
	rm -rf $(BUILD) out
