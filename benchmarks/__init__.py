"""Benchmarks and peer comparisons (not part of the installed package)."""
