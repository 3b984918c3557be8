"""Verification: measuring an answer against Pinocchio (``measure``), the verdict
(``verdict``) and every reason text (``reasons``)."""
