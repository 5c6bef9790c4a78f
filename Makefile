# Two commands set everything up on a fresh machine:
#   make demo   create .venv, install armkit, run the main job on the bundled fighter arm
#   make test   create .venv, install armkit with test extras, run the whole suite
PYTHON ?= python3
# Python writes each module's bytecode (.pyc, in __pycache__ folders git ignores) the first time it imports it, in
# .venv and src/. Where PYTHONDONTWRITEBYTECODE is set (it is on this project's machines) nothing was written and uv
# compiles nothing at install, so every new process (each test worker, each CLI command a test runs) parsed numpy,
# matplotlib, typer, rich ... from source again: `armkit info fighter` took 2.0 s in a fresh clone instead of 1.0 s.
# Compiling all of .venv at install instead (uv --compile-bytecode, ~10,000 files) took 47 s more in a clean clone.
unexport PYTHONDONTWRITEBYTECODE
VENV   := .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip

.PHONY: demo test fuzz bench bench-so101 clean chromium locale locale-update fonts pictures


# uv installs the ~140 packages of [test] (about 1 GB) with parallel downloads: 44 s on this machine with its
# download cache empty, 22 s with it filled, where pip took 139 s the same day; where uv cannot be had or fails,
# pip does the same install
$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --quiet --upgrade pip
	($(PIP) install --quiet uv && $(PY) -m uv pip install --python $(PY) --quiet -e '.[test]') || \
		$(PIP) install --quiet -e '.[test]'   # [test] pulls armkit[all]: every optional extra
	touch $@

demo: $(VENV)/.installed locale fonts
	$(PY) examples/00_demo.py

# the messages in every language of armkit/locale/languages.py: gettext catalogues compiled by Babel (docs/languages.md)
LOCALE_PO := $(wildcard src/armkit/locale/*/LC_MESSAGES/armkit.po)
LOCALE_MO := $(LOCALE_PO:.po=.mo)
locale: $(LOCALE_MO)
src/armkit/locale/%/LC_MESSAGES/armkit.mo: src/armkit/locale/%/LC_MESSAGES/armkit.po $(VENV)/.installed
	$(VENV)/bin/pybabel compile --use-fuzzy -d src/armkit/locale -D armkit -l $*
# after adding or changing _("...") messages: re-extract them and merge into every .po (then translate); `-k of`
# finds the templates of ArmkitError.of(...) and Fielded.of(...) at raise sites
locale-update: $(VENV)/.installed
	$(VENV)/bin/pybabel extract -F babel.cfg -k _ -k N_ -k NC_:1c,2 -k of --no-location --project armkit \
		-o src/armkit/locale/armkit.pot .
	$(VENV)/bin/pybabel update -i src/armkit/locale/armkit.pot -d src/armkit/locale -D armkit

# the browser tests (tests/viz/view) drive Debian's chromium headless through Playwright;
# never `playwright install` (it downloads a browser). apt installs it when missing.
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
chromium:
	@command -v chromium >/dev/null 2>&1 || [ -x /usr/bin/chromium ] || \
		($(SUDO) apt-get update && $(SUDO) apt-get install -y chromium)

# the pictures' fonts: each language of the table (src/armkit/locale/languages.py) names the Debian package of its
# font (Korean: fonts-nanum); `python -m armkit.locale.fonts` prints those whose font is not found, and they are
# installed (without one, that language's pictures fall back to English labels with a warning; docs/languages.md)
fonts: $(VENV)/.installed
	@pkgs="$$($(PY) -m armkit.locale.fonts)" && { [ -z "$$pkgs" ] || \
		($(SUDO) apt-get update && $(SUDO) apt-get install -y $$pkgs); }

# mypy (~15-30 s on one core) runs beside pytest: it fills the moments when one core idles (the end of the kernels'
# two-process warm-up in tests/conftest.py, the last tests of a worker) instead of adding its time at the end;
# its report follows pytest's, and the target fails if either does. Its incremental cache is the machine's
# (~/.cache/armkit/mypy, as the kernels' store: docs/performance.md), not the clone's: a new clone of sources it
# has checked takes 0.2 s instead of 15 CPU-s (mypy checks each file's hash where its time stamp differs; where the
# folder cannot be made, the clone's own .mypy_cache)
MYPY_CACHE := $(or $(XDG_CACHE_HOME),$(HOME)/.cache)/armkit/mypy
# pytest: two workers (pytest-xdist; the suite is CPU-bound, this machine has 2 cores); an idle worker takes queued
# tests from the busy one (--dist worksteal)
test: $(VENV)/.installed chromium locale fonts
	@cache=$$(mkdir -p "$(MYPY_CACHE)" 2>/dev/null && echo "--cache-dir=$(MYPY_CACHE)"); \
	$(PY) -m mypy $$cache > $(VENV)/mypy.log 2>&1 & types=$$!; \
	echo "$(PY) -m pytest -n 2 --dist worksteal   (mypy beside it)"; \
	$(PY) -m pytest -n 2 --dist worksteal; tests=$$?; \
	wait $$types; typed=$$?; echo "$(PY) -m mypy"; cat $(VENV)/mypy.log; [ $$tests = 0 ] && [ $$typed = 0 ]

# the long fuzz and corruption run (issue 24): reach stores, URDF and scene files, CLI arguments (reach, so101, info,
# view, convert; and the computing commands), 10 minutes;
# it prints its seed first and a table of outcomes per surface (exit 1 on any traceback, hang or wrong value).
# Rerun a run with `make fuzz SEED=<seed>`; the quick Hypothesis part is tests/hardening/test_fuzz_quick.py.
fuzz: $(VENV)/.installed
	$(PY) tests/hardening/fuzz_long.py $(if $(SEED),--seed $(SEED))

# refresh the docs pictures: the browser view's screenshots (docs/img/view-*.png) and make demo's
# branch picture (tests write theirs to a temporary folder; only this target rewrites docs/img)
pictures: $(VENV)/.installed chromium locale fonts
	ARMKIT_UPDATE_PICTURES=1 $(PY) -m pytest -q tests/viz/view/test_view.py tests/viz/view/test_notebook.py tests/viz/view/test_view_readouts.py
	$(PY) -c "from armkit.viz.demo import write_demo_pictures as w; import shutil; shutil.copy(w('out')[1], 'docs/img/fighter_ik_branches.png')"
	$(PY) -c "from armkit.viz.axes import class_gallery; from armkit.viz.plots import save_figure; save_figure(class_gallery(), 'docs/img/ik_classes.png', dpi=90)"

# the peers (pin, roboticstoolbox-python, ikpy, pytorch-kinematics, CPU torch) live in their own venv
BENCH_VENV := .venv-bench
BENCH_PY   := $(BENCH_VENV)/bin/python

$(BENCH_VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(BENCH_VENV)
	$(BENCH_PY) -m pip install --quiet --upgrade pip
	$(BENCH_PY) -m pip install --quiet -e '.[bench,test]'
	touch $@

bench: $(BENCH_VENV)/.installed
	$(BENCH_PY) benchmarks/bench_fk.py
	if [ -f benchmarks/bench_ik.py ]; then $(BENCH_PY) benchmarks/bench_ik.py; fi
	$(BENCH_PY) benchmarks/bench_urdf.py
	$(BENCH_PY) benchmarks/bench_analytic.py
	$(BENCH_PY) -m pytest -q tests/peers

# placo (LeRobot's IK library) pins an older pin, so it gets its own venv beside armkit for bench_so101; LeRobot
# itself goes in with --no-deps (its kinematics file needs only NumPy and placo: no torch) for its peer test
PLACO_VENV := .venv-placo
$(PLACO_VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(PLACO_VENV)
	$(PLACO_VENV)/bin/python -m pip install --quiet --upgrade pip
	$(PLACO_VENV)/bin/python -m pip install --quiet -e . placo pytest hypothesis
	$(PLACO_VENV)/bin/python -m pip install --quiet --no-deps lerobot
	touch $@

bench-so101: $(PLACO_VENV)/.installed
	$(PLACO_VENV)/bin/python benchmarks/bench_so101.py
	$(PLACO_VENV)/bin/python -m pytest -q -p no:cacheprovider tests/peers/test_lerobot_peer.py

clean:
	rm -rf $(VENV) $(BENCH_VENV) $(PLACO_VENV) out build *.egg-info src/*.egg-info
