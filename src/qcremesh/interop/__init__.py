"""Layer 7, beside the command line: qcremesh on the mesh objects of the libraries users
already run (meshio, trimesh, pyvista). Each module imports its library when called, so none of
them is needed to import qcremesh."""

import importlib


def require(name):
    """The module ``name``, or an ImportError saying how to install it."""
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise ImportError(f"qcremesh.interop.{name} needs {name}: pip install {name}") from exc
