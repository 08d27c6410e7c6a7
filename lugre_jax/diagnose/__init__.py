"""Diagnose model-reality mismatch: locate residual structure, name missing physics, refit."""
