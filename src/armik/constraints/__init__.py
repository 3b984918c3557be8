"""What an answer must satisfy besides the pose: obstacles (``shapes``) and collisions
(``collision``). Joint limits, the first constraint, live with the arm model and kernels."""
