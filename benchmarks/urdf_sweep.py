"""Load every URDF example-robot-data installs, with each leaf (up to 4) as the tip, and
solve one reachable target on each: counts of loads that solve, armik errors, and raw
exceptions (which should be zero). Usage: python benchmarks/urdf_sweep.py [OUT.json]"""

from __future__ import annotations

import json
import os
import sys
import warnings
from collections import Counter

import pinocchio as pin

import armik
from armik.model.catalogue import _erd_robot_dir

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

warnings.simplefilter("ignore")
root = _erd_robot_dir()
out = {}
for path in sorted([*root.glob("*/urdf/*.urdf"), *root.glob("*/robots/*.urdf")]):
    try:
        model = pin.buildModelFromUrdf(str(path))
    except Exception:  # files Pinocchio itself cannot read are not armik's to judge
        continue
    parents = {f.parentFrame for f in model.frames}
    leaves = [
        model.frames[i].name
        for i in range(1, model.nframes)
        if i not in parents and model.frames[i].type == pin.BODY
    ][:4]
    for tip in leaves:
        key = f"{path.relative_to(root)}:{tip}"
        try:
            arm = armik.load(path, tip=tip)
            r = arm.solve(arm.fk(arm.random_q(0)), timeout=0.05)
            out[key] = f"ok {arm.dof} {r.success}"
        except armik.ArmikError as exc:
            out[key] = f"ERR {type(exc).__name__} {str(exc)[:80]}"
        except Exception as exc:
            out[key] = f"RAW {type(exc).__name__} {str(exc)[:80]}"
kinds = Counter(v.split()[0] + (" solved" if v.endswith("True") else "") for v in out.values())
print(f"{len(out)} loads: {dict(kinds)}")
if len(sys.argv) > 1:
    with open(sys.argv[1], "w") as f:
        json.dump(out, f, indent=0)
