"""The error model and the fits: log-log slopes, the reference's noise floor, and
MSE(spp) = a / spp + b with time(spp) = c0 + c1 spp for equal-time comparisons."""

import math

import numpy as np


def loglog_fit(x, y):
    """Least-squares line through (log x, log y): (slope, intercept). NaN with < 2 points."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = (x > 0) & (y > 0)
    if ok.sum() < 2:
        return float("nan"), float("nan")
    slope, icpt = np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)
    return float(slope), float(icpt)


def nonneg_fit(f0, f1, y):
    """Least squares y = c0 f0 + c1 f1 with c0, c1 >= 0 (two columns: try both, each alone)."""
    cols = np.stack([np.asarray(f0, float), np.asarray(f1, float)], axis=1)
    y = np.asarray(y, float)
    best = (float("inf"), 0.0, 0.0)
    for use in ((0, 1), (0,), (1,)):
        sol, *_ = np.linalg.lstsq(cols[:, use], y, rcond=None)
        if np.any(sol < 0):
            continue
        coef = np.zeros(2)
        coef[list(use)] = sol
        resid = float(np.sum((cols @ coef - y) ** 2))
        if resid < best[0]:
            best = (resid, float(coef[0]), float(coef[1]))
    return best[1], best[2]


def reference_floor(spp, rmse, ref_spp):
    """The RMSE a reference of ref_spp samples adds by its own noise (independent seeds).
    With the same per-sample variance a in render and reference, MSE(spp) = a/spp + a/R:
    fit a by least squares and return sqrt(a / R)."""
    spp, rmse = np.asarray(spp, float), np.asarray(rmse, float)
    x = 1.0 / spp + 1.0 / ref_spp
    var = float(np.sum(rmse ** 2 * x) / np.sum(x * x))
    return math.sqrt(var / ref_spp)


def without_floor(rmse, floor):
    """RMSE with a constant floor taken out in quadrature."""
    return np.sqrt(np.maximum(np.asarray(rmse, float) ** 2 - floor ** 2, 1e-300))


class ErrorModel:
    """MSE(spp) = a / spp + b and time(spp) = c0 + c1 spp, fitted to one setting's renders.
    a is its Monte Carlo noise; b what more samples do not remove (bias against the reference,
    the reference's own noise); c0 the fixed cost of a render (wavefront iterations that are
    not full), c1 the cost of a sample. Fitting error against spp and converting through
    the time model keeps a/t from being bent by c0. Residuals are relative (weights 1/MSE):
    otherwise the noisiest, lowest-spp point decides b. With `floor` given, b is that."""

    def __init__(self, spp, seconds, mse, floor=None):
        spp, seconds, mse = (np.asarray(v, float) for v in (spp, seconds, mse))
        w = 1.0 / mse
        if floor is None:
            self.a, self.b = nonneg_fit(w / spp, w, w * mse)
        else:
            x = w / spp
            self.a, self.b = max(0.0, float(np.sum(x * w * (mse - floor)) / np.sum(x * x))), floor
        self.c1, self.c0 = nonneg_fit(spp, np.ones_like(spp), seconds)
        if self.c1 <= 0:  # all points at one spp: cost per sample from the mean
            self.c0, self.c1 = 0.0, float(np.mean(seconds / spp))

    def rmse_at_time(self, t):
        spp = max(t - self.c0, 1e-9) / self.c1
        return math.sqrt(self.a / spp + self.b)

    def time_to_rmse(self, e):
        """Seconds to reach RMSE e; inf when the floor b alone is above it."""
        if e * e <= self.b * 1.0001 or self.a <= 0:
            return math.inf
        return self.c0 + self.c1 * self.a / (e * e - self.b)


def shared_floor(groups):
    """b in MSE_ij = a_i / spp_ij + b, fitted jointly over settings that converge to the same
    image as the reference (groups = [(spp, mse)]): their only floor is the reference's own
    noise, common to all, and many points pin it down where one setting's three cannot.
    Relative residuals, as in ErrorModel."""
    rows = []
    for i, (spp, mse) in enumerate(groups):
        for s, m in zip(spp, mse):
            row = np.zeros(len(groups) + 1)
            row[i], row[-1] = 1.0 / (s * m), 1.0 / m
            rows.append(row)
    sol, *_ = np.linalg.lstsq(np.array(rows), np.ones(len(rows)), rcond=None)
    return max(0.0, float(sol[-1]))
