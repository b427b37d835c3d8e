"""The validation document reads back (issue 19): records' ``/validation`` and HTTP
responses become a typed Validation again (no Drake needed)."""

from __future__ import annotations

import json

import pytest

from algrasp.errors import PartDocumentError


def test_validation_documents_round_trip() -> None:
    from algrasp.sim.validate import Sample, Validation

    v = Validation((Sample(10.0, 70.0, 70.4, True, False, 0.0, 40.0, 40.2, True),
                    Sample(100.0, 250.0, 249.0, False, True, 0.5)), 0.5, 1.0, 1.0, "random", 3.2, 1.5,
                   {"part_mass_kg": 0.02}, push_agreement=1.0, optimised=True)
    doc = json.loads(json.dumps(v.to_dict({"action": "squeeze"})))
    back, plan_doc = Validation.from_dict(doc)
    assert back == v and plan_doc == {"action": "squeeze"}
    with pytest.raises(PartDocumentError) as err:
        Validation.from_dict({k: x for k, x in doc.items() if k != "agreement"})
    assert err.value.field == "validation.agreement"
