# mefem build. `make run` and `make test` do everything on a fresh Debian 12 machine:
# they install missing packages (make deps), build, and run the main example / all tests.
#
#   make            release build: bin/mefem
#   make DEBUG=1    debug build (bounds checks, FPE traps): bin/mefem_debug
#   make run        install, build, run the main example deck
#   make test       install, build (release + debug), run every test; last line "N passed, N failed"
#   make bench      benchmarks: deck reading, linear static, plasticity, explicit (ns per element-cycle),
#                   contact, the copper Taylor bar's time to solution per element; figures
#   make punch      the seed paper's punch study (post/punch_study.py; ~8-12 min)
#   make sphere     the seed paper's sphere compression (post/sphere_study.py; 2 runs on 2 ranks)
#   make deps       install the Debian packages that are missing (no-op when all present)
#   make clean

SHELL := /bin/bash

# ---- packages -------------------------------------------------------------------------
DEB_BUILD := gfortran make openmpi-bin libopenmpi-dev libmumps-dev libmetis-dev \
             libhdf5-openmpi-dev hdf5-tools liblapack-dev libblas-dev libopenblas-dev
DEB_TEST  := python3 python3-numpy python3-h5py python3-vtk9 python3-matplotlib python3-meshio
DEB_ALL   := $(DEB_BUILD) $(DEB_TEST)
SUDO      := $(if $(filter 0,$(shell id -u)),,sudo)

# ---- MPI runs as root and with more ranks than cores (tests use up to 4 ranks) --------
export OMPI_ALLOW_RUN_AS_ROOT := 1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM := 1
export OMPI_MCA_rmaps_base_oversubscribe := 1
export OPENBLAS_NUM_THREADS := 1
MPIRUN := mpirun --oversubscribe

# ---- compiler and libraries -----------------------------------------------------------
FC       := mpif90
HDF5_DIR := /usr/lib/x86_64-linux-gnu/hdf5/openmpi
INCLUDES := -I/usr/include -I$(HDF5_DIR)/include
LIBS     := -L$(HDF5_DIR)/lib -Wl,-rpath,$(HDF5_DIR)/lib -lhdf5_fortran -lhdf5 \
            -ldmumps -lmumps_common -lmetis -llapack -lblas
WARN     := -std=f2008 -Wall -Wno-maybe-uninitialized -fimplicit-none

# Instruction set of the release build: x86-64-v3 (AVX2 and FMA, which the explicit block
# kernels are written to vectorise with) when the CPU
# that builds has it (glibc's loader lists the levels it supports), else x86-64-v2. A binary
# built here runs on CPUs of that level or newer; `make ARCH=x86-64-v2` builds a portable one.
ifndef ARCH
  ARCH := $(shell /lib64/ld-linux-x86-64.so.2 --help 2>/dev/null | \
            grep -q 'x86-64-v3 .supported' && echo x86-64-v3 || echo x86-64-v2)
endif

ifeq ($(DEBUG),1)
  BUILD  := build/debug
  EXE    := bin/mefem_debug
  FFLAGS := $(WARN) -O0 -g -fcheck=all,no-array-temps -ffpe-trap=invalid,zero,overflow -fbacktrace
else
  BUILD  := build/release
  EXE    := bin/mefem
  FFLAGS := $(WARN) -O3 -march=$(ARCH) -g -fno-backtrace
endif

# Every .f90 under src/ is part of the library except the main program.
SRC      := $(sort $(wildcard src/*/*.f90))
MAIN_SRC := src/main/mefem.f90
LIB_SRC  := $(filter-out $(MAIN_SRC),$(SRC))
LIB_OBJ  := $(patsubst src/%.f90,$(BUILD)/%.o,$(LIB_SRC))
MAIN_OBJ := $(patsubst src/%.f90,$(BUILD)/%.o,$(MAIN_SRC))
UNIT_SRC := $(sort $(wildcard tests/unit/test_*.f90))
UNIT_EXE := $(patsubst tests/unit/%.f90,$(BUILD)/tests/%,$(UNIT_SRC))
HARNESS  := $(BUILD)/tests/testing.o $(BUILD)/tests/fixtures.o

.PHONY: all deps build run test bench punch sphere clean lint unit-tests
.DEFAULT_GOAL := all

all: deps $(EXE)

# Install whatever of the Debian packages is missing; a no-op when everything is there.
deps:
	@missing=""; for p in $(DEB_ALL); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'install ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "make deps: installing$$missing"; \
	  $(SUDO) apt-get -o DPkg::Lock::Timeout=600 update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get -o DPkg::Lock::Timeout=600 install -y -qq \
	    --no-install-recommends $$missing >/dev/null && echo "make deps: done"; \
	fi

$(EXE): $(LIB_OBJ) $(MAIN_OBJ) | bin
	$(FC) $(FFLAGS) -o $@ $(MAIN_OBJ) $(LIB_OBJ) $(LIBS)

bin:
	@mkdir -p bin

# Module dependencies are derived from the sources (use/module statements).
$(BUILD)/deps.mk: $(SRC) $(UNIT_SRC) tests/unit/testing.f90 tests/unit/fixtures.f90 \
                  src/fortran_deps.sh
	@mkdir -p $(BUILD)
	@bash src/fortran_deps.sh $(BUILD) $(SRC) tests/unit/testing.f90 tests/unit/fixtures.f90 \
	  $(UNIT_SRC) > $@

-include $(BUILD)/deps.mk

# The compile command of this build, rewritten only when it changes (another ARCH, FC or
# FFLAGS): every object depends on it, so a change of flags rebuilds all of them instead of
# leaving objects of two instruction sets in one binary.
COMPILE := $(FC) $(FFLAGS) $(INCLUDES)
$(BUILD)/compile_flags: FORCE
	@mkdir -p $(BUILD)
	@echo '$(COMPILE)' | cmp -s - $@ || echo '$(COMPILE)' > $@

.PHONY: FORCE
FORCE:

$(BUILD)/%.o: src/%.f90 $(BUILD)/compile_flags
	@mkdir -p $(dir $@) $(BUILD)/mod
	$(COMPILE) -J$(BUILD)/mod -c $< -o $@

$(BUILD)/tests/%.o: tests/unit/%.f90 $(BUILD)/compile_flags
	@mkdir -p $(dir $@) $(BUILD)/mod
	$(COMPILE) -J$(BUILD)/mod -c $< -o $@

$(BUILD)/tests/test_%: $(BUILD)/tests/test_%.o $(HARNESS) $(LIB_OBJ)
	$(FC) $(FFLAGS) -o $@ $< $(HARNESS) $(LIB_OBJ) $(LIBS)

unit-tests: $(UNIT_EXE)

# The explicit example: Taylor impact of an aluminium cylinder on a rigid wall, 2 MPI ranks.
run: deps
	@$(MAKE) --no-print-directory $(EXE)
	mpirun --oversubscribe -np 2 ./$(EXE) -o results/taylor_bar input/taylor_bar.k

# All tests: unit tests on the debug build (and the block kernels' placement checks on the
# release build), deck tests, output and MPI tests.
test: deps
	@$(MAKE) --no-print-directory bin/mefem build/release/tests/test_block_kernels
	@$(MAKE) --no-print-directory DEBUG=1 bin/mefem_debug unit-tests
	@bash tests/run_tests.sh

bench: deps
	@$(MAKE) --no-print-directory bin/mefem
	@bash tests/bench/run_bench.sh
	@bash tests/bench/run_linear_static_bench.sh
	@bash tests/bench/run_plasticity_bench.sh
	@bash tests/bench/run_explicit_bench.sh
	@/usr/bin/python3 tests/bench/run_contact_bench.py
	@/usr/bin/python3 tests/bench/taylor_copper.py --meshes coarse medium

# The seed paper's punch study (doc/verification.md): twenty runs (rigid and nodal punch),
# figures and tables in doc/verification_data/punch_*; 330 s of CPU, about 8-12 minutes on 2
# cores shared with other jobs.
punch: deps
	@$(MAKE) --no-print-directory bin/mefem
	/usr/bin/python3 post/punch_study.py

# The seed paper's sphere compression (doc/verification.md): frictionless and frictional mortar
# contact, one run after the other on 2 ranks, figures and tables in
# doc/verification_data/sphere_*.
sphere: deps
	@$(MAKE) --no-print-directory bin/mefem
	/usr/bin/python3 post/sphere_study.py

# The code rules (implicit none, private modules, no legacy statements, newunit, each library
# behind its one module); also part of make test (tests/style/test_code_rules.sh).
lint:
	@bash tests/style/check_code_rules.sh

clean:
	rm -rf build bin results tests/out
