"""Layer 2 — planning: transfer functions (exact and set-valued), dead bands and energy
barriers, Algorithm A′ and plans, the analysis of a part.

Imports geometry only."""
