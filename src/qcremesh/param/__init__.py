"""Layer 4: parameterizations of disk-topology meshes onto the unit disk."""
