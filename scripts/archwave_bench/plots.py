"""The suite's plots: rows of log-log panels."""

import math

import matplotlib

matplotlib.use("Agg")  # no display on the machines this runs on
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def _series(ax, i, label, x, y, slope, icpt):
    color = f"C{i}"
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = (x > 0) & (y > 0)
    if not ok.any():
        return
    fit_txt = f", slope {slope:.2f}" if math.isfinite(slope) else ""
    ax.loglog(x[ok], y[ok], "o-", color=color, ms=4, lw=1, label=f"{label}{fit_txt}")
    if math.isfinite(slope):
        xs = np.array([x[ok].min(), x[ok].max()])
        ax.loglog(xs, np.exp(icpt) * xs ** slope, "--", color=color, lw=0.8)


def _guide(ax, series, slope):
    """The expected slope as a dotted line through the first series' first point."""
    x0, y0 = float(series[0][1][0]), float(series[0][2][0])
    xs = np.array([x0, max(float(np.max(s[1])) for s in series)])
    ax.loglog(xs, y0 * (xs / x0) ** slope, ":", color="gray", label=f"slope {slope}")


def loglog_figure(path, panels, title):
    """One row of log-log panels. panel = (xlabel, ylabel, [(label, x, y, slope, icpt)],
    guide_slope or None): points, their fitted line, and the expected slope as a dotted guide
    through the first series' first point."""
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.0), squeeze=False)
    for ax, (xlabel, ylabel, series, guide) in zip(axes[0], panels):
        for i, s in enumerate(series):
            _series(ax, i, *s)
        if guide is not None and series and len(series[0][1]):
            _guide(ax, series, guide)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
