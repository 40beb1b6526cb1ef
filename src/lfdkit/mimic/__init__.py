"""Mimicking: one clean generalized path from several noisy demonstrations."""
