"""Pinocchio FK of every bundled arm against yourdfpy's FK of the same URDF."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

from armik.model.catalogue import CATALOGUE

from ..conftest import ALL_ROBOTS, TOL, arm


def _yourdfpy(path):
    return yourdfpy.URDF.load(
        str(path),
        build_scene_graph=True,
        load_meshes=False,
        build_collision_scene_graph=False,
        load_collision_meshes=False,
    )


@pytest.mark.parametrize("name", ALL_ROBOTS)
def test_fk_matches_yourdfpy(name, rng):
    a = arm(name)
    spec = CATALOGUE[name]
    model = _yourdfpy(spec.urdf_path())
    offset = pin.SE3(np.eye(3), np.array(spec.tip_offset or (0.0, 0.0, 0.0)))
    for _ in range(50):
        q = a.random_q(rng)
        cfg = {j: 0.0 for j in model.actuated_joint_names}  # locked joints at neutral
        cfg.update(dict(zip(a.joint_names, q)))
        model.update_cfg(cfg)
        T_ref = pin.SE3(model.get_transform(frame_to=a.tip, frame_from=a.base)) * offset
        T = a.fk(q)
        assert np.linalg.norm(T.translation - T_ref.translation) < TOL["fk_exact"]
        assert np.linalg.norm(pin.log3(T.rotation.T @ T_ref.rotation)) < TOL["fk_exact"]
