#!/usr/bin/python3
"""Precision and recall per method and family, from the results.json of
bench/join_families.py (or any list of rows with family, method, precision
and recall): one panel per family, each set a point per method.

    bench/plot_families.py RESULTS.json OUTPUT.png
"""
import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results")
    parser.add_argument("output")
    args = parser.parse_args()
    rows = json.load(open(args.results))
    if not rows:
        raise SystemExit(f"{args.results}: no rows")
    families = list(dict.fromkeys(r["family"] for r in rows))
    methods = list(dict.fromkeys(r["method"] for r in rows))
    fig, axes = plt.subplots(1, len(families), figsize=(3.0 * len(families), 3.4), sharey=True, squeeze=False)
    for ax, family in zip(axes[0], families):
        for m, method in enumerate(methods):
            points = [(r["recall"], r["precision"]) for r in rows if r["family"] == family and r["method"] == method]
            if points:
                ax.scatter(*zip(*points), s=22, alpha=0.7, label=method, marker="os^Dv"[m % 5])
        ax.set_title(f"{family} ({sum(r['family'] == family for r in rows) // len(methods)} sets)")
        ax.set_xlabel("recall")
        ax.set_xlim(-0.03, 1.03)
        ax.grid(True, alpha=0.3)
    axes[0][0].set_ylabel("precision")
    axes[0][0].legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
