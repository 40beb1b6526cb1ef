"""Data sets: seeded synthetic generators with known ground truth, and loaders."""
