# The README's two commands:
#   make run    installs what is missing, builds, runs the paper's 2D example and
#               draws its figures (Figs 4.6-4.7, PNG; without matplotlib: a warning)
#   make test   installs what is missing, builds what the quick tier needs and runs it
#               (CTest label quick: every module touched, the paper's 1D and 2D examples,
#               one MPI run, the Python module; docs/reliability.md)
# and, for CI (.ci/run) and docs/reliability.md:
#   make test-all        builds everything and runs every test (SKIP_QUICK=1: all but the
#                        quick tier, for CI, which has just run `make test`)
#   make test-sanitize   the tests again (but SANITIZE_SKIP's heaviest), built with
#                        AddressSanitizer and UndefinedBehaviorSanitizer in $(SANITIZE_BUILD)
#   make test-mpi        the PETSc + MPI engine's tests alone (under mpirun -np 1, 2, 3;
#                        docs/parallel.md); `make test-all` runs them too
BUILD ?= build
SANITIZE_BUILD ?= build-asan
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
PETSC ?= ON  # OFF: the serial engine alone, no MPI or PETSc installed
CASE ?= paper-2d

.PHONY: all deps configure build run test test-all test-sanitize test-mpi clean

all: build

deps:
	@bash scripts/install-deps.sh $(if $(filter OFF,$(PETSC)),--serial,)

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DVPCONTACT_ENABLE_PETSC=$(PETSC) > /dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# The run needs the program alone: not the ~400 test files that `build` compiles too.
run: configure
	@cmake --build $(BUILD) -j $(JOBS) --target vpcontact
	./$(BUILD)/app/vpcontact run $(CASE) --plot

# As root (containers, CI) OpenMPI needs consent; 3 ranks oversubscribe 2 cores.
MPI_ENV = OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

# The quick tier builds the program, the Python module and vpcontact_quick_tests alone (target
# vpcontact_quick_tier, tests/CMakeLists.txt): not the other test executables, which `test-all` builds.
test: configure
	@cmake --build $(BUILD) -j $(JOBS) --target vpcontact_quick_tier
	cd $(BUILD) && $(MPI_ENV) ctest --output-on-failure -j $(JOBS) -L quick

test-all: build
	cd $(BUILD) && $(MPI_ENV) ctest --output-on-failure -j $(JOBS) $(if $(SKIP_QUICK),-LE quick,)

# -O1 -g1 (line tables: ASan's reports keep file and line): compiles in 0.55x the time of -O2 -g
# (measured on src/solvers/dual_active_set.cpp: 9.3 s against 16.8 s), which halves CI's sanitized build.
SANITIZE_OPT ?= -O1 -g1 -DNDEBUG
# Leaks inside Gmsh are suppressed (tests/lsan.supp); any other report fails the test.
# Without PETSc: MPI's own allocations are not ours to check (the MPI tests run in `make test-all`).
# SANITIZE_SKIP: the heaviest runs, whose code paths smaller tests take too (the same solvers on
# larger meshes: under ASan they cost minutes each, 60 % of the sanitized tests' time); `make test-all`
# runs them. Set SANITIZE_SKIP= to run every test.
SANITIZE_SKIP ?= PrimalDual/EveryShippedCase.PrimalAndDualAgree/(hertz_2d|hertz_3d|hertz_cylinders_2d|hertz_spheres_3d|ironing_3d|indentation_3d|cattaneo_mindlin_2d|cattaneo_mindlin_pair_2d)( |$$)|^FrictionBenchmarks.CattaneoMindlin|^FrictionIroning.RunsToTheEnd|^cli.check_(cattaneo-mindlin-2d|cattaneo-mindlin-pair-2d|ironing-3d)$$|^Hertz.(LineContactOnARigidCylinder|SphereIntoAHalfSpaceQuarterModel)$$
test-sanitize: deps
	@cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$(SANITIZE_OPT)" -DVPCONTACT_SANITIZE=ON -DVPCONTACT_PYTHON=OFF -DVPCONTACT_BENCHMARKS=OFF -DVPCONTACT_ENABLE_PETSC=OFF > /dev/null
	@cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	cd $(SANITIZE_BUILD) && \
	  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 \
	  ctest --output-on-failure -j $(JOBS) $(if $(SANITIZE_SKIP),-E '$(SANITIZE_SKIP)',)

test-mpi: build
	cd $(BUILD) && $(MPI_ENV) ctest --output-on-failure -L mpi

clean:
	rm -rf $(BUILD) $(SANITIZE_BUILD)
