# Two commands set everything up on a fresh machine:
#   make demo   create .venv, install armkit, run the main job on the bundled fighter arm
#   make test   create .venv, install armkit with test extras, run the whole suite
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip

.PHONY: demo test bench clean

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --quiet --upgrade pip
	$(PIP) install --quiet -e '.[test]'
	touch $@

demo: $(VENV)/.installed
	$(PY) examples/00_demo.py

test: $(VENV)/.installed
	$(PY) -m pytest
	$(PY) -m mypy

bench: $(VENV)/.installed
	$(PIP) install --quiet -e '.[bench]'
	$(PY) benchmarks/bench_fk.py

clean:
	rm -rf $(VENV) out build *.egg-info src/*.egg-info
