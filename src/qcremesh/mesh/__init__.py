"""Layer 1: reading and writing meshes, combinatorial topology and validation."""
