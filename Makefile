# Two commands do everything on a fresh machine with Python >= 3.10 and pip:
#   make test   set up .venv, install manip[dev,video,ray], run the test suite
#   make demo   set up .venv, run the flagship example headless
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: setup test demo bench clean

$(PY):
	$(PYTHON) -m venv $(VENV)

$(STAMP): $(PY) pyproject.toml
	$(PY) -m pip install --upgrade pip
	$(PY) -m pip install -e ".[dev,video,viz,ray]"
	touch $(STAMP)

setup: $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q $(PYTEST_ARGS)

demo: $(STAMP)
	$(PY) examples/pick_and_place.py --episodes 3

# Benchmarks (results go to BENCHMARKS.md); the peers come with the bench extra.
bench: $(STAMP)
	$(PY) -m pip install -e ".[bench]"
	$(PY) benchmarks/kinematics.py --write-md
	$(PY) benchmarks/sim.py --write-md
	$(PY) benchmarks/pick_and_place.py --episodes 100 --write-md
	$(PY) benchmarks/mbm.py --goal both --planners manip,roboplan,ompl --write-md

clean:
	rm -rf $(VENV) build dist *.egg-info .pytest_cache
