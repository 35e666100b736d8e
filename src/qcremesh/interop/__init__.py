"""Layer 7, beside the command line: qcremesh on the mesh objects of the libraries users
already run (trimesh, pyvista). Each module imports its library when called, so none of
them is needed to import qcremesh."""
