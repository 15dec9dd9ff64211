#!/usr/bin/env python3
"""Side-by-side report of a qpbenchmark run and `signorini qpset --solve` on the same set.

Reads qpbenchmark's results CSV (the Python solvers) and our CSV (same columns, one row per
problem x signorini backend x settings), and writes a Markdown table per settings with
qpbenchmark's metrics -- success rate (found and the three residuals below the settings'
tolerances), shifted geometric means of runtime (shift 10 s as qpbenchmark, and 10 ms), primal
and dual residuals and duality gap (shift 10, failures counted at the tolerance, as qpbenchmark;
every mean given as a ratio to the best solver's) -- plus a performance profile (SVG) per
settings: the fraction of problems each solver solves within a factor tau of the fastest.

Usage: qpset-report.py --peers PEERS.csv --ours OURS.csv --out REPORT.md --plot PREFIX
           [--settings default,high_accuracy] [--runtime 10]
"""

import argparse
import sys

import numpy as np
import pandas

# qpbenchmark.TestSet.define_tolerances (qpbenchmark 2.7): primal, dual, gap.
TOLERANCES = {
    "default": 1.0,
    "low_accuracy": 1e-3,
    "mid_accuracy": 1e-6,
    "high_accuracy": 1e-9,
}


def shgeom(v, shift):
    """Shifted geometric mean, exp(mean(log(v + shift))) - shift (qpbenchmark.shgeom)."""
    v = np.asarray(v, dtype=float)
    return float(np.exp(np.mean(np.log(v + shift))) - shift)


def success(df, tol):
    return (
        df["found"].astype(bool)
        & (df["primal_residual"] < tol)
        & (df["dual_residual"] < tol)
        & (df["duality_gap"] < tol)
    )


def table(df, settings, runtime):
    """Rows of the table for one settings."""
    tol = TOLERANCES[settings]
    df = df[df["settings"] == settings].copy()
    df["ok"] = success(df, tol)
    rows = {}
    for solver, g in df.groupby("solver"):
        found = g["found"].astype(bool)
        t = np.where(found, g["runtime"], runtime)
        rows[solver] = {
            "problems": len(g),
            "success": 100.0 * g["ok"].mean(),
            "time10s": shgeom(t, 10.0),
            "time10ms": shgeom(t, 0.01),
            "primal": shgeom(np.where(found, g["primal_residual"], tol), 10.0),
            "dual": shgeom(np.where(found, g["dual_residual"], tol), 10.0),
            "gap": shgeom(np.where(found, g["duality_gap"], tol), 10.0),
        }
    best = {
        k: min(r[k] for r in rows.values())
        for k in ("time10s", "time10ms", "primal", "dual", "gap")
    }
    out = []
    header = (
        f"| solver | success (%) | time, shift 10 s | time, shift 10 ms | primal | dual | gap |\n"
        f"|---|---|---|---|---|---|---|\n"
    )
    order = sorted(rows, key=lambda s: (-rows[s]["success"], rows[s]["time10ms"]))
    for s in order:
        r = rows[s]
        ratio = lambda k: r[k] / best[k] if best[k] > 0 else float("nan")
        out.append(
            f"| {s} | {r['success']:.1f} | {ratio('time10s'):.2f} | {ratio('time10ms'):.1f} "
            f"| {ratio('primal'):.2f} | {ratio('dual'):.2f} | {ratio('gap'):.2f} |"
        )
    note = (
        f"\nBest shifted geometric mean of time: {best['time10s']:.4g} s (shift 10 s), "
        f"{best['time10ms']:.4g} s (shift 10 ms); {len(df['problem'].unique())} problems, "
        f"tolerance {tol:g}, time limit {runtime:g} s.\n"
    )
    return header + "\n".join(out) + "\n" + note, df


def profile(df, settings, path):
    """Performance profile of runtime over successful runs."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    problems = sorted(df["problem"].unique())
    solvers = sorted(df["solver"].unique())
    times = {}
    for s in solvers:
        g = df[df["solver"] == s].set_index("problem")
        times[s] = np.array(
            [
                g.at[p, "runtime"] if p in g.index and bool(g.at[p, "ok"]) else np.inf
                for p in problems
            ]
        )
    best = np.min(np.vstack(list(times.values())), axis=0)
    taus = np.logspace(0, 4, 400)
    fig, ax = plt.subplots(figsize=(8, 5))
    for s in solvers:
        ratio = times[s] / best
        frac = [(ratio <= tau).mean() for tau in taus]
        style = "-" if s.startswith("signorini-") else "--"
        ax.step(taus, frac, style, where="post", label=s, linewidth=1.6)
    ax.set_xscale("log")
    ax.set_xlabel("tau: runtime within tau x the fastest successful solver")
    ax.set_ylabel("fraction of problems")
    ax.set_ylim(0, 1.02)
    ax.set_title(f"FEM contact test set, {settings} (solid: signorini, dashed: qpbenchmark)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--peers", required=True)
    parser.add_argument("--ours", required=True, nargs="+")
    parser.add_argument("--out", required=True)
    parser.add_argument("--plot", required=True, help="prefix of the SVG files")
    parser.add_argument("--settings", default="default,high_accuracy")
    parser.add_argument("--runtime", type=float, default=10.0)
    parser.add_argument("--header", default="")
    args = parser.parse_args()
    peers = pandas.read_csv(args.peers)
    ours = pandas.concat([pandas.read_csv(p) for p in args.ours])
    ours = ours[["problem", "solver", "settings", "runtime", "found",
                 "primal_residual", "dual_residual", "duality_gap"]]
    df = pandas.concat([peers, ours], ignore_index=True)
    # Only problems of the set both sides ran.
    common = set(peers["problem"]) & set(ours["problem"])
    df = df[df["problem"].isin(common)]
    text = [args.header] if args.header else []
    for settings in args.settings.split(","):
        if settings not in set(df["settings"]):
            print(f"no results for settings {settings}", file=sys.stderr)
            continue
        t, sdf = table(df, settings, args.runtime)
        svg = f"{args.plot}-{settings}.svg"
        profile(sdf, settings, svg)
        text.append(f"### {settings}\n\n{t}\nPerformance profile: `{svg}`\n")
    with open(args.out, "w", encoding="utf-8") as fh:
        fh.write("\n".join(text))
    print("\n".join(text))


if __name__ == "__main__":
    main()
