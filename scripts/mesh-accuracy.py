#!/usr/bin/env python3
"""FFT d_net / psi_net / opening-angle errors of `pensight run` against a rendered dataset's truth.

    scripts/mesh-accuracy.py DATASET OUT     (OUT from `pensight run DATASET --out OUT`)
Prints frames, NaN frames, and median / p95 of |d - d_true| / d_true, |psi - psi_true| and
|angle - angle_true| (groundtruth0/mesh.csv); then how the d_net error follows the pose's
fft_quality (diagnostics.csv): Spearman's rank correlation and the error's median / p95 in each
third of the frames by quality."""
import csv
import math
import sys


def rows(path):
    with open(path) as f:
        return [r for r in csv.reader(f) if r and not r[0].startswith("#")]


def pct(v, q):
    v = sorted(v)
    return v[int(round(q * (len(v) - 1)))] if v else float("nan")


def main(dataset, out):
    truth, est = rows(f"{dataset}/groundtruth0/data.csv"), rows(f"{out}/estimates.csv")
    diag, mesh = rows(f"{out}/diagnostics.csv"), rows(f"{dataset}/groundtruth0/mesh.csv")
    d_rel, psi, angle, quality, nan, off20 = [], [], [], [], 0, 0
    for g, e, d, m in zip(truth, est, diag, mesh):
        d_true, psi_true, d_est, psi_est = float(g[7]), float(g[8]), float(e[1]), float(e[2])
        if math.isnan(d_true):
            continue
        if math.isnan(d_est):
            nan += 1
            continue
        d_rel.append(abs(d_est - d_true) / d_true)
        off20 += d_rel[-1] > 0.2
        psi.append(abs(psi_est - psi_true) * 180 / math.pi)
        angle.append(abs(float(d[5]) - float(m[2])))
        quality.append(float(d[-1]))
    print(f"{dataset}: {len(truth)} frames, {nan} NaN, {off20} off by > 20 % | "
          f"d_rel median {100 * pct(d_rel, .5):.2f} % p95 {100 * pct(d_rel, .95):.2f} % | "
          f"psi median {pct(psi, .5):.2f} p95 {pct(psi, .95):.2f} deg | "
          f"angle median {pct(angle, .5):.2f} max {pct(angle, 1):.2f} deg")
    by_quality = sorted(zip(quality, d_rel))
    thirds = [by_quality[i * len(by_quality) // 3:(i + 1) * len(by_quality) // 3] for i in range(3)]
    print(f"  fft_quality: Spearman with d_rel {spearman(quality, d_rel):+.2f} | " + " | ".join(
        f"q {t[0][0]:.2f}-{t[-1][0]:.2f}: d_rel median {100 * pct([e for _, e in t], .5):.2f} % "
        f"p95 {100 * pct([e for _, e in t], .95):.2f} %" for t in thirds if t))


def ranks(v):
    order = sorted(range(len(v)), key=lambda i: v[i])
    r = [0.0] * len(v)
    for rank, i in enumerate(order):
        r[i] = float(rank)
    return r


def spearman(a, b):
    if len(a) < 2:
        return float("nan")
    ra, rb = ranks(a), ranks(b)
    ma, mb = sum(ra) / len(ra), sum(rb) / len(rb)
    cov = sum((x - ma) * (y - mb) for x, y in zip(ra, rb))
    var = math.sqrt(sum((x - ma) ** 2 for x in ra) * sum((y - mb) ** 2 for y in rb))
    return cov / var if var else float("nan")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
