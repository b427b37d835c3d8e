"""Types of the compiled kernels (algrasp/planning/_kernels.pyx; read through algrasp.compiled)."""

from typing import Any

import numpy as np

from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import SupportPairFunction
from algrasp.planning.transfer import TransferFunction, TransferPiece

def classify(f: SupportPairFunction, T: float, edges: FloatArray, grid: FloatArray, band: Any, first: bool) -> tuple[
    FloatArray, np.ndarray, np.ndarray, np.ndarray, FloatArray, FloatArray, FloatArray, list[float],
    tuple[FloatArray, FloatArray] | None]: ...
def runs(x: FloatArray, T: float, R: np.ndarray, L: np.ndarray, S: np.ndarray) -> FloatArray: ...
def bound_pieces(x: FloatArray, T: float, R: np.ndarray, L: np.ndarray, S: np.ndarray, run_right: FloatArray,
                 run_left: FloatArray, cell_runs: FloatArray, barrier_right: FloatArray, barrier_left: FloatArray,
                 tol: float) -> tuple[list[tuple[float, float, float | None]], list[tuple[float, float, float | None]]] | None: ...
def canonical(pieces: list[TransferPiece], period: float, tol_rad: float) -> list[TransferPiece]: ...
def compose(outer: TransferFunction, inner: TransferFunction, tol_rad: float) -> list[TransferPiece]: ...
