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

test: $(STAMP)
	$(BIN)/python -m pytest

clean:
	rm -rf $(VENV) out .pytest_cache
