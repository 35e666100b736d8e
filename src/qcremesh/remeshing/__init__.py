"""Layer 6: the remeshing pipeline."""
