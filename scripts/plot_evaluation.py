#!/usr/bin/python3
"""Plots what risas_evaluate wrote into DIR (curves.csv, summary.csv, scale.csv):
  pr_<scene>_<sequence>.png  precision-recall curves, one per method, as the paper's figures
  scale_<scene>.png          correct-match percentage at ratio 0.8 against the scale step
  pose_<scene>.png           pose recovered within 5 deg / 5 cm per sequence and method (bars),
                             2 deg / 2 cm hatched inside them
  study.png                  mean PR-AUC of each RISAS variant (parameter studies)
Usage: plot_evaluation.py DIR"""
import csv
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main(out):
    out = Path(out)
    auc = {(r["scene"], r["sequence"], r["method"]): float(r["mean_pr_auc"]) for r in rows(out / "summary.csv")}
    methods = list(dict.fromkeys(r["method"] for r in rows(out / "pairs.csv")))  # in the order they ran

    curves = defaultdict(lambda: defaultdict(lambda: ([], [])))
    for r in rows(out / "curves.csv"):
        recall, precision = curves[(r["scene"], r["sequence"])][r["method"]]
        recall.append(float(r["recall"]))
        precision.append(float(r["precision"]))
    for (scene, sequence), by_method in curves.items():
        fig, ax = plt.subplots(figsize=(5.2, 4.2))
        for method in methods:
            if method in by_method:
                recall, precision = by_method[method]
                ax.plot(recall, precision, label=f"{method} ({auc[(scene, sequence, method)]:.2f})")
        ax.set(xlabel="recall", ylabel="precision", xlim=(0, 1), ylim=(0, 1.02),
               title=f"{scene} / {sequence} (mean PR-AUC)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="lower left")
        fig.tight_layout()
        fig.savefig(out / f"pr_{scene}_{sequence}.png", dpi=110)
        plt.close(fig)

    scale = defaultdict(lambda: defaultdict(list))
    for r in rows(out / "scale.csv"):
        scale[r["scene"]][r["method"]].append((int(r["step"]), float(r["correct_percentage"])))
    for scene, by_method in scale.items():
        fig, ax = plt.subplots(figsize=(5.2, 4.2))
        for method in methods:
            if method in by_method:
                steps, percent = zip(*sorted(by_method[method]))
                ax.plot([0.1 * (s - 1) for s in steps], percent, marker="o", label=method)
        ax.set(xlabel="camera moved back from frame 1 (m)", ylabel="correct matches at ratio 0.8 (%)",
               ylim=(0, 102), title=f"{scene} / scale")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / f"scale_{scene}.png", dpi=110)
        plt.close(fig)

    success = defaultdict(dict)
    for r in rows(out / "summary.csv"):
        if "success_5deg_5cm" in r:
            success[r["scene"]][(r["sequence"], r["method"])] = (float(r["success_5deg_5cm"]),
                                                                 float(r["success_2deg_2cm"]))
    for scene, by_key in success.items():
        sequences = list(dict.fromkeys(q for q, _ in by_key))
        present = [m for m in methods if any((q, m) in by_key for q in sequences)]
        width = 0.8 / max(1, len(present))
        fig, ax = plt.subplots(figsize=(max(5.2, 1.3 * len(sequences) + 2), 4.2))
        for k, method in enumerate(present):
            xs = [i + (k - (len(present) - 1) / 2) * width for i in range(len(sequences))]
            loose = [100 * by_key.get((q, method), (0, 0))[0] for q in sequences]
            tight = [100 * by_key.get((q, method), (0, 0))[1] for q in sequences]
            bars = ax.bar(xs, loose, width, label=method)
            ax.bar(xs, tight, width * 0.6, color=bars[0].get_facecolor(), hatch="///", edgecolor="white")
        ax.set_xticks(range(len(sequences)), sequences)
        ax.set(ylabel="pairs with the pose recovered (%)", ylim=(0, 105),
               title=f"{scene}: pose within 5 deg / 5 cm (hatched: 2 deg / 2 cm)")
        ax.title.set_fontsize(9)
        ax.grid(alpha=0.3, axis="y")
        ax.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        fig.savefig(out / f"pose_{scene}.png", dpi=110)
        plt.close(fig)

    variants = [m for m in methods if m.startswith("RISAS(")]
    if variants:
        means = [sum(v for (s, q, m), v in auc.items() if m == method) /
                 max(1, sum(1 for (s, q, m) in auc if m == method)) for method in variants]
        fig, ax = plt.subplots(figsize=(max(5.0, 0.6 * len(variants)), 4.0))
        ax.bar(range(len(variants)), means)
        ax.set_xticks(range(len(variants)), variants, rotation=60, ha="right", fontsize=7)
        ax.set(ylabel="mean PR-AUC over the sequences", title="parameter study")
        fig.tight_layout()
        fig.savefig(out / "study.png", dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
