# grainlift: two commands do all set-up on a fresh Debian machine (see README.md).
#   make demo   install deps if missing, configure, build, run cases/demo/, print where results are
#   make test   install deps if missing, configure, build, run the test suite (ctest)
BUILD ?= build
JOBS ?= 2
DEMO_SOLVER ?= both
CMAKE_FLAGS ?=
PYTHON ?= /usr/bin/python3

.PHONY: all deps configure build demo test test-fast bench docs-keys clean

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

# time to an answer, as ratios measured in one run on this machine (bench/speed_to_answer.sh:
# DEM against LAMMPS on a whole production run, thread scaling, replicas, fields, error against
# wall time; ~12 min), then the state hashes that show the step bit-identical on 1 and 2 threads
bench: build
	bash bench/speed_to_answer.sh $(BUILD)
	$(BUILD)/bin/dem_state_hash 3000

# regenerate the key table of docs/case-format.md from the registry
docs-keys: build
	$(PYTHON) scripts/update_case_docs.py $(BUILD)/bin/grainlift docs/case-format.md

clean:
	rm -rf $(BUILD) $(BUILD).configure.log
