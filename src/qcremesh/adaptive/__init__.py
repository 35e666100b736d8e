"""Layer 5: the adaptive mesh of the disk (Algorithm 2): density, landmarks, base mesh."""
