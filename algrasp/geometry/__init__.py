"""Layer 1 — geometry: exact curves and segments, the part model and its document
parser, moments, the exact convex hull, diameter and radius functions, tolerances.

Imports nothing from the layers above (planning, io, sim, the CLI)."""
