"""Transfer functions (algrasp/planning/transfer.py): the plain-float evaluation gives
the vectorised one's values bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from algrasp.pipeline import WARM_UP_PART
from algrasp.planning.analysis import ROBUST, analyse_document
from algrasp.planning.transfer import TransferFunction, TransferPiece
from algrasp.testing import shapes


def _functions() -> list[TransferFunction]:
    out = [TransferFunction(np.pi, (TransferPiece(0.0, np.pi, None),)),  # the identity
           TransferFunction(np.pi, (TransferPiece(0.0, 1.0, 0.5), TransferPiece(1.0, np.pi, None)))]
    for doc in (WARM_UP_PART, shapes.rectangle(3.0, 1.0), shapes.pie(5.0, 20.0)):
        a = analyse_document(doc, ROBUST)
        assert a.robust is not None
        out += [a.squeeze, a.push, a.push_grasp]
        out += [F for S in (a.robust.squeeze, a.robust.push, a.robust.push_grasp) if S is not None
                for F in (S.lower, S.upper)]
    return out


@pytest.mark.parametrize("F", _functions())
def test_apply_floats_is_apply_bit_for_bit(F: TransferFunction) -> None:
    """Random θ over several periods, every piece start lifted by −3 … 3 periods and the
    floats either side of each (where rounding decides the piece), and ±0.0."""
    rng = np.random.default_rng(7)
    starts = np.array([p.start for p in F.pieces])
    lifted = (starts[None, :] + F.period * np.arange(-3, 4)[:, None]).ravel()
    x = np.concatenate([rng.uniform(-4.0 * F.period, 4.0 * F.period, 500), lifted, [0.0, -0.0]])
    x = np.concatenate([x, np.nextafter(x, np.inf), np.nextafter(x, -np.inf)])
    assert np.array(F.apply_floats(x.tolist())).tobytes() == F.apply(x).tobytes()


@pytest.mark.parametrize("F", _functions())
def test_values_at_few_is_values_at_many_bit_for_bit(F: TransferFunction) -> None:
    """A few θ at a time (plain floats) give the values of one vectorised pass over all."""
    rng = np.random.default_rng(11)
    starts = np.array([p.start for p in F.pieces])
    lifted = (starts[None, :] + F.period * np.arange(-3, 4)[:, None]).ravel()
    x = np.concatenate([rng.uniform(-4.0 * F.period, 4.0 * F.period, 200), lifted, [0.0, -0.0]])
    x = np.concatenate([x, np.nextafter(x, np.inf), np.nextafter(x, -np.inf)]).tolist()
    few = [v for i in range(0, len(x), 8) for v in F.values_at(x[i:i + 8])]
    assert np.array(few).tobytes() == np.array(F.values_at(x)).tobytes()
