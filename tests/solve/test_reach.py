"""Reachability maps: the fraction per voxel is the success rate of its orientations."""

from __future__ import annotations

import numpy as np
import pytest

from armik.errors import InputError, OptionError
from armik.solve.reach import ReachMap, grid, reachability

from ..conftest import arm, model


def test_planar_arm_map_matches_its_annulus(tmp_path):
    # The 2-link arm (l1 = 1.0, l2 = 0.8) on position targets reaches the annulus
    # 0.2 <= r <= 1.8 in its plane (z = 0) and nothing off it.
    a = arm("planar_2link")
    m = reachability(a, resolution=0.3, orientations=1, workers=1, position_only=True)
    X, Y, Z = np.meshgrid(m.xs, m.ys, m.zs, indexing="ij")
    r = np.hypot(X, Y)
    sampled = np.isfinite(m.fraction)
    on_plane = np.isclose(Z, 0.0) & sampled
    assert (m.fraction[on_plane & (r > 0.25) & (r < 1.75)] == 1).all()
    assert (m.fraction[on_plane & (r > 1.85)] == 0).all()
    assert (m.fraction[sampled & ~np.isclose(Z, 0.0)] == 0).all()
    back = ReachMap.load(m.save(tmp_path / "m.npz"))
    np.testing.assert_array_equal(back.fraction, m.fraction)
    assert back.arm == "planar_2link" and back.solves == m.solves == int(sampled.sum())


def test_fraction_is_the_mean_of_orientation_successes():
    a = arm("ur5")
    m = reachability(a, resolution=0.5, orientations=3, workers=1, timeout=0.002, seed=1)
    f = m.fraction[np.isfinite(m.fraction)]
    assert set(np.round(f * 3).astype(int)) <= {0, 1, 2, 3}
    assert (f > 0).any() and (f == 0).any()


def test_grid_covers_the_reach_ball():
    a = model("panda")
    xs, ys, zs, inside = grid(a, 0.2)
    o = a.first_joint_origin
    assert xs[0] <= o[0] - a.reach and xs[-1] >= o[0] + a.reach
    assert inside.sum() < inside.size


def test_bad_arguments():
    a = arm("ur5")
    with pytest.raises(OptionError, match="resolution"):
        reachability(a, resolution=0)
    with pytest.raises(OptionError, match="got 'fine'"):  # the value given, not nan
        reachability(a, resolution="fine")
    with pytest.raises(OptionError, match="orientations"):
        reachability(a, orientations=0)
    with pytest.raises(OptionError, match="too many solves"):
        reachability(a, resolution=0.001)
    with pytest.raises(OptionError, match="too many solves"):  # not an OverflowError
        reachability(a, resolution=1e-300)
    with pytest.raises(InputError, match="not a reachability map"):
        ReachMap.load(__file__)
    # numpy's own ValueError before: the CLI's words for a --seed out of range
    for seed in (-1, 2**32, 1.5, True):
        with pytest.raises(OptionError, match=r"seed must be a whole number in \[0, 4294967295\]"):
            reachability(a, resolution=0.5, orientations=2, seed=seed)


def test_an_arm_of_fewer_than_6_joints_maps_positions(tmp_path):
    """Sampled tool orientations over SO(3) are out of a 2-joint arm's reach: its map was 0
    everywhere although solve reaches its plane; it is a map of positions, and says so."""
    a = arm("planar_2link")
    m = reachability(a, resolution=0.3, orientations=4, workers=1)
    assert m.position_only and m.solves == int(np.isfinite(m.fraction).sum())
    X, Y, Z = np.meshgrid(m.xs, m.ys, m.zs, indexing="ij")
    on_plane = np.isclose(Z, 0.0) & np.isfinite(m.fraction)
    r = np.hypot(X, Y)
    assert (m.fraction[on_plane & (r > 0.25) & (r < 1.75)] == 1).all()
    assert "positions only" in m.summary() and "fewer than 6 joints" in m.summary()
    back = ReachMap.load(m.save(tmp_path / "m.npz"))
    assert back.position_only and "positions only" in back.summary()
    assert not reachability(arm("ur5"), resolution=0.5, orientations=1, timeout=0.001).position_only


def test_a_robot_of_several_tips_is_mapped_chain_by_chain():
    """An ``armik.Arms`` has no one tip to map: refused naming ``robot.chain(tip)``, not
    as if it were no arm of ``armik.load``'s."""
    import armik

    from ..test_arms import dual_irb120

    robot = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    with pytest.raises(InputError, match=r"robot\.chain\(tip\)"):
        reachability(robot, resolution=0.5, orientations=1)


def test_a_plot_names_the_file_it_writes_and_refuses_a_kind_matplotlib_lacks(tmp_path):
    pytest.importorskip("matplotlib", reason="the plot extra (matplotlib) is not installed")
    m = reachability(arm("planar_2link"), 0.6, 1)
    written = m.plot(tmp_path / "map")
    assert written == tmp_path / "map.png" and written.is_file()
    with pytest.raises(InputError, match=r"no \.xyz file.*\.png"):
        m.plot(tmp_path / "map.xyz")
    assert not (tmp_path / "map.xyz").exists()
