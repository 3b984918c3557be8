"""Random inputs at the doors (targets, options, limits, load arguments): each is either
accepted or refused with an ``ArmikError``; nothing else escapes."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pinocchio as pin
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import armik
from armik.errors import ArmikError
from armik.options import Options
from armik.targets.pose import Target, parse_target

from ..conftest import arm, model

FLOATS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e-300, 1e154, 1e200, 1e308, -1e308, 0.5, 1.0]),
)
SCALARS = st.one_of(
    FLOATS,
    st.integers(-(10**20), 10**20),
    st.booleans(),
    st.text(max_size=4),
    st.complex_numbers(max_magnitude=1e3),
    st.none(),
)
SHAPES = st.sampled_from([(), (2,), (3,), (4,), (6,), (7,), (3, 3), (4, 4), (2, 4, 4), (1, 3)])


@st.composite
def arrays(draw):
    shape = draw(SHAPES)
    n = int(np.prod(shape)) if shape else 1
    values = draw(st.lists(FLOATS, min_size=n, max_size=n))
    return np.array(values, dtype=float).reshape(shape)


@st.composite
def targets(draw):
    kind = draw(st.integers(0, 4))
    if kind == 0:
        return draw(arrays())
    if kind == 1:
        return (draw(arrays()), draw(arrays()))
    if kind == 2:
        return [draw(SCALARS) for _ in range(draw(st.integers(0, 8)))]
    if kind == 3:
        return (draw(st.lists(SCALARS, max_size=4)), draw(st.lists(SCALARS, max_size=5)))
    return draw(SCALARS)


QUICK = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@QUICK
@given(targets())
def test_parse_target_accepts_or_refuses(value):
    try:
        t = parse_target(value, model("planar_2link"))
    except ArmikError:
        return
    assert isinstance(t, Target) and t.position.shape == (3,)
    assert np.isfinite(t.position).all() and np.abs(t.position).max() <= 1e6
    if t.rotation is not None:
        R = t.rotation
        assert np.abs(R.T @ R - np.eye(3)).max() < 1e-9 and np.linalg.det(R) > 0


OPTION_VALUES = st.one_of(SCALARS, st.lists(SCALARS, max_size=7), st.tuples(FLOATS, FLOATS))


@QUICK
@given(st.dictionaries(st.sampled_from(sorted(Options.__dataclass_fields__)), OPTION_VALUES))
def test_options_accept_or_refuse(kwargs):
    try:
        opts = Options.from_kwargs(kwargs)
    except ArmikError:
        return
    assert isinstance(opts.position_only, bool)
    if opts.weights is not None:
        w = np.array(opts.weights)
        assert np.isfinite(w).all() and (w >= 0).all() and (w <= 1e6).all() and w.any()
    for key in ("tol_position", "tol_orientation", "timeout"):
        assert getattr(opts, key) > 0


@QUICK
@given(
    st.sampled_from(["shoulder_pan_joint", "elbow_joint", "nope", 3]),
    st.one_of(st.tuples(SCALARS, SCALARS), SCALARS, st.lists(SCALARS, max_size=3)),
)
def test_with_limits_accepts_or_refuses(name, pair):
    try:
        a = arm("ur5").with_limits({name: pair})
    except ArmikError:
        return
    assert (a.lower <= a.upper).all() and not np.isnan(a.lower).any()
    assert np.isfinite(a.random_q(0)).all()


@settings(max_examples=60, deadline=None)
@given(
    st.one_of(st.none(), SCALARS, st.lists(SCALARS, max_size=4)),
    st.one_of(st.none(), SCALARS, st.dictionaries(SCALARS, SCALARS, max_size=2)),
)
def test_load_arguments_accept_or_refuse(tip_offset, locked):
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            a = armik.load("panda", tip_offset=tip_offset, locked=locked)
    except ArmikError:
        return
    assert isinstance(a.fk(a.middle), pin.SE3)


def test_one_sided_limits_sample_beside_the_limit():
    """The example the fuzzing above once drew: (-inf, -4) sampled [-4 - 2 pi, -4]."""
    for pair, (lo, hi) in {(-math.inf, -4.0): (-4.0 - 2 * math.pi, -4.0),
                           (4.0, math.inf): (4.0, 4.0 + 2 * math.pi)}.items():  # fmt: skip
        a = arm("ur5").with_limits({"shoulder_pan_joint": pair})
        q = a.random_q(0, n=200)[:, 0]
        assert (q >= lo).all() and (q <= hi).all() and q.max() - q.min() > 5.0
