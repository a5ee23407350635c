#!/usr/bin/env python3
"""Plots `tessera bench` JSON lines: one PNG per scenario, GPU median time per technique/path
against image size (one panel per dataset); the `growth` scenario as two PNGs, frame time
against pixels and against data size (one panel per family of data, log-log).
Usage: plot_bench.py OUT_DIR FILE.jsonl..."""
import collections
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


UNITS = ("voxels", "tets", "glyphs")


def frame_ms(r):
    """The whole frame: its span where a frame has several stages (their sum in records made
    before spans were), else its one stage."""
    stages = {s["stage"]: s["median_ms"] for s in r["stages"]}
    return stages.get("frame-span", stages.get("frame", r["stages"][-1]["median_ms"]))


def plot_growth(out, records):
    for ladder, x_name in (("pixels", "pixels"), ("data", None)):
        chosen = [r for r in records if r.get("variant") == ladder]
        units = [u for u in UNITS if any(u in r["counts"] for r in chosen)]
        if not units:
            continue
        fig, axes = plt.subplots(1, len(units), figsize=(5 * len(units), 4), squeeze=False)
        for ax, unit in zip(axes[0], units):
            series = collections.defaultdict(dict)
            for r in chosen:
                if unit not in r["counts"]:
                    continue
                x = r["counts"][x_name or unit]
                series[f'{r["technique"]} ({r["path"]})'][x] = frame_ms(r)
            for label, points in sorted(series.items()):
                xs = sorted(points)
                ax.plot(xs, [points[x] for x in xs], marker="o", label=label)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel(x_name or unit)
            ax.set_ylabel("GPU ms per frame (median)")
            ax.set_title(unit if x_name else f"at {chosen[0]['width']}x{chosen[0]['height']}",
                         fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
        fig.suptitle(f"growth against {x_name or 'data size'} — {chosen[0]['device']}")
        fig.tight_layout()
        fig.savefig(f"{out}/growth-{ladder}.png", dpi=90)
        plt.close(fig)


def main():
    out, files = sys.argv[1], sys.argv[2:]
    by_scenario = collections.defaultdict(list)
    for name in files:
        with open(name) as f:
            for line in f:
                r = json.loads(line)
                by_scenario[r["scenario"]].append(r)
    for scenario, records in by_scenario.items():
        if scenario == "growth":
            plot_growth(out, records)
            continue
        datasets = sorted({r["dataset"] for r in records})
        fig, axes = plt.subplots(1, len(datasets), figsize=(5 * len(datasets), 4), squeeze=False)
        for ax, dataset in zip(axes[0], datasets):
            series = collections.defaultdict(dict)
            for r in records:
                if r["dataset"] != dataset:
                    continue
                size = f'{r["width"]}x{r["height"]}'
                # Last stage = the rendering stage, or the span of a frame of several
                # (time-varying frames also upload and build).
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
