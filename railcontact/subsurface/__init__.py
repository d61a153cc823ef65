"""Subsurface stresses of the elastic half-space under solved contact patches."""
