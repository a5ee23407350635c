#!/usr/bin/env python3
"""Plots `tessera bench` JSON lines: one PNG per scenario, GPU median time per technique/path
against image size (one panel per dataset). Usage: plot_bench.py OUT_DIR FILE.jsonl..."""
import collections
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    out, files = sys.argv[1], sys.argv[2:]
    by_scenario = collections.defaultdict(list)
    for name in files:
        with open(name) as f:
            for line in f:
                r = json.loads(line)
                by_scenario[r["scenario"]].append(r)
    for scenario, records in by_scenario.items():
        datasets = sorted({r["dataset"] for r in records})
        fig, axes = plt.subplots(1, len(datasets), figsize=(5 * len(datasets), 4), squeeze=False)
        for ax, dataset in zip(axes[0], datasets):
            series = collections.defaultdict(dict)
            for r in records:
                if r["dataset"] != dataset:
                    continue
                size = f'{r["width"]}x{r["height"]}'
                # Last stage = the rendering stage (time-varying frames also upload and build).
                stage = r["stages"][-1]
                series[f'{r["technique"]} ({r["path"]}) {stage["stage"]}'][size] = stage["median_ms"]
            for label, points in sorted(series.items()):
                sizes = list(points)
                ax.plot(sizes, [points[s] for s in sizes], marker="o", label=label)
            ax.set_yscale("log")
            ax.set_title(dataset, fontsize=9)
            ax.set_ylabel("GPU ms (median)")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
        device = records[0]["device"]
        fig.suptitle(f"{scenario} — {device}")
        fig.tight_layout()
        fig.savefig(f"{out}/{scenario}.png", dpi=90)
        plt.close(fig)


if __name__ == "__main__":
    main()
