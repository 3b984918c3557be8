"""Does Pinocchio's URDF parser survive a serial chain N links deep on a thread with a
given stack? Run in a subprocess (a crash is a segmentation fault):
python benchmarks/urdf_parser_depth.py N STACK_KB [revolute|fixed]
Measured here: 8 MB stack, 3000 links fine, 4000 crash; 512 kB stack, 200 fine, 300 crash."""

import os
import sys
import threading

import pinocchio as pin

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

n, kb = int(sys.argv[1]), int(sys.argv[2])
joint_type = sys.argv[3] if len(sys.argv) > 3 else "revolute"
limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>' if joint_type != "fixed" else ""
parts = ['<robot name="deep">', '<link name="l0"/>']
for i in range(1, n + 1):
    parts.append(
        f'<link name="l{i}"/><joint name="j{i}" type="{joint_type}"><parent link="l{i - 1}"/>'
        f'<child link="l{i}"/><origin xyz="0 0 0.01"/><axis xyz="0 0 1"/>{limit}</joint>'
    )
parts.append("</robot>")
threading.stack_size(kb * 1024)
t = threading.Thread(target=lambda: print("ok", pin.buildModelFromXML("".join(parts)).nframes))
t.start()
t.join()
