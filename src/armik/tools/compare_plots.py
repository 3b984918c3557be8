"""The figures of ``armik compare --plot``: matplotlib (the ``plot`` extra) on the Agg
backend, never opening a window."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from armik.errors import ArmikError
from armik.tools.compare import Report


def need_matplotlib(what: str) -> None:
    """Raise ``ArmikError`` naming the plot extra when matplotlib is not installed: checked
    before a run that would otherwise end in an ImportError."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise ArmikError(
            f'{what} draws with matplotlib, which is not installed: pip install "armik[plot]"'
        ) from None


def plot(report: Report, out_dir: str | Path) -> list[Path]:
    """Write the comparison figures as PNG files into ``out_dir``; returns their paths."""
    need_matplotlib("the comparison's figures")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    # the bundled arms (the random family arms' rows are in the table only)
    keys = [k for k in report.samples if "/" in k and not k.startswith("random ")]
    paths = []

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for k in keys:
        err = report.samples[k]["pos_err"]
        err = err[np.isfinite(err)]
        if err.size:
            ax.hist(np.log10(np.maximum(err, 1e-18)), bins=40, histtype="step", label=k)
    ax.set_xlabel("log10 position error of successful solves (m)")
    ax.set_ylabel("count")
    ax.set_title("Accuracy: verified position error")
    ax.legend(fontsize=7)
    paths.append(_save(fig, out / "error_histogram.png"))

    fig, ax = plt.subplots(figsize=(8, 4.5))
    data = [report.samples[k]["time_ms"] for k in keys]
    ax.boxplot(data, showfliers=False)
    ax.set_xticks(range(1, len(keys) + 1), keys, rotation=45, ha="right", fontsize=7)
    ax.set_yscale("log")
    ax.set_ylabel("time per solve (ms), log scale")
    ax.set_title("Speed: time per solve, verification included")
    paths.append(_save(fig, out / "time_distribution.png"))

    fig, ax = plt.subplots(figsize=(8, 4.5))
    dist = report.samples["distance"]
    bins = np.linspace(-0.4, 0.8, 25)
    centers = 0.5 * (bins[1:] + bins[:-1])
    styles = {"planar2r": ("o", "-", 9), "dls": ("s", "--", 6), "qp": ("^", ":", 4)}
    for solver in ("planar2r", "dls", "qp"):
        marker, line, size = styles[solver]
        ok = report.samples[f"planar_2link/{solver}"]["success"]
        rate = [
            ok[(dist >= a) & (dist < b)].mean() * 100
            if ((dist >= a) & (dist < b)).any()
            else np.nan
            for a, b in zip(bins[:-1], bins[1:])
        ]
        ax.plot(centers, rate, marker=marker, linestyle=line, markersize=size, label=solver)
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_xlabel("signed distance to the workspace boundary (m); < 0 is unreachable")
    ax.set_ylabel("success %")
    ax.set_title("planar_2link: success versus distance to the boundary")
    ax.legend()
    paths.append(_save(fig, out / "success_vs_boundary.png"))
    return paths


def _save(fig, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    import matplotlib.pyplot as plt

    plt.close(fig)
    return path
