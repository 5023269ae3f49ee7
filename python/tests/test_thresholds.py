"""The paper's arithmetic through the Python adapter: weights of 1/3 reach a threshold after
exactly fifteen commands, as they do in the adapter, ``serve`` and the limit."""

from __future__ import annotations

from pathlib import Path

import trustcbr

THIRD = 0.3333333333333333


def test_fifteen_weights_of_a_third_reach_each_threshold(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("movement", tmp_path / "cases.db", seed=1)
    adapter.begin({"speed": 3.5, "padding": 0.4})
    kinds = [adapter.tell("interrupted", weight=THIRD, duration_s=10.0).kind for _ in range(15)]
    assert kinds == ["keep"] * 14 + ["switch"]
    kinds = [adapter.tell("completed", weight=THIRD, duration_s=10.0).kind for _ in range(15)]
    assert kinds == ["keep"] * 14 + ["settled"]
