"""Layer 2: discrete operators, quality measures, point location and edits of planar
triangulations on triangle meshes."""
