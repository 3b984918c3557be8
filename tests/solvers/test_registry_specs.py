"""``registry.register`` checks a ``SolverSpec``'s fields before it registers anything: a
field given wrong is a ``SolverError`` naming the field and the value, and the registry is
left as it was (a priority given as text was registered, then sorting it raised a raw
``TypeError`` at every later registration)."""

from __future__ import annotations

import pytest

import armik
from armik.solvers import registry
from armik.solvers.registry import SolverSpec

GOOD = dict(
    name="checked_spec",
    kind="analytic",
    enforces_limits=True,
    priority=10,
    why_not=lambda arm, target=None, opts=None: "never",
    run=lambda arm, target, q0, opts, every: None,
    summary="a test's spec",
)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("priority", "high"),
        ("priority", None),
        ("priority", True),
        ("kind", "closed"),
        ("enforces_limits", "yes"),
        ("why_not", None),
        ("run", "dls"),
        ("name", 3),
        ("name", ""),
        ("summary", None),
        ("solves", {"position_only"}),
        ("needs", frozenset({"spn"})),
        ("enforces", [int]),
        ("sweep", "joint 7"),
        ("parameter", "swivel"),
    ],
)
def test_a_field_given_wrong_is_refused_by_name_and_nothing_registered(field, value):
    before, generation = armik.solvers(), registry.generation
    with pytest.raises(armik.SolverError, match=rf"SolverSpec\.{field} must be .*got "):
        registry.register(SolverSpec(**{**GOOD, field: value}))
    assert armik.solvers() == before and registry.generation == generation
    # the registry still works: a good spec registers and goes
    spec = registry.register(SolverSpec(**GOOD))
    try:
        assert GOOD["name"] in armik.solvers()
    finally:
        registry.unregister(spec.name)
    assert armik.solvers() == before


def test_register_takes_a_spec():
    with pytest.raises(armik.SolverError, match="register takes a SolverSpec"):
        registry.register(GOOD)  # type: ignore[arg-type]
