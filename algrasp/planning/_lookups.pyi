"""Types of the compiled lookups read directly (algrasp/planning/_lookups.pyx; only where
algrasp.compiled.KERNELS is set). The rest are re-exported by _kernels (see _kernels.pyi)."""

from typing import Any

from algrasp.geometry.curves import FloatArray
from algrasp.planning.transfer import TransferFunction

def verify_arcs(lower: TransferFunction, upper: TransferFunction, starts: FloatArray, c0: float, c1: float, T: float,
                angles: list[float], samples: int, probe: float, want: list[float], bound: float) -> bool: ...
def __getattr__(name: str) -> Any: ...
