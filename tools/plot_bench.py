#!/usr/bin/env python3
"""Figures and report for a gi-bench run: reads DIR/results.csv (and run.txt,
images/*.pfm) and writes DIR/tradeoff.png, DIR/insets.png and DIR/report.md.

tradeoff.png: error (MSE of the final image against the reference) over GPU
ms per frame, log-log, one curve per method; the Pareto front (no other
configuration is both faster and more accurate) is drawn through the points.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w, channels)
    return np.ascontiguousarray(data[::-1])  # PFM stores the bottom row first


def to_srgb(img):
    x = np.clip(np.nan_to_num(img, nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def pareto(points):
    """Indices of points not dominated in (time, error), sorted by time."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def main(out_dir):
    with open(os.path.join(out_dir, "results.csv")) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print("plot_bench: no rows in results.csv", file=sys.stderr)
        return 1
    meta = {}
    run_txt = os.path.join(out_dir, "run.txt")
    if os.path.exists(run_txt):
        for line in open(run_txt):
            key, _, value = line.strip().partition(" ")
            meta[key] = value

    # Trade-off plot.
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    methods = []
    for r in rows:
        if r["method"] not in methods:
            methods.append(r["method"])
    for m in methods:
        pts = sorted((float(r["total_ms"]), float(r["mse"]), r["spp"]) for r in rows if r["method"] == m)
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=m)
        for t, e, spp in pts:
            ax.annotate(spp, (t, e), textcoords="offset points", xytext=(4, 4), fontsize=7)
    points = [(float(r["total_ms"]), float(r["mse"])) for r in rows]
    front = pareto(points)
    ax.plot([points[i][0] for i in front], [points[i][1] for i in front], "k--", lw=1, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("GPU ms per frame (median)")
    ax.set_ylabel("MSE vs reference (final image)")
    ax.set_title("%s, %s (labels: spp)" % (rows[0]["scene"], meta.get("size", "")))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "tradeoff.png"), dpi=110)
    plt.close(fig)

    # Insets: a central crop of the reference and of each configuration's last frame.
    ref_path = os.path.join(out_dir, "images", "reference.pfm")
    panels = [("reference", ref_path)] + [(r["label"], os.path.join(out_dir, r["image"])) for r in rows]
    panels = [(name, p) for name, p in panels if os.path.exists(p)]
    if panels:
        ref = read_pfm(panels[0][1])
        h, w = ref.shape[:2]
        ch, cw = max(8, h // 2), max(8, w // 3)
        y0, x0 = (h - ch) // 2, (w - cw) // 2
        cols = min(4, len(panels))
        nrows = (len(panels) + cols - 1) // cols
        fig, axes = plt.subplots(nrows, cols, figsize=(3.0 * cols, 2.6 * nrows), squeeze=False)
        for ax in axes.ravel():
            ax.axis("off")
        for k, (name, p) in enumerate(panels):
            img = read_pfm(p)[y0:y0 + ch, x0:x0 + cw]
            ax = axes[k // cols][k % cols]
            ax.imshow(to_srgb(img[..., :3] if img.shape[2] >= 3 else np.repeat(img, 3, axis=2)), interpolation="nearest")
            ax.set_title(name, fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out_dir, "insets.png"), dpi=110)
        plt.close(fig)

    # Error over frames (gi-bench --series).
    series_path = os.path.join(out_dir, "series.csv")
    has_series = os.path.exists(series_path)
    if has_series:
        with open(series_path) as f:
            series = list(csv.DictReader(f))
        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        labels = []
        for s in series:
            if s["label"] not in labels:
                labels.append(s["label"])
        for label in labels:
            pts = [(int(s["frame"]), float(s["mse"])) for s in series if s["label"] == label]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3, label=label)
        ax.set_yscale("log")
        ax.set_xlabel("frames rendered")
        ax.set_ylabel("MSE vs reference (final image)")
        ax.set_title("%s: error over frames" % rows[0]["scene"])
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(out_dir, "series.png"), dpi=110)
        plt.close(fig)

    # Report.
    lines = ["# gi-bench report: %s" % rows[0]["scene"], ""]
    for key in ("scene", "device", "size", "max_bounces", "reference", "reference_spp", "frames", "warmup", "bare_mrays_per_s"):
        if key in meta:
            lines.append("- %s: %s" % (key.replace("_", " "), meta[key]))
    lines += ["", "| configuration | ms/frame | passes (ms) | Mrays/s | ray eff. | MSE | relMSE | PSNR | SSIM | MSE indirect | speed-up | flicker |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| %s | %.2f | %s | %.3f | %.2f | %.3e | %.3e | %.2f | %.4f | %s | %.2f | %s |" % (
            r["label"], float(r["total_ms"]), r["pass_ms"].replace(";", "; "), float(r["mrays_per_s"]),
            float(r.get("ray_efficiency", r.get("rq_efficiency", 0))), float(r["mse"]), float(r["relmse"]), float(r["psnr"]), float(r["ssim"]),
            ("%.3e" % float(r["mse_indirect"])) if float(r["mse_indirect"]) > 0 else "n/a",
            float(r["equal_error_speedup"]), r["flicker_ratio"] or "n/a"))
    if any(float(r.get("hash_occupancy") or 0) > 0 for r in rows):
        lines += ["", "| configuration | hash occupancy | failed inserts | mean probe | max probe | evicted |",
                  "|---|---|---|---|---|---|"]
        for r in rows:
            if float(r.get("hash_occupancy") or 0) > 0:
                lines.append("| %s | %.3f | %s | %s | %s | %s |" % (r["label"], float(r["hash_occupancy"]), r["hash_failed_inserts"],
                                                            r["hash_mean_probe"], r["hash_max_probe"], r["hash_evicted"]))
    lines += ["", "![trade-off](tradeoff.png)", "", "![insets](insets.png)", ""]
    if has_series:
        lines += ["![error over frames](series.png)", ""]
    with open(os.path.join(out_dir, "report.md"), "w") as f:
        f.write("\n".join(lines))
    print("plot_bench: wrote tradeoff.png, insets.png and report.md in", out_dir)
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: plot_bench.py DIR", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
