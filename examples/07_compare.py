"""The analytic-versus-numeric comparison as a script (also: armik compare --plot DIR)."""

from _common import out_dir

from armik import compare

out = out_dir(__doc__)
report = compare.run(n=150)
print(report.text())
for path in compare.plot(report, out):
    print(f"wrote {path}")
