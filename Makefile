# Two commands do everything on a fresh machine with Python >= 3.11 and pip:
#   make demo   set up .venv with manip alone (no extras), prebuild its kernels, run the
#               flagship pick-and-place headless (fresh clone, 2-core machine, no pip cache:
#               1.7 min: install 40 s, prebuild 48 s, three episodes 10 s; 1.4 GB in .venv)
#   make test   set up .venv with manip-robotics[dev,video,viz,ray,datagen], prebuild, run the test
#               suite (fresh clone, 2-core machine, no pip cache: 17-18 min, of which 1603
#               tests 10-13 min)
# Both install into .venv only. `make wheel` builds the wheel (with the prebuilt kernels) and
# the sdist into dist/ and checks them.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
CORE   := $(VENV)/.installed-core
FULL   := $(VENV)/.installed-full
# the compiled kernels and the Panda's collision geometry, built ahead of time (manip.prebuild)
PREBUILT := manip/_prebuilt/kernels/manifest.json
KERNEL_SOURCES := $(shell grep -rl --include='*.py' '^@kernel' manip) manip/jit.py manip/prebuild.py

.PHONY: setup test demo bench wheel clean

$(PY):
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11))' || { echo "manip needs Python >= 3.11 (MuJoCo 4 does); $(PYTHON) is $$($(PYTHON) -V 2>&1): run e.g. make $(MAKECMDGOALS) PYTHON=python3.12" >&2; exit 1; }
	$(PYTHON) -m venv $(VENV)

$(CORE): $(PY) pyproject.toml
	$(PY) -m pip install --upgrade pip
	$(PY) -m pip install -e .
	touch $(CORE)

$(FULL): $(CORE)
	$(PY) -m pip install -e ".[dev,video,viz,ray,datagen]"
	touch $(FULL)

$(PREBUILT): $(CORE) $(KERNEL_SOURCES)
	$(PY) -m manip.prebuild --robots franka

setup: $(FULL) $(PREBUILT)

test: $(FULL) $(PREBUILT)
	$(PY) -m pytest -q $(PYTEST_ARGS)

demo: $(CORE) $(PREBUILT)
	$(PY) examples/pick_and_place.py --episodes 3

# The wheel carries the prebuilt kernels and every shipped robot's geometry, with the kernels of
# each Python of WHEEL_PYTHONS found here besides the venv's (a venv .venv-3.X each, `prebuild --add`);
# users of a Python not found compile the kernels on first use (20-40 s once).
WHEEL_PYTHONS ?= python3.11 python3.12 python3.13
wheel: $(FULL)
	$(PY) -m manip.prebuild --robots all
	@own=$$($(PY) -c 'import sys; print("%d.%d" % sys.version_info[:2])'); \
	for p in $(WHEEL_PYTHONS); do \
	  v=$$($$p -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null) || \
	    { echo "wheel: no working $$p here (WHEEL_PYTHONS names the interpreters): the wheel carries no kernels for it"; continue; }; \
	  [ "$$v" = "$$own" ] && continue; \
	  $$p -m venv .venv-$$v && .venv-$$v/bin/python -m pip install --quiet --upgrade pip && \
	  .venv-$$v/bin/python -m pip install --quiet -e . && \
	  .venv-$$v/bin/python -m manip.prebuild --add --robots all || exit 1; \
	done
	$(PY) -m pip install --quiet build twine
	rm -rf dist
	$(PY) -m build --wheel    # from the checkout: the sdist leaves the prebuilt files out
	$(PY) -m build --sdist
	$(PY) -m twine check dist/*

# Benchmarks (results go to BENCHMARKS.md); the peers come with the bench extra.
bench: $(FULL) $(PREBUILT)
	$(PY) -m pip install -e ".[bench]"
	$(PY) benchmarks/cold_start.py --write-md
	$(PY) benchmarks/kinematics.py --write-md
	$(PY) benchmarks/sim.py --write-md
	$(PY) benchmarks/pick_and_place.py --episodes 100 --write-md
	$(PY) benchmarks/mbm.py --goal both --planners manip,roboplan,ompl --write-md

clean:
	rm -rf $(VENV) .venv-3.* build dist *.egg-info .pytest_cache manip/_prebuilt
