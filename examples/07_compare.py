"""The analytic-versus-numeric comparison as a script (also: armik compare --plot DIR).

The 2-link closed form against dls and qp; then the 6R closed forms (three_parallel on the
UR5, spherical on the ABB IRB 120) against dls and qp: success, accuracy, time, how often
the numeric answer is the branch nearest q0, and its distance to the nearest analytic
branch; the non-Pieper 6R route (elimination_6r on a Panda with joint 1 locked, a 6R arm no
closed form fits) against dls and qp the same way, and so the families no bundled arm belongs
to, on random arms (the general spherical wrist, three parallel axes without a wrist, and the
arms of the two one-dimensional searches, which the elimination now takes); EAIK's time as a
peer when it is installed.
"""

from _common import out_dir, pyplot

from armik.tools import compare, compare_plots

out = out_dir(__doc__)
plt = pyplot()  # the figures only: without matplotlib, the tables alone
report = compare.run(n=150)
print(report.text())
if plt is not None:
    for path in compare_plots.plot(report, out):
        print(f"wrote {path}")
