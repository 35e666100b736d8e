# The two commands of the README: `make demo` and `make test`. Both set up .venv first.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --disable-pip-version-check -e ".[test,plot,progress]"
	@# Optional faster sparse solver (MKL PARDISO); scipy's SuperLU is used without it.
	-$(BIN)/pip install --quiet --disable-pip-version-check -e ".[fast]"
	touch $(STAMP)

demo: $(STAMP)
	mkdir -p out
	$(BIN)/qcremesh param data/human_face.obj -o out/human_face_disk.obj --plot out/human_face_disk.png
	$(BIN)/qcremesh remesh data/human_face.obj -o out/human_face_remeshed.obj --report out/report

test: $(STAMP)
	$(BIN)/python -m pytest

clean:
	rm -rf $(VENV) out .pytest_cache

# Side-by-side benchmarks (benchmarks/README.md). Competitor tools go into their own venv so
# they never reach the test venv. `make bench ARGS=--quick` or `make bench-quick` for the
# two-mesh smoke run; ARGS passes any option of benchmarks/run.py.
BENCH_VENV := .venv-bench
BENCH_STAMP := $(BENCH_VENV)/.installed
ARGS ?=

.PHONY: bench bench-quick

$(BENCH_STAMP): pyproject.toml
	$(PYTHON) -m venv $(BENCH_VENV)
	$(BENCH_VENV)/bin/pip install --quiet --disable-pip-version-check -e ".[bench]"
	-$(BENCH_VENV)/bin/pip install --quiet --disable-pip-version-check -e ".[fast]"
	touch $(BENCH_STAMP)

bench: $(BENCH_STAMP)
	$(BENCH_VENV)/bin/python benchmarks/run.py $(ARGS)

bench-quick: $(BENCH_STAMP)
	$(BENCH_VENV)/bin/python benchmarks/run.py --quick $(ARGS)
