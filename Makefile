# grainlift: two commands do all set-up on a fresh Debian machine (see README.md).
#   make demo   install deps if missing, configure, build, run cases/demo/, print where results are
#   make test   install deps if missing, configure, build, run the test suite (ctest)
BUILD ?= build
JOBS ?= 2
DEMO_SOLVER ?= both
CMAKE_FLAGS ?=
PYTHON ?= /usr/bin/python3

.PHONY: all deps configure build demo test test-fast sanitize bench docs-keys docs-schema clean

all: build

deps:
	@bash scripts/install-deps

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > $(BUILD).configure.log 2>&1 \
	  || { cat $(BUILD).configure.log; exit 1; }

build: configure
	cmake --build $(BUILD) -j$(JOBS)

demo: build
	$(BUILD)/bin/grainlift run cases/demo/demo.toml --solver $(DEMO_SOLVER) --out out/demo --threads $(JOBS)
	$(PYTHON) scripts/plot_results.py out/demo
	$(BUILD)/bin/grainlift report out/demo
	@echo "demo results: out/demo/ (report.html: DEM and FEM side by side; summary.json, *.h5 for h5py, *_fields.xmf for ParaView, *.png plots)"

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

# unit tests only, without the minutes-long regression runs
test-fast: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS) -LE regression

# AddressSanitizer + UndefinedBehaviorSanitizer: everything built in $(SANITIZE_BUILD), then the
# unit tests there (not the minutes-long labels regression/stress/fuzz/asymptotic, 3-10x slower under
# ASan). Reports stop the test that hit them; the last result is in docs/reliability.md. Leak
# detection is off: the MPI runtime that deal.II starts in every binary leaves allocations in
# modules it has unloaded, which LeakSanitizer can neither name nor suppress (docs/reliability.md).
SANITIZE_BUILD ?= build-sanitize
SANITIZE_ENV = ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:strict_string_checks=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
sanitize: deps
	@cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGRAINLIFT_SANITIZE=ON \
	  -DGRAINLIFT_BUILD_BENCH=OFF > $(SANITIZE_BUILD).configure.log 2>&1 \
	  || { cat $(SANITIZE_BUILD).configure.log; exit 1; }
	cmake --build $(SANITIZE_BUILD) -j$(JOBS)
	cd $(SANITIZE_BUILD) && $(SANITIZE_ENV) ctest --output-on-failure -j$(JOBS) -LE 'regression|stress|fuzz|asymptotic' --timeout 1800

# time to an answer, as ratios measured in one run on this machine (bench/speed_to_answer.sh:
# DEM against LAMMPS on a whole production run, thread scaling, replicas, fields, error against
# wall time; ~12 min), then the state hashes that show the step bit-identical on 1 and 2 threads
bench: build
	bash bench/speed_to_answer.sh $(BUILD)
	$(BUILD)/bin/dem_state_hash 3000

# regenerate the key table of docs/case-format.md from the registry
docs-keys: build
	$(PYTHON) scripts/update_case_docs.py $(BUILD)/bin/grainlift docs/case-format.md

# regenerate the table of docs/schema.md (between its schema markers) from the schema table
docs-schema: build
	$(BUILD)/bin/grainlift schema --markdown > $(BUILD)/schema-table.md
	awk -v table=$(BUILD)/schema-table.md \
	  '/<!-- schema:end -->/ { while ((getline line < table) > 0) print line; skip = 0 } \
	   !skip { print } /<!-- schema:begin -->/ { skip = 1 }' docs/schema.md > $(BUILD)/schema.md
	cmp -s $(BUILD)/schema.md docs/schema.md || { cp $(BUILD)/schema.md docs/schema.md; \
	  echo "updated docs/schema.md"; }

clean:
	rm -rf $(BUILD) $(BUILD).configure.log
