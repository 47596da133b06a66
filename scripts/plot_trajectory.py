#!/usr/bin/python3
"""Plots trajectories in the TUM format ("timestamp tx ty tz qx qy qz qw")
against the ground truth: a top view (x-z, the camera's optical frame has y
down) and x, y, z over time. Each estimate is first aligned to the ground
truth by the least-squares rigid motion (Horn/Umeyama, no scale) on the
poses associated by nearest stamp within 0.02 s, as the ATE is computed.
Usage: plot_trajectory.py GROUNDTRUTH.txt EST.txt[=LABEL] [...] --out P.png"""
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                rows.append([float(v) for v in line.split()[:4]])
    return np.array(rows)


def associate(est, gt, max_difference=0.02):
    pairs = []
    for i, t in enumerate(est[:, 0]):
        j = int(np.argmin(np.abs(gt[:, 0] - t)))
        if abs(gt[j, 0] - t) < max_difference:
            pairs.append((i, j))
    return pairs


def align(source, target):
    """R, t minimising |R source + t - target|^2 (Umeyama, no scale)."""
    mu_s, mu_t = source.mean(0), target.mean(0)
    u, _, vt = np.linalg.svd((target - mu_t).T @ (source - mu_s))
    s = np.diag([1, 1, np.sign(np.linalg.det(u @ vt))])
    r = u @ s @ vt
    return r, mu_t - r @ mu_s


def main(args):
    if "--out" not in args or len(args) < 4:
        sys.exit(__doc__)
    out = args[args.index("--out") + 1]
    files = [a for k, a in enumerate(args) if a != "--out" and (k == 0 or args[k - 1] != "--out")]
    gt = read(files[0])
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), gridspec_kw={"width_ratios": [1, 1.3]})
    t0 = None
    estimates = []
    for spec in files[1:]:
        path, _, label = spec.partition("=")
        est = read(path)
        pairs = associate(est, gt)
        if len(pairs) < 3:
            sys.exit(f"{path}: fewer than 3 poses near ground-truth stamps")
        i, j = map(list, zip(*pairs))
        r, t = align(est[i, 1:4], gt[j, 1:4])
        estimates.append((label or path, est[:, 0], est[:, 1:4] @ r.T + t))
        t0 = est[0, 0] if t0 is None else min(t0, est[0, 0])
    span = (min(e[1][0] for e in estimates), max(e[1][-1] for e in estimates))
    near = (gt[:, 0] >= span[0] - 0.05) & (gt[:, 0] <= span[1] + 0.05)
    gt = gt[near]
    axes[0].plot(gt[:, 1], gt[:, 3], "k-", lw=2, label="ground truth")
    for label, _, p in estimates:
        axes[0].plot(p[:, 0], p[:, 2], "-", marker=".", ms=3, label=label)
    axes[0].set(xlabel="x (m)", ylabel="z (m)", title="top view (aligned)")
    axes[0].axis("equal")
    axes[0].grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    for axis, name in enumerate("xyz"):
        line, = axes[1].plot(gt[:, 0] - t0, gt[:, 1 + axis], "-", lw=2, label=f"{name} truth")
        for label, stamps, p in estimates:
            axes[1].plot(stamps - t0, p[:, axis], "--", color=line.get_color(), alpha=0.8, label=f"{name} {label}")
    axes[1].set(xlabel="time (s)", ylabel="position (m)", title="per axis")
    axes[1].grid(alpha=0.3)
    axes[1].legend(fontsize=7, ncol=3)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1:])
