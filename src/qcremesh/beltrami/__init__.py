"""Layer 3: Beltrami coefficients, the linear Beltrami solver and Teichmueller maps."""
