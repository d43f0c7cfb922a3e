#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The conditional moments of `aenl moments` written with pandas and numpy, as a reference for
its speed and its numbers (tools/scripts/moments_vs_pandas.sh).

usage: moments_reference.py DATA.csv CHANNEL LAGS XMIN XMAX NODES BANDWIDTH OUT.csv [SECS]

SECS, when given, receives the seconds from reading the CSV to writing the output, the
interpreter's start and the imports left out.

The same estimator as `aenl moments --lags LAGS --grid XMIN:XMAX:NODES --bandwidth BANDWIDTH`
(direction split on, reported merged) on a record without missing samples: for every lag L and
node x_k, the triangular-kernel weighted mean and variance of X_{c+L} given X_c near x_k, with
weights 1 - |X_c - x_k| / h, over the conditioning samples c = 1 .. N - 1 - max(LAGS) (every lag
on the same samples). Written the way numpy is fast: for each node offset within the kernel, the
weights of all samples at once, summed per node by bincount; the variance in a second pass about
each node's mean.
"""
import sys
import time

import numpy as np
import pandas as pd


def main(argv):
    if len(argv) not in (9, 10):
        sys.exit(__doc__)
    t0 = time.perf_counter()
    path, channel, lags = argv[1], argv[2], [int(v) for v in argv[3].split(",")]
    x_min, x_max, nodes, h = float(argv[4]), float(argv[5]), int(argv[6]), float(argv[7])
    x = pd.read_csv(path, usecols=[channel], dtype={channel: np.float64})[channel].to_numpy()
    n = x.size
    l_max = max(lags)
    c = np.arange(1, n - l_max)  # conditioning samples (1: the direction needs X_{c-1})
    u = x[c]
    dx = (x_max - x_min) / (nodes - 1)
    t = (u - x_min) / dx
    reach = int(np.ceil(h / dx))
    base = np.floor(t).astype(np.int64)
    grid = x_min + dx * np.arange(nodes)
    grid[-1] = x_max  # as aenl places its last node
    rows = []
    for lag in lags:
        y = x[c + lag]
        sw = np.zeros(nodes)
        sw2 = np.zeros(nodes)
        swy = np.zeros(nodes)
        parts = []
        for off in range(-reach, reach + 2):
            k = base + off
            ok = (k >= 0) & (k < nodes)
            kk = k[ok]
            w = 1.0 - np.abs(grid[kk] - u[ok]) / h
            inside = w > 0.0
            kk, w, yy = kk[inside], w[inside], y[ok][inside]
            sw += np.bincount(kk, weights=w, minlength=nodes)
            sw2 += np.bincount(kk, weights=w * w, minlength=nodes)
            swy += np.bincount(kk, weights=w * yy, minlength=nodes)
            parts.append((kk, w, yy))
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = swy / sw
        m2 = np.zeros(nodes)
        for kk, w, yy in parts:
            m2 += np.bincount(kk, weights=w * (yy - mean[kk]) ** 2, minlength=nodes)
        with np.errstate(invalid="ignore", divide="ignore"):
            var = m2 / sw
            n_eff = sw * sw / sw2
            se = np.sqrt(var / n_eff)
        keep = sw > 0.0
        rows.append(pd.DataFrame({"lag": lag, "x": grid[keep], "mean": mean[keep],
                                  "var": var[keep], "n_eff": n_eff[keep], "se": se[keep]}))
    pd.concat(rows).to_csv(argv[8], index=False, float_format="%.17g")
    if len(argv) == 10:
        with open(argv[9], "w") as f:
            f.write(f"{time.perf_counter() - t0:.3f}\n")


if __name__ == "__main__":
    main(sys.argv)
