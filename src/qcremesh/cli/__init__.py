"""Layer 7: the command line and the reports."""
