#!/usr/bin/python3
"""Mehta et al. Fig. 10: filtered adaptive sampling against filtered uniform
sampling at equal sample counts, as μ grows.

For each μ, gi-bench runs `aaf` (n(μ) per pixel), then `aaf` with
aaf.uniform=N, where N is the adaptive run's mean count per covered pixel
(found by a first uniform run that measures the covered fraction). Both use
the same filter (β from μ). Writes OUT/fig10.csv and OUT/fig10.md.

usage: aaf_fig10.py GI_BENCH SCENE SIZE REFERENCE_SPP OUT [MU ...]
"""
import csv
import os
import subprocess
import sys


def bench(gi_bench, scene, size, ref_spp, out, settings):
    subprocess.run([gi_bench, "--scene", scene, "--size", size, "--methods", "aaf", "--set", settings, "--frames", "2",
                    "--warmup", "0", "--max-bounces", "4", "--reference-spp", str(ref_spp), "--out", out],
                   check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "results.csv")) as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) < 6:
        sys.exit(__doc__)
    gi_bench, scene, size, ref_spp, out = sys.argv[1:6]
    mus = sys.argv[6:] or ["0.5", "1", "2", "4"]
    os.makedirs(out, exist_ok=True)
    # One directory for every run, so the reference is rendered once and cached beside them.
    adaptive = bench(gi_bench, scene, size, ref_spp, out, "aaf.mu=" + ",".join(mus))
    rows = []
    for mu, a in zip(mus, adaptive):
        mean = float(a["traced_spp"])
        n = max(16, round(mean))  # every covered pixel takes at least the 16 initial samples
        u = bench(gi_bench, scene, size, ref_spp, out, f"aaf.mu={mu},aaf.uniform={n}")[0]
        covered = float(u["traced_spp"]) / n
        if covered > 0 and round(mean / covered) != n:  # background pixels take no samples: match per covered pixel
            n = max(16, round(mean / covered))
            u = bench(gi_bench, scene, size, ref_spp, out, f"aaf.mu={mu},aaf.uniform={n}")[0]
        rows.append({"mu": mu, "uniform_n": n, "spp_adaptive": a["traced_spp"], "spp_uniform": u["traced_spp"],
                     "mse_indirect_adaptive": a["mse_indirect"], "mse_indirect_uniform": u["mse_indirect"],
                     "mse_adaptive": a["mse"], "mse_uniform": u["mse"], "ms_adaptive": a["total_ms"],
                     "ms_uniform": u["total_ms"]})
    with open(os.path.join(out, "fig10.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(out, "fig10.md"), "w") as f:
        f.write("| μ | mean spp, adaptive / uniform | indirect MSE, adaptive | indirect MSE, uniform | uniform / adaptive |\n")
        f.write("|---|---|---|---|---|\n")
        for r in rows:
            ratio = float(r["mse_indirect_uniform"]) / float(r["mse_indirect_adaptive"])
            f.write(f"| {r['mu']} | {r['spp_adaptive']} / {r['spp_uniform']} | {float(r['mse_indirect_adaptive']):.3g} | "
                    f"{float(r['mse_indirect_uniform']):.3g} | {ratio:.2f} |\n")


if __name__ == "__main__":
    main()
