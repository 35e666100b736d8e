"""Layer 2: discrete operators, quality measures and point location on triangle meshes."""
