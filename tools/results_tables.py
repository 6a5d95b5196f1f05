#!/usr/bin/env python3
"""Markdown tables for docs/RESULTS.md from gi-bench's results.csv and series.csv.

  tools/results_tables.py trade DIR          the trade-off table (ms, tracing ms, MSE, SSIM, speed-ups, memory)
  tools/results_tables.py frames DIR K,K,..  final-image MSE after frame k per configuration (series.csv)
  tools/results_tables.py indirect DIR K,..  indirect MSE and indirect light over the reference's after frame k
  tools/results_tables.py move DIR           the moving-light columns (recovery frames, steady indirect MSE)
  tools/results_tables.py walk DIR [DIR64]   a --camera-path run: the walk's mean errors and flicker, time over
                                             raw at 1 spp; with DIR64, raw at 64 spp's run over the same walk
  tools/results_tables.py sweep DIR KEY      relMSE per method for each value of a swept setting KEY, and over
                                             its first value (plus flicker and the composite pass's ms)
  tools/results_tables.py coldstart BEFORE AFTER  cold first-frame wall time per method, scene and backend
                                             (scripts/bench coldstart's cold.csv, two builds)
  tools/results_tables.py programs JSON...   each program's first dispatch (gi-render --stats), per method
  tools/results_tables.py switch DIR         the demo's method switch (sample_game's benchmark.csv): readied
                                             against in the frame
  tools/results_tables.py warm BEFORE AFTER  warm bare-ray rates (rays.csv) and frame times (results.csv) of
                                             scripts/bench warm's directories, two builds

  tools/results_tables.py speedups METHOD DIR...  a method's equal-error speed-ups over raw per scene and spp
  tools/results_tables.py demo DIR           the demo scene's figure of merit (relMSE × ms per frame)
  tools/results_tables.py refit_rebuild CSV  the update that finds a level degraded: rebuilt in it or off thread
  tools/results_tables.py bench_log LOG...   gi-bench's printed lines (runs cut off before their results.csv)
  tools/results_tables.py device_memory GPU LAVAPIPE  memory per method at 1080p on a GPU against lavapipe
  tools/results_tables.py light_samplers CSV  frame ms against the point-light count per light sampler
  tools/results_tables.py hash_map NAME DIR ...  the map's occupancy, failed inserts, memory and error per run
  tools/results_tables.py hash_live SEGMENTS JSON ...  live cells a pixel and a vertex (gi-render --stats)
  tools/results_tables.py gtest_logs LOG...  GoogleTest logs: tests run, passed, skipped, failed by name
  tools/results_tables.py label_stress DIR   tests/label_stress.cpp's runs: submissions made and how each ended
  tools/results_tables.py check FILE...      every generated block of the markdown FILEs against its data
  tools/results_tables.py write FILE...      rewrites those blocks from their data

A generated block in a markdown file is a table between

  <!-- generated: results_tables.py KIND ARGS -->
  <!-- end generated -->

(paths relative to the repository root); `check` exits 1 naming each block
that differs (the ctest DocsTablesMatchTheirData runs it).

"Tracing ms" is the time gi-bench divided the rays by (its tracing passes):
rays / Mrays/s.
"""
import contextlib
import io
import json
import os
import re
import statistics
import csv
import sys

def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def named(pairs):
    """NAME DIR NAME DIR ... as (name, directory) pairs."""
    return zip(pairs[::2], pairs[1::2])


def tracing_ms(row):
    mrays = float(row["mrays_per_s"])
    return float(row["rays"]) / (mrays * 1e3) if mrays > 0 else 0.0


def trade(directory):
    print("| configuration | ms/frame | tracing ms | MSE (final) | MSE (indirect) | SSIM | speed-up (final) "
          "| speed-up (indirect) | memory MB |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows(f"{directory}/results.csv"):
        print(f"| {r['label']} | {float(r['total_ms']):.1f} | {tracing_ms(r):.1f} | {float(r['mse']):.3e} "
              f"| {float(r['mse_indirect']):.3e} | {float(r['ssim']):.4f} | {float(r['equal_error_speedup']):.2f} "
              f"| {float(r['equal_error_speedup_indirect']):.2f} | {int(r['memory_bytes']) / 1048576:.1f} |")


def series_by_label(directory):
    out = {}
    for r in rows(f"{directory}/series.csv"):
        out.setdefault(r["label"], {})[int(r["frame"])] = r
    return out


def frames(ks, pairs, column="mse"):
    """Final-image MSE after frame k of every run of each series (args: K1,K2,... NAME DIR ...)."""
    ks = [int(k) for k in ks.split(",")]
    print("| scene | configuration | " + " | ".join(f"k = {k}" for k in ks) + " |")
    print("|---|---|" + "---|" * len(ks))
    for name, directory in named(pairs):
        for label, series in series_by_label(directory).items():
            cells = []
            for k in ks:
                r = series.get(k)  # series.csv numbers frames from 1
                cells.append(f"{float(r[column]):.2e}" if r else "–")
            print(f"| {name.replace('_', ' ')} | {label} | " + " | ".join(cells) + " |")


def indirect(directory, ks):
    ks = [int(k) for k in ks.split(",")]
    print("| configuration | " + " | ".join(f"MSE ind. k = {k}" for k in ks) + " | "
          + " | ".join(f"light k = {k}" for k in ks) + " |")
    print("|---|" + "---|" * (2 * len(ks)))
    for label, series in series_by_label(directory).items():
        mse = [f"{float(series[k]['mse_indirect']):.2e}" if k in series else "–" for k in ks]
        light = [f"{float(series[k]['energy_indirect']):.3f}" if k in series else "–" for k in ks]
        print(f"| {label} | " + " | ".join(mse) + " | " + " | ".join(light) + " |")


def move(directory):
    print("| configuration | frames to recover | steady MSE (indirect) | MSE (final) |")
    print("|---|---|---|---|")
    for r in rows(f"{directory}/results.csv"):
        rec = int(r["move_recovery_frames"])
        print(f"| {r['label']} | {rec if rec >= 0 else 'not within the run'} | "
              f"{float(r['move_steady_mse_indirect']):.3e} | {float(r['mse']):.3e} |")


def walk(directory, raw64=None):
    rows_ = rows(f"{directory}/results.csv")
    base = float(next(r for r in rows_ if r["label"].startswith("raw spp=1 raw.temporal=0"))["total_ms"])
    if raw64:
        r = dict(rows(f"{raw64}/results.csv")[0])
        r["label"] = "raw spp=64 (separate run)"
        rows_ = rows_ + [r]
    print("| configuration | ms/frame | × raw 1 spp | relMSE final | relMSE indirect | MSE final | flicker |")
    print("|---|---|---|---|---|---|---|")
    for r in rows_:
        flicker = f"{float(r['flicker_ratio']):.2f}" if r["flicker_ratio"] else "–"  # --animate runs: none
        print(f"| {r['label']} | {float(r['total_ms']):.1f} | {float(r['total_ms']) / base:.2f} | "
              f"{float(r['relmse']):.3e} | {float(r['relmse_indirect']):.3e} | {float(r['mse']):.3e} | {flicker} |")


def walk_best(pairs, budget=1.5):
    """Per scene, the lowest final relMSE at 1 spp within `budget` x raw's 1-spp time, against raw at 64 spp."""
    for directory, raw64 in named(pairs):
        rows_ = rows(f"{directory}/results.csv")
        base = float(next(r for r in rows_ if r["label"].startswith("raw spp=1 raw.temporal=0"))["total_ms"])
        within = [r for r in rows_ if not r["label"].startswith("raw ") and float(r["total_ms"]) <= budget * base]
        best = min(within, key=lambda r: float(r["relmse"]))
        reference = rows(f"{raw64}/results.csv")[0]
        print(f"- {directory.rstrip('/').split('/')[-1]}: `{best['label']}` {float(best['relmse']):.3e} "
              f"against raw at 64 spp {float(reference['relmse']):.3e}, at "
              f"{float(best['total_ms']) / base:.2f}x raw's 1-spp time")


def hashdirect(pairs):
    """The hash methods' direct history: off, hpsf.temporal, + hpsf.temporal_indirect (args: NAME DIR ...)."""
    print("| scene | method | off | `hpsf.temporal` (default) | + `hpsf.temporal_indirect` | ms off → default → + indirect |")
    print("|---|---|---|---|---|---|")
    for name, directory in named(pairs):
        name = name.replace("_", " ")  # names travel as one argument
        rows_ = rows(f"{directory}/results.csv")
        for method in dict.fromkeys(r["method"] for r in rows_):
            mine = [r for r in rows_ if r["method"] == method]
            if method == "svgf":
                r = mine[0]
                print(f"| {name} | svgf | {float(r['relmse']):.3e} | | | {float(r['total_ms']):.1f} |")
                continue
            by = {r["settings"]: r for r in mine}
            cells = [by["hpsf.temporal=0 hpsf.temporal_indirect=0"], by["hpsf.temporal=1 hpsf.temporal_indirect=0"],
                     by["hpsf.temporal=1 hpsf.temporal_indirect=1"]]
            off = float(cells[0]["relmse"])
            on = " | ".join(f"{float(c['relmse']):.3e} ({float(c['relmse']) / off:.2f}×)" for c in cells[1:])
            ms = " → ".join(f"{float(c['total_ms']):.1f}" for c in cells)
            print(f"| {name} | {method} | {off:.3e} | {on} | {ms} |")


def spikes(before_root, after_root, scenes):
    """Per scene and eviction policy, before and after: the worst frame against its two neighbours' mean."""
    print("| scene | policy | build | worst frame / neighbours' mean | frames above 1.3× | indirect MSE frame 1 | mean of the last 16 |")
    print("|---|---|---|---|---|---|---|")
    for scene in scenes:
        for build, root in (("before", before_root), ("after", after_root)):
            series = rows(f"{root}/eviction_{scene}/series.csv")
            for label in dict.fromkeys(r["label"] for r in series):
                e = [float(r["mse_indirect"]) for r in series if r["label"] == label]
                ratios = [(e[i] / (0.5 * (e[i - 1] + e[i + 1])), i + 1) for i in range(1, len(e) - 1)]
                worst = max(ratios)
                policy = "strict" if "hpsf.eviction=0" in label else "aging"
                print(f"| {scene} | {policy} | {build} | {worst[0]:.2f} (frame {worst[1]}) | "
                      f"{sum(1 for r, _ in ratios if r > 1.3)} | {e[0]:.3e} | {sum(e[-16:]) / 16:.3e} |")


# Issue 30's goal at 1920×1080: every method within 200 MB, hpsf and svgf within 150 MB (NRD documents
# 91 MB for RELAX_DIFFUSE and 76 MB for REBLUR_DIFFUSE). ModuleMemoryTest.EveryMethodAt1080pHoldsWhatTheMemoryTableSays
# asserts the same goals on the live module.
MEMORY_GOAL_MB = {"hpsf": 150, "svgf": 150}
MEMORY_GOAL_DEFAULT_MB = 200


def memory(path, before_path, before_label="before"):
    """Device memory each method holds after one frame (scripts/bench memory), MB = 10^6 bytes: held at
    720p and 1080p (and at 1080p in another run: an earlier one, or another scene's, named by
    `before_label`, underscores for spaces), at 1080p what gi::predictMemory said before the
    module existed ("=": to the byte), what is used, of that what lives within
    a frame (transient) and what carries over (histories, the hash map, the outputs), the blocks, and
    the goal."""
    def by_method(p):
        by = {}
        for r in rows(p):
            by.setdefault(r["method"], {})[f"{r['width']}x{r['height']}"] = r
        return by
    before = by_method(before_path)
    def predicted(r):  # gi::predictMemory's held bytes, and whether they are the held bytes to the byte
        if not r.get("predicted_bytes"):
            return "–"
        return f"{int(r['predicted_bytes']) / 1e6:.1f}" + (" (=)" if r["predicted_bytes"] == r["held_bytes"] else " (≠)")
    print(f"| method | 1280x720 held MB | 1920x1080 held MB | predicted MB | {before_label.replace('_', ' ')} | used MB | transient MB "
          "| persistent MB | blocks | goal MB | held / goal |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for method, at in by_method(path).items():
        small, full = at["1280x720"], at["1920x1080"]
        held, used, transient = (int(full[k]) / 1e6 for k in ("held_bytes", "used_bytes", "transient_bytes"))
        goal = MEMORY_GOAL_MB.get(method, MEMORY_GOAL_DEFAULT_MB)
        verdict = f"{held / goal:.2f}" + ("" if held <= goal else " (over)")
        print(f"| `{method}` | {int(small['held_bytes']) / 1e6:.1f} | {held:.1f} | {predicted(full)} | "
              f"{int(before[method]['1920x1080']['held_bytes']) / 1e6:.1f} | {used:.1f} | {transient:.1f} | "
              f"{used - transient:.1f} | {full['blocks']} | {goal} | {verdict} |")


def dynamic_resolution(path):
    """The render size alternating within the module's largest size (scripts/bench dynamic_resolution): the
    last frame's MSE against the reference with the size fixed and alternating, their ratio (issue 35's
    goal: at most 1.5), and the module's memory after the first and the last frame."""
    print("| sizes | method | MSE, fixed | MSE, alternating | alternating / fixed | memory after frame 1 / 36, MB |")
    print("|---|---|---|---|---|---|")
    for r in rows(path):
        ratio = float(r["mse_alternating"]) / float(r["mse_fixed"])
        print(f"| {r['large']} with {r['small']} | `{r['method']}` | {float(r['mse_fixed']):.3e} | "
              f"{float(r['mse_alternating']):.3e} | {ratio:.2f}" + ("" if ratio <= 1.5 else " (over)") +
              f" | {int(r['memory_first_frame']) / 1e6:.2f} / {int(r['memory_last_frame']) / 1e6:.2f} |")


def ab(prefix, a_name, b_name, scenes, over_settings=False):
    """Two runs of the same configurations against the same reference (args: PREFIX A B SCENE ...; the runs
    are PREFIX_<scene>_A and PREFIX_<scene>_B): each method's final and indirect MSE, the means over the
    runs' frames, and the change from A to B. A method run with several settings has a row for each, or
    with `over_settings` (ab_mean) one row of their mean (seeds, say)."""
    print(f"| scene | method | final MSE, {a_name} | {b_name} | change | indirect MSE, {a_name} | {b_name} | change |")
    print("|---|---|---|---|---|---|---|---|")
    for scene in scenes:
        def configuration(r):
            return f'{r["method"]} ({r["settings"]})' if r["settings"] and not over_settings else r["method"]

        def means(run):
            grouped = {}
            for r in rows(f"{prefix}_{scene.lower()}_{run}/results.csv"):
                grouped.setdefault(configuration(r), []).append(r)
            return {k: {c: sum(float(r[c]) for r in v) / len(v) for c in ("mse", "mse_indirect")}
                    for k, v in grouped.items()}
        single, half = means(a_name), means(b_name)
        for method, s in single.items():
            h = half[method]
            cells = []
            for column in ("mse", "mse_indirect"):
                a, b = s[column], h[column]
                cells.append(f"{a:.4e} | {b:.4e} | {100 * (b - a) / a:+.2f}%")
            print(f"| {scene} | {method} | " + " | ".join(cells) + " |")


def gif_order(pairs):
    """Bauszat et al.'s Fig. 8 ordering from the trade-off runs (args: NAME DIR ...): indirect MSE of gif,
    bilateral, à-trous and raw at 1 and 4 spp, and their order."""
    names = {"gif": "gif", "bilateral": "bilateral", "atrous": "à-trous", "raw": "raw"}
    paper = ["gif", "bilateral", "atrous", "raw"]
    print("| scene, spp | gif | bilateral | à-trous | raw | order |")
    print("|---|---|---|---|---|---|")
    for name, directory in named(pairs):
        by = {r["label"]: float(r["mse_indirect"]) for r in rows(f"{directory}/results.csv")}
        for spp in (1, 4):
            mse = {m: by[f"raw spp={spp}" if m == "raw" else f"{m} {m}.spp={spp}"] for m in paper}
            ranked = sorted(paper, key=lambda m: mse[m])
            order = " < ".join(names[m] for m in ranked)
            if ranked == paper:
                order = f"**{order}** (the paper's order)"
            print(f"| {name}, {spp} | " + " | ".join(f"{mse[m]:.2e}" for m in paper) + f" | {order} |")


def filter_cost(directory):
    """The filters' cost against reach (scripts/bench cost): per configuration, the filter passes' ms (the frame
    less the G-buffer, the tracing pass, guidance and composite), the frame's ms and the indirect MSE."""
    outside = {"gbuffer", "raw_trace", "guidance", "composite"}
    print("| configuration | filter passes ms | frame ms | MSE (indirect) |")
    print("|---|---|---|---|")
    for r in rows(f"{directory}/results.csv"):
        passes = dict(p.split(":") for p in r["pass_ms"].split(";"))
        filters = sum(float(ms) for name, ms in passes.items() if name not in outside)
        print(f"| {r['label']} | {filters:.1f} | {float(r['total_ms']):.1f} | {float(r['mse_indirect']):.3e} |")


def aaf_cost(pairs):
    """AAF's frame from the trade-off runs (args: NAME DIR ...): frame ms, its two tracing passes, the filter
    (guidance and the two Gaussian passes), the filter's share and the equal-error speed-ups over raw."""
    print("| scene | frame ms | pass 1 + pass 2 (tracing) ms | filter ms (guidance + 2 Gaussian passes) | filter share "
          "| speed-up final / indirect |")
    print("|---|---|---|---|---|---|")
    for name, directory in named(pairs):
        r = next(r for r in rows(f"{directory}/results.csv") if r["label"] == "aaf")
        total = float(r["total_ms"])
        tracing = pass_ms(r, "aaf_sample") + pass_ms(r, "aaf_adaptive")
        filtering = sum(pass_ms(r, p) for p in ("guidance", "aaf_filter_diffuse_rows", "aaf_filter_diffuse_columns"))
        print(f"| {name} | {total:.0f} | {tracing:.0f} | {filtering:.1f} | {100 * filtering / total:.1f}% | "
              f"{float(r['equal_error_speedup']):.2f} / {float(r['equal_error_speedup_indirect']):.2f} |")


def aaf_fig10(pairs):
    """Filtered adaptive against filtered uniform sampling (scripts/bench fig10; args: NAME DIR ...)."""
    print("| scene | μ | mean spp, adaptive / uniform | indirect MSE, adaptive | indirect MSE, uniform | uniform / adaptive |")
    print("|---|---|---|---|---|---|")
    for name, directory in named(pairs):
        for r in rows(f"{directory}/fig10.csv"):
            a, u = float(r["mse_indirect_adaptive"]), float(r["mse_indirect_uniform"])
            print(f"| {name} | {r['mu']} | {r['spp_adaptive']} / {r['spp_uniform']} | {a:.2e} | {u:.2e} | {u / a:.2f} |")


def settings_at_frame(k, pairs):
    """Settings swept one at a time (args: K KEY DIR [KEY DIR ...]): per value, the final and indirect MSE
    after frame K of the run's series and the map's occupancy then."""
    print(f"| setting | final MSE, frame {k} | indirect | occupancy |")
    print("|---|---|---|---|")
    for key, directory in named(pairs):
        for label, series in series_by_label(directory).items():
            r = series[int(k)]
            value = label.split(f"{key}=")[1].split()[0]
            print(f"| {key} = {value} | {float(r['mse']):.2e} | {float(r['mse_indirect']):.2e} | "
                  f"{100 * float(r['hash_occupancy']):.1f}% |")


def deviations(pairs):
    """nhpsf and anhpsf with the thesis's secondary level of detail and ours, with and without the history
    samples (args: NAME DIR ...): indirect MSE and indirect light against the reference at frames 32 and 64."""
    lods = {"0": "segment (thesis)", "1": "path", "2": "camera"}
    print("| scene | secondary LOD | history samples | nhpsf indirect MSE k = 32 / 64 | nhpsf light k = 32 / 64 "
          "| anhpsf indirect MSE k = 32 / 64 | anhpsf light k = 32 / 64 |")
    print("|---|---|---|---|---|---|---|")
    for name, directory in named(pairs):
        series = series_by_label(directory)
        for history in ("0", "8"):
            for lod in ("0", "1", "2"):
                cells = []
                for method in ("nhpsf", "anhpsf"):
                    s = series[f"{method} spp=1 hpsf.secondary_lod={lod} hpsf.history_samples={history}"]
                    cells.append(f"{float(s[32]['mse_indirect']):.2e} / {float(s[64]['mse_indirect']):.2e}")
                    cells.append(f"{float(s[32]['energy_indirect']):.3f} / {float(s[64]['energy_indirect']):.3f}")
                lod_cell, history_cell = lods[lod], "off" if history == "0" else history
                if (lod, history) == ("2", "8"):  # the defaults (HpsfSettings::secondaryLod, historySamples)
                    lod_cell, history_cell = f"**{lod_cell}**", f"**{history_cell}**"
                print(f"| {name} | {lod_cell} | {history_cell} | " + " | ".join(cells) + " |")


def light_at_frame(k, key, directories):
    """A setting's values against methods (args: K KEY DIR ...): indirect light against the reference and
    indirect MSE after frame K of each run's series; – where a method did not run a value."""
    cells, methods, values = {}, [], []
    for directory in directories:
        for label, series in series_by_label(directory).items():
            method, value = label.split()[0], label.split(f"{key}=")[1].split()[0]
            methods += [method] if method not in methods else []
            values += [value] if value not in values else []
            r = series[int(k)]
            cells[method, value] = f"{float(r['energy_indirect']):.3f} / {float(r['mse_indirect']):.2e}"
    print(f"| {key} | " + " | ".join(methods) + " |")
    print("|---|" + "---|" * len(methods))
    for value in values:
        print(f"| {value} | " + " | ".join(cells.get((m, value), "–") for m in methods) + " |")


def hash_passes(pairs):
    """The hash methods' passes per scene (args: NAME DIR ...): the tracing pass, resolve and lookup against
    the frame, ms, and the hash passes' share (resolve + lookup)."""
    tracing = {"hpsf": "hpsf_insert", "nhpsf": "nhpsf_paths", "anhpsf": "anhpsf_paths"}
    print("| scene | hpsf: insert / resolve / lookup of frame | nhpsf: paths / resolve / lookup "
          "| anhpsf: paths / resolve / lookup |")
    print("|---|---|---|---|")
    for name, directory in named(pairs):
        by = {r["method"]: r for r in rows(f"{directory}/results.csv")}
        cells = []
        for method, trace in tracing.items():
            r = by[method]
            resolve, lookup, total = pass_ms(r, "hpsf_resolve"), pass_ms(r, "hpsf_lookup"), float(r["total_ms"])
            share = f"{100 * (resolve + lookup) / total:.0f}%"
            cells.append(f"{pass_ms(r, trace):.1f} / {resolve:.1f} / {lookup:.1f} of {total:.1f} "
                         f"({'hash ' if method == 'hpsf' else ''}{share})")
        print(f"| {name} | " + " | ".join(cells) + " |")


def lights(path):
    """A frame's cost against the light count (scripts/bench lights): GPU ms per frame per method, the rays
    of raw's frame, and each method's time against its own at 4 lights (issue 31's goal: at most 1.5× at 1024)."""
    by = {}
    for r in rows(path):
        by.setdefault(r["lights"], {})[r["method"]] = r
    methods = list(next(iter(by.values())).keys())
    print("| point lights | " + " | ".join(f"{m} ms" for m in methods) + " | rays per frame (raw) | "
          + " | ".join(f"{m} against 4 lights" for m in methods) + " |")
    print("|---|" + "---|" * (2 * len(methods) + 1))
    for n, at in by.items():
        ms = " | ".join(f"{float(at[m]['gpu_ms_per_frame']):.1f}" for m in methods)
        # Another scene (the hall) is not compared with Conference's 4 lights.
        ratio = " | ".join(f"{float(at[m]['gpu_ms_per_frame']) / float(by['4'][m]['gpu_ms_per_frame']):.2f}×"
                           if n.isdigit() else "–" for m in methods)
        print(f"| {n} | {ms} | {int(at[methods[0]]['rays_per_frame']):,} | {ratio} |")


def goal_cells(at, base, methods):
    """Per method: GPU ms per frame, final MSE, and both over `base`'s (issue 31's goal columns)."""
    cells = []
    for m in methods:
        ms, mse = float(at[m]["total_ms"]), float(at[m]["mse"])
        cells.append(f"{ms:.1f} | {mse:.3e} | {ms / float(base[m]['total_ms']):.2f}×, {mse / float(base[m]['mse']):.2f}×")
    return " | ".join(cells)


def samplers(prefix):
    """The light samplers against the light count (scripts/bench samplers; runs PREFIX_<N>_<sampler>): per
    method GPU ms per frame, final MSE against the N's one reference, and both over the same method's with
    every light sampled at 4 lights (issue 31's goal: at most 1.5× each at 1024). tree4r: tree4 with the
    primary hits' reservoirs (ReservoirSettings, temporal reuse)."""
    methods = ["raw", "svgf", "hpsf"]
    runs = {}
    for n in ("1", "4", "64", "256", "1024", "4096"):
        for sampler in ("all", "power", "tree1", "tree4", "tree4r"):
            path = f"{prefix}_{n}_{sampler}/results.csv"
            if os.path.exists(path):
                runs[(n, sampler)] = {r["method"]: r for r in rows(path)}
    base = runs[("4", "all")]
    print("| point lights | sampler | " + " | ".join(f"{m} ms | {m} MSE | {m} against all at 4 lights" for m in methods)
          + " |")
    print("|---|---|" + "---|" * (3 * len(methods)))
    for (n, sampler), at in runs.items():
        print(f"| {n} | {sampler} | " + goal_cells(at, base, methods) + " |")


def emissive_reservoirs(prefix, default_min=16):
    """Reservoirs over the emissive triangles against the panel count (scripts/bench emissive_reservoirs;
    runs PREFIX_<N>): per N and reservoirs.enabled, per method GPU ms per frame, final MSE, and both over
    the same method's at 4 panels with the defaults (no reservoirs: two triangles a panel, 8 not above
    reservoirs.emissive_min), issue 31's goal (at most 1.5× each at 1024). "default": what the defaults run
    at that N."""
    methods = ["raw", "svgf", "hpsf"]
    runs = {}
    for n in ("4", "16", "64", "1024", "4096"):
        path = f"{prefix}_{n}/results.csv"
        if os.path.exists(path):
            for r in rows(path):
                value = r["label"].split("reservoirs.enabled=")[1].split()[0]
                runs.setdefault((n, value), {})[r["method"]] = r
    base = runs[("4", "0")]
    print("| panels | reservoirs | default | " + " | ".join(f"{m} ms | {m} MSE | {m} against 4 panels" for m in methods)
          + " |")
    print("|---|---|---|" + "---|" * (3 * len(methods)))
    for (n, value), at in runs.items():
        default = (value == "1") == (2 * int(n) > default_min)
        print(f"| {n} | {'on' if value == '1' else 'off'} | {'yes' if default else ''} | " +
              goal_cells(at, base, methods) + " |")


def median_runs(directory):
    """The rows of a run, or of several runs of the same configurations (DIR, comma-separated: rounds that
    alternated with others on one machine), keyed by method and settings: each round's times replaced by
    their median (total and every pass), the rest (the errors, the same every round) the first round's."""
    merged = {}
    for d in directory.split(","):
        for r in rows(f"{d}/results.csv"):
            merged.setdefault((r["method"], r["settings"]), []).append(r)
    out = {}
    for k, rounds in merged.items():
        row = dict(rounds[0])
        row["total_ms"] = str(statistics.median_high(float(r["total_ms"]) for r in rounds))
        passes = {}
        for r in rounds:
            for item in r["pass_ms"].split(";"):
                label, ms = item.split(":")
                passes.setdefault(label, []).append(float(ms))
        row["pass_ms"] = ";".join(f"{label}:{statistics.median_high(v)}" for label, v in passes.items())
        out[k] = row
    return out


def goal_sweep(key, pass_prefix, pairs):
    """A setting swept on many-light scenes beside their 4-light run (args: KEY PREFIX BASE_NAME BASE_DIR NAME DIR
    ...; the first pair the base, run with the defaults): per scene and value, the ms per frame of the passes
    whose names start with PREFIX, and per method GPU ms per frame, final MSE and both over the base's (issue
    31's goal columns). KEY `settings`: a row per run of several settings swept together, named by all of
    them; the methods those of raw, aaf, svgf and hpsf that the base and every run ran. A DIR may be rounds,
    comma-separated (median_runs)."""
    (base_name, base_dir), *runs = named(pairs)
    base = {method: r for (method, _), r in median_runs(base_dir).items()}
    ran = [{method for method, _ in median_runs(directory)} for _, directory in runs]
    methods = [m for m in ["raw", "aaf", "svgf", "hpsf"] if m in base and all(m in r for r in ran)]
    print(f"| scene | {key} | {methods[0]}'s {pass_prefix}* ms | " +
          " | ".join(f"{m} ms | {m} MSE | {m} against {base_name.replace('_', ' ')}" for m in methods) + " |")
    print("|---|---|---|" + "---|" * (3 * len(methods)))
    for name, directory in [(base_name, base_dir)] + runs:
        by_value = {}
        for r in median_runs(directory).values():
            if key == "settings":
                value = r["settings"].replace("reservoirs.", "") or "–"
            else:
                value = r["label"].split(f"{key}=")[1].split()[0] if f"{key}=" in r["label"] else "–"
            by_value.setdefault(value, {})[r["method"]] = r
        for value, at in by_value.items():
            ms = sum(float(x.split(":")[1]) for x in at[methods[0]]["pass_ms"].split(";") if x.startswith(pass_prefix))
            print(f"| {name.replace('_', ' ')} | {value} | {ms:.1f} | " + goal_cells(at, base, methods) + " |")


def per_frame(path, key):
    """GPU ms per frame against one column of a per-run CSV (scripts/bench sky: KEY = sky): rows the
    column's values, columns the methods."""
    by, methods = {}, []
    for r in rows(path):
        by.setdefault(r[key], {})[r["method"]] = r
        methods += [r["method"]] if r["method"] not in methods else []
    print(f"| {key} | " + " | ".join(f"`{m}` ms" for m in methods) + " |")
    print("|---|" + "---|" * len(methods))
    for value, at in by.items():
        print(f"| {value} | " + " | ".join(f"{float(at[m]['gpu_ms_per_frame']):.1f}" for m in methods) + " |")


def pathtracer(path):
    """The reference path tracer per backend (scripts/bench pathtracer): rays, GPU ms and Mrays/s."""
    names = {"rayquery": "ray queries", "compute": "compute"}
    print("| scene | triangles | rays | backend | GPU ms | Mrays/s |")
    print("|---|---|---|---|---|---|")
    previous = None
    for r in rows(path):
        first = r["scene"] != previous
        previous = r["scene"]
        rays, ms = int(r["rays"]), float(r["gpu_ms"])
        lead = f"| `{r['scene']}` | {int(r['triangles']):,} | {rays:,} |" if first else "| | | |"
        print(f"{lead} {names[r['traversal']]} | {ms:,.0f} | {rays / ms / 1e3:.2f} |")


MOVING_RUNS = (  # (directory suffix, label prefix, the table's name for it)
    ("strict", "hpsf spp=4 hpsf.eviction=0", "hpsf strict"),
    ("hpsf", "hpsf spp=4 hpsf.eviction=1 hpsf.validation=0", "hpsf aging"),
    ("hpsf", "hpsf spp=4 hpsf.eviction=1 hpsf.validation=4", "hpsf aging + sentinels"),
    ("anhpsf", "anhpsf spp=4 hpsf.validation=0", "anhpsf"),
    ("anhpsf", "anhpsf spp=4 hpsf.validation=4", "anhpsf + sentinels"),
    ("invalidate", "hpsf spp=4", "hpsf aging + sentinels + invalidate(LightsChanged)"),
    ("invalidate", "anhpsf spp=4", "anhpsf + sentinels + invalidate(LightsChanged)"),
)


def moving(root, move_at, scenes):
    """The moving-light experiment (scripts/bench move): indirect MSE before the jump and k frames after it."""
    after = (1, 2, 4, 8, 16, 32, 48)
    print("| scene | method | before | " + " | ".join(str(k) for k in after) +
          " | steady | recovery (frames) | light after 1 / 4 / 48 | histories cut |")
    print("|---|---|---|" + "---|" * len(after) + "---|---|---|---|")
    for scene in scenes:
        for suffix, label, name in MOVING_RUNS:
            directory = f"{root}/move_{scene.lower()}_{suffix}"
            result = next(r for r in rows(f"{directory}/results.csv") if r["label"] == label)
            series = {int(r["frame"]): r for r in rows(f"{directory}/series.csv") if r["label"] == label}
            errors = " | ".join(f"{float(series[move_at + k]['mse_indirect']):.2e}" for k in after)
            light = " / ".join(f"{float(series[move_at + k]['energy_indirect']):.2f}" for k in (1, 4, 48))
            print(f"| {scene} | {name} | {float(series[move_at]['mse_indirect']):.2e} | {errors} | "
                  f"{float(result['move_steady_mse_indirect']):.2e} | {result['move_recovery_frames']} | {light} | "
                  f"{result['hash_stale_resets']} |")


def rays(path):
    """Bare-ray rates per scene and backend (gi-bench --rays), Mrays/s, and diffuse against Embree's."""
    names = {"rayquery": "ray queries", "compute": "compute", "embree_cpu": "Embree"}
    print("| scene | backend | primary | diffuse | shadow | diffuse, of Embree | build ms |")
    print("|---|---|---|---|---|---|---|")
    last = None
    for r in rows(path):
        scene = f"{r['scene']} ({int(r['triangles']):,} triangles)" if r["scene"] != last else ""
        last = r["scene"]
        build = float(r["bvh_build_ms"])  # 0: not measured (the ray queries' builds run on the device)
        print(f"| {scene} | {names[r['backend']]} | {float(r['primary_mrays']):.3g} | {float(r['diffuse_mrays']):.3g} | "
              f"{float(r['shadow_mrays']):.3g} | {float(r['diffuse_of_embree']):.2f} | "
              f"{f'{build:.1f}' if build > 0 else '–'} |")


def hash_map(pairs):
    """The hash map under configurations of its size (args: NAME DIR ...): per run and row, the map's
    occupancy and failed inserts in the last frame, the module's memory and the final and indirect relMSE."""
    print("| run | configuration | occupancy | failed inserts, last frame | memory MB | relMSE (final) "
          "| relMSE (indirect) |")
    print("|---|---|---|---|---|---|---|")
    for name, directory in named(pairs):
        for r in rows(f"{directory}/results.csv"):
            print(f"| {name.replace('_', ' ')} | {r['label']} | {float(r['hash_occupancy']):.2f} | "
                  f"{r['hash_failed_inserts']} | {int(r['memory_bytes']) * 1e-6:.1f} | {float(r['relmse']):.3e} | "
                  f"{float(r['relmse_indirect']):.3e} |")


def hash_live(segments, paths):
    """The cells a method keeps live in a map too large to fill (gi-render --stats after N frames, args:
    SEGMENTS JSON ...): per pixel and per vertex a pixel's path reaches (pixels × SEGMENTS)."""
    print("| method | size | frames | capacity | live cells | a pixel | a vertex | failed inserts |")
    print("|---|---|---|---|---|---|---|---|")
    for path in paths:
        d = json.load(open(path))
        h, pixels = d["hash_last_frame"], d["width"] * d["height"]
        print(f"| {d['method']} | {d['width']}×{d['height']} | {d['frames']} | {h['capacity']:,} | {h['occupied']:,} | "
              f"{h['occupied'] / pixels:.3f} | {h['occupied'] / (pixels * int(segments)):.3f} | {h['failed_inserts']} |")


def bench_log(paths):
    """gi-bench runs' printed lines (runs cut off before their results.csv, or split over calls): ms a frame
    and the final image's errors per configuration (aaf, adaptive, prints no spp)."""
    line = re.compile(r"gi-bench: (\S+)( spp=\d+)?\s+([\d.]+) ms\s+MSE (\S+)\s+relMSE (\S+)\s+SSIM (\S+)")
    print("| configuration | ms/frame | MSE (final) | relMSE (final) | SSIM |")
    print("|---|---|---|---|---|")
    for path in paths:
        for m in filter(None, map(line.search, open(path, encoding="utf-8"))):
            print(f"| {m[1]}{m[2] or ''} | {float(m[3]):.1f} | {float(m[4]):.3e} | {float(m[5]):.3e} | "
                  f"{float(m[6]):.3f} |")


def device_memory(device_path, lavapipe_path):
    """Each method's device memory at 1920×1080 on a GPU against lavapipe, the same command on both
    (scripts/device/run memory: gi-render --frames 4, MB = 10^6 bytes), and issue 30's goal."""
    lavapipe = {r["method"]: r for r in rows(lavapipe_path)}
    goal = {"hpsf": 150, "svgf": 150}
    print("| method | held on the GPU | held on lavapipe | GPU − lavapipe | transient on the GPU | predicted = held "
          "(GPU) | goal |")
    print("|---|---|---|---|---|---|---|")
    for r in rows(device_path):
        mine, theirs = int(r["held_bytes"]), int(lavapipe[r["method"]]["held_bytes"])
        print(f"| {r['method']} | {mine / 1e6:.1f} | {theirs / 1e6:.1f} | {(mine - theirs) / 1e6:+.1f} | "
              f"{int(r['transient_bytes']) / 1e6:.1f} | {'yes' if r['predicted_bytes'] == r['held_bytes'] else 'no'} | "
              f"≤ {goal.get(r['method'], 200)} |")


def light_samplers(path):
    """A frame's GPU ms against the point-light count for each light sampler (scripts/device/run lights),
    and each against its own time at 4 lights."""
    by = {}
    for r in rows(path):
        by.setdefault((r["method"], r["lights"]), {})[r["sampler"]] = float(r["gpu_ms_per_frame"])
    samplers = ["tree", "power", "all"]
    print("| method | point lights | " + " | ".join(f"{s} ms" for s in samplers) + " | "
          + " | ".join(f"{s} against 4 lights" for s in samplers) + " |")
    print("|---|---|" + "---|" * (2 * len(samplers)))
    for (method, n), ms in by.items():
        base = by[(method, "4")]
        cell = lambda s: f"{ms[s]:.2f}" if s in ms else "–"
        ratio = lambda s: f"{ms[s] / base[s]:.2f}×" if s in ms else "–"
        print(f"| {method} | {n} | " + " | ".join(map(cell, samplers)) + " | " + " | ".join(map(ratio, samplers)) + " |")


def gtest_logs(paths):
    """GoogleTest runs (--gtest_brief logs, one or more processes each): tests run, passed, skipped, and the
    failed tests by name."""
    print("| log | ran | passed | skipped | failed |")
    print("|---|---|---|---|---|")
    for path in paths:
        text = open(path, encoding="utf-8").read()
        count = lambda pattern: sum(int(n) for n in re.findall(pattern, text, re.M))
        failed = sorted(set(re.findall(r"^\[  FAILED  \] (\S+) \(", text, re.M)))
        ran, passed = count(r"^\[==========\] (\d+) tests? from"), count(r"^\[  PASSED  \] (\d+) tests?")
        skipped = count(r"^\[  SKIPPED \] (\d+) tests?")
        print(f"| `{os.path.basename(path)}` | {ran} | {passed} | {skipped} | {', '.join(failed) if failed else '–'} |")


def label_stress(directory):
    """tests/label_stress.cpp's runs (logs named PATTERN_labelsL_syncS_rR_P.log: pattern, labels a
    submission, the validation layer's synchronization checks, round, process): the submissions each made
    (its last progress line, or all), its seconds, and how it ended (glibc's heap message, an uncaught
    std::bad_alloc, or the signal)."""
    name = re.compile(r"(\w+?)_labels(\d+)_sync(\d)_r(\d+)_(\d+)\.log$")
    print("| pattern | labels a submission | synchronization checks | run | submissions | s | outcome |")
    print("|---|---|---|---|---|---|---|")
    for path in sorted(os.listdir(directory)):
        m = name.match(path)
        if not m:
            continue
        text = open(os.path.join(directory, path), encoding="utf-8").read()
        done = max([int(n) for n in re.findall(r"^(\d+) submissions$", text, re.M)] or [0])
        seconds = re.findall(r"^([\d.]+) s$", text, re.M)
        rc = int(re.findall(r"^rc=(\d+)$", text, re.M)[-1])
        heap = re.findall(r"^(malloc\S*\(\): .*|free\(\): .*|double free.*|corrupted .*)$", text, re.M) + [
            f"{m} thrown" for m in re.findall(r"^  what\(\):\s+(std::bad_alloc)$", text, re.M)]
        signal = {134: "SIGABRT", 139: "SIGSEGV"}.get(rc, f"exit {rc}")
        outcome = "clean (0 validation messages)" if rc == 0 and "all submitted, 0 validation" in text else (
            f"{signal}: {heap[0]}" if heap else signal)
        reached = f"{done:,}" if rc == 0 else f"{done:,}–{done + 10000:,}"
        print(f"| {m[1]} | {m[2]} | {'on' if m[3] == '1' else 'off'} | {m[4]}.{m[5]} | {reached} | "
              f"{float(seconds[-1]):.0f} | {outcome} |")


def refit(path):
    """A deforming mesh's cost a frame (gi-bench --refit): the device refit against creating the scene anew."""
    names = {"rayquery": "ray queries (+ compute BVH)", "compute": "compute"}
    print("| backend | triangles | refit, CPU ms | refit, GPU ms | rebuild, CPU ms | rebuild, GPU ms | rebuild ÷ refit |")
    print("|---|---|---|---|---|---|---|")
    for r in rows(path):
        refit_ms = float(r["refit_cpu_ms"]) + float(r["refit_gpu_ms"])
        rebuild_ms = float(r["rebuild_cpu_ms"]) + float(r["rebuild_gpu_ms"])
        print(f"| {names[r['backend']]} | {int(r['triangles']):,} | {float(r['refit_cpu_ms']):.2f} | "
              f"{float(r['refit_gpu_ms']):.2f} | {float(r['rebuild_cpu_ms']):.1f} | {float(r['rebuild_gpu_ms']):.1f} | "
              f"{rebuild_ms / refit_ms:.0f}× |")


def pass_times(pairs):
    """Each method's passes, ms a frame, per configuration (args: NAME DIR ...; underscores in names are spaces).
    DIR may be several runs of one configuration, comma-separated: each pass's median over them."""
    runs = [(name.replace("_", " "), {method: r for (method, _), r in median_runs(directory).items()})
            for name, directory in named(pairs)]
    print("| method | pass | " + " | ".join(name for name, _ in runs) + " |")
    print("|---|---|" + "---|" * len(runs))
    methods = list(dict.fromkeys(m for _, byMethod in runs for m in byMethod))
    for method in methods:
        passes = {}
        for name, byMethod in runs:
            for item in byMethod[method]["pass_ms"].split(";") if method in byMethod else []:
                label, ms = item.split(":")
                passes.setdefault(label, {})[name] = float(ms)
        for label, times in passes.items():
            cells = " | ".join(f"{times[name]:.1f}" if name in times else "–" for name, _ in runs)
            print(f"| {method} | {label} | {cells} |")


def refit_rebuild(path):
    """The update that finds a level degraded (gi-bench --refit-rebuild): CPU ms of a refit, of the update
    that rebuilds in it, and off thread of the update that starts the rebuild and the one that installs it."""
    print("| triangles | refit update ms | rebuilt in the update, ms | off thread: starting update, ms | "
          "installing update, ms | updates between | start to install, ms |")
    print("|---|---|---|---|---|---|---|")
    for r in rows(path):
        print(f"| {int(r['triangles']):,} | {float(r['refit_update_ms']):.2f} | {float(r['rebuild_update_ms']):.1f} | "
              f"{float(r['start_update_ms']):.2f} | {float(r['install_update_ms']):.1f} | "
              f"{r['updates_until_installed']} | {float(r['start_to_install_ms']):.0f} |")


def refit_quality(path):
    """A folded grid's level refit against built anew (gi-bench --refit's second table): cost ratio, camera Mrays/s."""
    names = {"rayquery": "ray queries (BLAS updated / built)", "compute": "compute"}
    print("| backend | fold | cost ratio (refit ÷ built) | refit Mrays/s | built anew Mrays/s | refit ÷ built |")
    print("|---|---|---|---|---|---|")
    for r in rows(path):
        refit_rate, built_rate = float(r["refit_primary_mrays"]), float(r["built_primary_mrays"])
        print(f"| {names[r['backend']]} | {float(r['fold']):.1f} | {float(r['cost_ratio']):.2f} | {refit_rate:.2f} | "
              f"{built_rate:.2f} | {refit_rate / built_rate:.2f} |")


def error_at_frames(pairs, ks=(1, 4, 8, 32, 64)):
    """Final / indirect MSE after frame k of each run's series, its light at 32 and 64, its ms (args: NAME DIR ...)."""
    print("| scene | method | " + " | ".join(f"k = {k}" for k in ks) + " | light at k = 32 / 64 | frame ms |")
    print("|---|---|" + "---|" * len(ks) + "---|---|")
    for name, directory in named(pairs):
        series = rows(f"{directory}/series.csv")
        for result in rows(f"{directory}/results.csv"):
            mine = {int(r["frame"]): r for r in series if r["label"] == result["label"]}
            errors = " | ".join(f"{float(mine[k]['mse']):.2e} / {float(mine[k]['mse_indirect']):.2e}" for k in ks)
            print(f"| {name} | {result['method']} | {errors} | {float(mine[32]['energy_indirect']):.3f} / "
                  f"{float(mine[64]['energy_indirect']):.3f} | {float(result['total_ms']):.0f} |")


def hpsf_frames(pairs, ks=(1, 4, 8, 32)):
    """Final-image MSE after frame k per eviction policy and sspsf beside it (args: NAME DIR ...)."""
    policy = {"hpsf spp=1 hpsf.eviction=0": "hpsf, strict", "hpsf spp=1 hpsf.eviction=1": "hpsf, aging", "sspsf spp=1": "sspsf"}
    print("| scene | method | " + " | ".join(f"k = {k}" for k in ks) + " | hash occupancy |")
    print("|---|---|" + "---|" * len(ks) + "---|")
    for name, directory in named(pairs):
        series = rows(f"{directory}/series.csv")
        for result in rows(f"{directory}/results.csv"):
            mine = {int(r["frame"]): r for r in series if r["label"] == result["label"]}
            occupancy = float(result["hash_occupancy"])
            print(f"| {name} | {policy[result['label']]} | " + " | ".join(f"{float(mine[k]['mse']):.2e}" for k in ks) +
                  f" | {f'{100 * occupancy:.1f}%' if result['method'] != 'sspsf' else '–'} |")


def pass_ms(row, name):
    return next(float(x.split(":")[1]) for x in row["pass_ms"].split(";") if x.startswith(name + ":"))


def sweep(key, pairs):
    """A setting swept per method (args: KEY NAME DIR ...): final relMSE per value and against the first,
    the flicker and the composite pass's ms from the first value to the second, one scene after another."""
    header = None
    for name, directory in named(pairs):
        by_method = {}
        for r in rows(f"{directory}/results.csv"):
            value = r["label"].split(f"{key}=")[1].split()[0]
            by_method.setdefault(r["method"], {})[value] = r
        values = list(next(iter(by_method.values())).keys())
        if header is None:
            header = values
            print(f"| scene | method | " + " | ".join(f"{key} = {v}" for v in values) +
                  f" | flicker {values[0]} → {values[1]} | composite ms {values[0]} → {values[1]} |")
            print("|---|---|" + "---|" * (len(values) + 2))
        for method, runs in by_method.items():
            first = float(runs[values[0]]["relmse"])
            cells = [f"{first:.3e}"] + [f"{float(runs[v]['relmse']):.3e} ({float(runs[v]['relmse']) / first:.2f}×)"
                                        for v in values[1:]]
            a, b = runs[values[0]], runs[values[1]]
            flicker = f"{float(a['flicker_ratio']):.2f} → {float(b['flicker_ratio']):.2f}" if a["flicker_ratio"] else "–"
            print(f"| {name.replace('_', ' ')} | {method} | " + " | ".join(cells) + f" | {flicker} | "
                  f"{pass_ms(a, 'composite'):.2f} → {pass_ms(b, 'composite'):.2f} |")


def sweep_passes(key, prefix, pairs):
    """A setting swept (args: KEY PREFIX NAME DIR ...): per scene (and method, where a run has several) and value, the final and
    indirect MSE (the mean over the run's frames) against the first value's, the flicker of a camera-path run
    (its frame-to-frame change against the references'), and the ms per frame of the passes whose names
    start with PREFIX (the passes the setting changes)."""
    print(f"| scene | {key} | MSE (final) | against the first | MSE (indirect) | against the first | flicker | "
          f"{prefix}* ms |")
    print("|---|---|---|---|---|---|---|---|")
    for name, directory in named(pairs):
        runs = rows(f"{directory}/results.csv")
        several = len({r["method"] for r in runs}) > 1  # then each method against its own first value
        first = {}
        for r in runs:
            value = r["label"].split(f"{key}=")[1].split()[0]
            final, indirect = float(r["mse"]), float(r["mse_indirect"])
            base = first.setdefault(r["method"], (final, indirect))
            ms = sum(float(x.split(":")[1]) for x in r["pass_ms"].split(";") if x.startswith(prefix))
            flicker = f"{float(r['flicker_ratio']):.2f}" if r["flicker_ratio"] else "–"
            label = f"{name} {r['method']}" if several else name
            print(f"| {label} | {value} | {final:.3e} | {final / base[0]:.2f}× | {indirect:.3e} | "
                  f"{indirect / base[1]:.2f}× | {flicker} | {ms:.2f} |")


def seed_means(key, prefix, pairs):
    """A setting swept over several seeds (args: KEY PREFIX NAME DIR ...; runs swept with seed=... and KEY=...;
    KEY may name several settings joined by '+', each value then theirs joined by ', '): per scene, method and
    value, the final MSE's mean over the seeds (each run's the mean over its frames), its smallest and largest,
    the mean against the first value's, and the ms per frame and of the passes whose names start with PREFIX,
    the seeds' medians."""
    keys = key.split("+")
    print(f"| scene | method | {', '.join(keys)} | MSE (final), mean | seeds' range | against the first | ms/frame | "
          f"{prefix}* ms |")
    print("|---|---|---|---|---|---|---|---|")
    for name, directory in named(pairs):
        grouped = {}
        for r in rows(f"{directory}/results.csv"):
            value = ", ".join(r["label"].split(f"{k}=")[1].split()[0] for k in keys)
            grouped.setdefault(r["method"], {}).setdefault(value, []).append(r)
        for method, by_value in grouped.items():
            first = None
            for value, runs in by_value.items():
                mse = [float(r["mse"]) for r in runs]
                mean = sum(mse) / len(mse)
                first = first or mean
                ms = statistics.median_high(float(r["total_ms"]) for r in runs)
                passes = statistics.median_high(
                    sum(float(x.split(":")[1]) for x in r["pass_ms"].split(";") if x.startswith(prefix)) for r in runs)
                print(f"| {name.replace('_', ' ')} | {method} | {value} | {mean:.3e} | {min(mse):.3e}–{max(mse):.3e} | "
                      f"{mean / first:.2f}× | {ms:.2f} | {passes:.2f} |")


def sky_cap(path):
    """The sky tests' output (args: FILE: EmissiveSamplerTest.ReservoirsWeighTheSkyByItsMeasuredVisibility's
    printed lines under '== cap N' headers, one run of the test with reservoirs.sky_max_history at N each):
    per cap and scene, the mean against NEE's, the worst block, and the MSE against the sky left to NEE at
    frame 16 and over 64 accumulated frames."""
    print("| reservoirs.sky_max_history | scene | mean against NEE's | worst 8×8 block | frame 16 against the sky "
          "left to NEE | 64 frames accumulated |")
    print("|---|---|---|---|---|---|")
    pattern = re.compile(r"^(.*): mean ([-+][0-9.]+)% of NEE's, worst 8x8 block ([0-9.]+)%.*frame 16 \S+ against "
                         r"\S+ \(([0-9.]+)x\), 64 frames accumulated \S+ against \S+ \(([0-9.]+)x\)")
    cap = None
    for line in open(path):
        if line.startswith("== cap "):
            cap = line.split()[2]
        elif match := pattern.match(line):
            scene, mean, worst, frame, accumulated = match.groups()
            print(f"| {cap} | {scene} | {mean}% | {worst}% | {frame}× | {accumulated}× |")


def configurations(pairs):
    """Runs of one scene in several configurations against the same references (args: NAME DIR ...): per
    run and method, GPU ms per frame, final MSE, indirect MSE and flicker against the first run's."""
    runs = [(name, {r["method"]: r for r in rows(f"{directory}/results.csv")}) for name, directory in named(pairs)]
    first = runs[0][1]
    print("| configuration | method | ms/frame | MSE (final) | against the first | MSE (indirect) | flicker |")
    print("|---|---|---|---|---|---|---|")
    for name, by_method in runs:
        for method, r in by_method.items():
            flicker = f"{float(r['flicker_ratio']):.2f}" if r["flicker_ratio"] else "–"
            print(f"| {name.replace('_', ' ')} | {method} | {float(r['total_ms']):.1f} | {float(r['mse']):.3e} | "
                  f"{float(r['mse']) / float(first[method]['mse']):.2f}× | {float(r['mse_indirect']):.3e} | {flicker} |")


def coldstart(before_csv, after_csv):
    def table(path):
        return {(r["traversal"], r["scene"], r["method"]): float(r["wall_s"]) for r in rows(path)}
    before, after = table(before_csv), table(after_csv)
    scenes = list(dict.fromkeys(k[1] for k in after))
    methods = list(dict.fromkeys(k[2] for k in after))
    for traversal in dict.fromkeys(k[0] for k in after):
        print(f"\n{traversal} traversal: seconds, before → after\n")
        print("| method | " + " | ".join(scenes) + " |")
        print("|---|" + "---|" * len(scenes))
        for m in methods:
            cells = []
            for sc in scenes:
                b, a = before.get((traversal, sc, m)), after.get((traversal, sc, m))
                cells.append(f"{b:.1f} → **{a:.1f}**" if b is not None and a is not None else "–")
            print(f"| {m} | " + " | ".join(cells) + " |")
        worst = max(v for k, v in after.items() if k[0] == traversal)
        worst_before = max(v for k, v in before.items() if k[0] == traversal)
        print(f"\nSlowest first frame: {worst_before:.1f} s before, {worst:.1f} s after.")


def warm(before_dir, after_dir):
    scenes = ("cornell", "sponza", "conference")
    print("Bare rays, diffuse Mrays/s (fraction of Embree's), before → after:\n")
    print("| scene | backend | before | after |")
    print("|---|---|---|---|")
    for sc in scenes:
        b = {r["backend"]: r for r in rows(f"{before_dir}/warm_{sc}/rays.csv")}
        a = {r["backend"]: r for r in rows(f"{after_dir}/warm_{sc}/rays.csv")}
        for backend in a:
            if backend == "embree_cpu":
                continue
            cell = lambda r: f"{float(r['diffuse_mrays']):.2f} ({float(r['diffuse_of_embree']):.2f})"
            print(f"| {sc} | {backend} | {cell(b[backend]) if backend in b else '–'} | {cell(a[backend])} |")
    print("\nFrame time at 320×180, 1 spp, ms (median of 4 frames after 2), before → after:\n")
    labels = list(dict.fromkeys(r["label"] for r in rows(f"{after_dir}/warm_cornell/results.csv")))
    print("| method | " + " | ".join(scenes) + " |")
    print("|---|" + "---|" * len(scenes))
    for label in labels:
        cells = []
        for sc in scenes:
            b = {r["label"]: r for r in rows(f"{before_dir}/warm_{sc}/results.csv")}.get(label)
            a = {r["label"]: r for r in rows(f"{after_dir}/warm_{sc}/results.csv")}.get(label)
            cells.append(f"{float(b['total_ms']):.1f} → **{float(a['total_ms']):.1f}**" if a and b else "–")
        print(f"| {label} | " + " | ".join(cells) + " |")


def programs(paths):
    import json
    print("| method | program: first dispatch, ms | wall s |")
    print("|---|---|---|")
    for path in paths:
        d = json.load(open(path))
        cells = ", ".join(f"{k} {v:.0f}" for k, v in sorted(d["program_first_dispatch_ms"].items(), key=lambda kv: -kv[1]))
        print(f"| {d['method']} | {cells} | {d['wall_seconds']:.1f} |")


def switch(directory):
    print("| switch | frames readying | switched at frame | longest frame after the request, ms | median frame, ms |")
    print("|---|---|---|---|---|")
    for mode, name in (("readied", "readied off the frame (default)"), ("in_frame", "in the frame (--switch-in-frame)")):
        r = rows(f"{directory}/{mode}/benchmark.csv")
        body = r[30:-2]  # from the request on; the last two are timed at exit
        at = next((int(x["frame"]) for x in r if x["method"] != r[0]["method"]), None)
        ms = sorted(float(x["cpu_ms"]) for x in body)
        print(f"| {name} | {sum(1 for x in r if x['readying'] == '1')} | {at} | {ms[-1]:.0f} | {ms[len(ms) // 2]:.1f} |")


def speedups(method, directories):
    print("| scene | spp | final | indirect |")
    print("|---|---|---|---|")
    for d in directories:
        for r in rows(f"{d}/results.csv"):
            if r["method"] != method:
                continue
            print(f"| {d.rstrip('/').split('/')[-1]} | {r['spp']} | {float(r['equal_error_speedup']):.1f}× | "
                  f"{float(r['equal_error_speedup_indirect']):.1f}× |")


def history(pairs):
    """The demo's benchmark CSVs (scripts/bench budget_history: NAME CSV ...): rays and the frames of
    history behind the median pixel at a few frames of each run."""
    ks = (1, 10, 20, 40)
    print("| run | " + " | ".join(f"rays, frame {k}" for k in (1, 40)) + " | "
          + " | ".join(f"history frames at {k}" for k in ks) + " |")
    print("|---|" + "---|" * (2 + len(ks)))
    for name, path in named(pairs):
        by = {int(r["frame"]) + 1: r for r in rows(path)}
        print(f"| {name} | " + " | ".join(by[k]["rays"] for k in (1, 40)) + " | "
              + " | ".join(by[k]["history_frames"] for k in ks) + " |")


def calls(path, first):
    """The demo's benchmark CSV (scripts/bench frames_in_flight): per frame from FIRST on, the demo's own
    fence and idle waits and Vulkan creations, and the module's device allocations."""
    steady = [r for r in rows(path) if int(r["frame"]) >= int(first)]
    def spread(key):
        values = [int(r[key]) for r in steady]
        return f"{min(values)} / {sum(values) / len(values):.2f} / {max(values)}"
    print("| frames | fence waits a frame (min / mean / max) | idle waits | creations | module device allocations |")
    print("|---|---|---|---|---|")
    print(f"| {steady[0]['frame']}–{steady[-1]['frame']} | {spread('fence_waits')} | {spread('idle_waits')} | "
          f"{spread('creations')} | {spread('module_allocations')} |")


def demo(directory):
    print("| configuration | ms/frame | relMSE final | relMSE indirect | relMSE × ms |")
    print("|---|---|---|---|---|")
    for r in rows(f"{directory}/results.csv"):
        print(f"| {r['label']} | {float(r['total_ms']):.1f} | {float(r['relmse']):.3e} | "
              f"{float(r['relmse_indirect']):.3e} | {float(r['relmse']) * float(r['total_ms']):.4f} |")


BLOCK = re.compile(r"(<!-- generated: results_tables\.py ([^>]*?) -->\n)(.*?)(<!-- end generated -->)", re.S)


def render(args):
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        run(args)
    return out.getvalue().strip() + "\n"


def blocks(path, write):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    text = open(path, encoding="utf-8").read()
    stale = []
    def fresh(m):
        args = m.group(2).split()
        here = os.getcwd()
        os.chdir(root)
        try:
            table = render(args)
        finally:
            os.chdir(here)
        if m.group(3) != table:
            stale.append(m.group(2))
        return m.group(1) + table + m.group(4)
    new = BLOCK.sub(fresh, text)
    if write and new != text:
        open(path, "w", encoding="utf-8").write(new)
    return stale, len(BLOCK.findall(text))


# Each table kind and how it takes its arguments (the words after the kind in a generated block's marker).
KINDS = {
    "trade": lambda a: trade(a[0]),
    "frames": lambda a: frames(a[0], a[1:]),
    "indirect": lambda a: indirect(a[0], a[1]),
    "move": lambda a: move(a[0]),
    "walk": lambda a: walk(a[0], a[1] if len(a) > 1 else None),
    "refit": lambda a: refit(a[0]),
    "refit_quality": lambda a: refit_quality(a[0]),
    "refit_rebuild": lambda a: refit_rebuild(a[0]),
    "bench_log": bench_log,
    "device_memory": lambda a: device_memory(a[0], a[1]),
    "light_samplers": lambda a: light_samplers(a[0]),
    "hash_map": hash_map,
    "hash_live": lambda a: hash_live(a[0], a[1:]),
    "gtest_logs": gtest_logs,
    "label_stress": lambda a: label_stress(a[0]),
    "walk_best": walk_best,
    "hashdirect": hashdirect,
    "spikes": lambda a: spikes(a[0], a[1], a[2:]),
    # A table a test wrote, committed as it came (tests/extremes_test.cpp: extremes.md).
    "file": lambda a: print(open(a[0], encoding="utf-8").read().strip()),
    "memory": lambda a: memory(*a),
    "dynamic_resolution": lambda a: dynamic_resolution(a[0]),
    "gif_order": gif_order,
    "filter_cost": lambda a: filter_cost(a[0]),
    "aaf_cost": aaf_cost,
    "aaf_fig10": aaf_fig10,
    "settings_at_frame": lambda a: settings_at_frame(a[0], a[1:]),
    "deviations": deviations,
    "light_at_frame": lambda a: light_at_frame(a[0], a[1], a[2:]),
    "hash_passes": hash_passes,
    "per_frame": lambda a: per_frame(a[0], a[1]),
    "pathtracer": lambda a: pathtracer(a[0]),
    "lights": lambda a: lights(a[0]),
    "samplers": lambda a: samplers(a[0]),
    "emissive_reservoirs": lambda a: emissive_reservoirs(a[0]),
    "configurations": lambda a: configurations(a),
    "sky_cap": lambda a: sky_cap(a[0]),
    "pass_times": lambda a: pass_times(a),
    "ab": lambda a: ab(a[0], a[1], a[2], a[3:]),
    "ab_mean": lambda a: ab(a[0], a[1], a[2], a[3:], over_settings=True),
    "moving": lambda a: moving(a[0], int(a[1]), a[2:]),
    "rays": lambda a: rays(a[0]),
    "error_at_frames": error_at_frames,
    "hpsf_frames": hpsf_frames,
    "sweep": lambda a: sweep(a[0], a[1:]),
    "sweep_passes": lambda a: sweep_passes(a[0], a[1], a[2:]),
    "seed_means": lambda a: seed_means(a[0], a[1], a[2:]),
    "goal_sweep": lambda a: goal_sweep(a[0], a[1], a[2:]),
    "coldstart": lambda a: coldstart(a[0], a[1]),
    "programs": programs,
    "switch": lambda a: switch(a[0]),
    "warm": lambda a: warm(a[0], a[1]),
    "speedups": lambda a: speedups(a[0], a[1:]),
    "demo": lambda a: demo(a[0]),
    "history": history,
    "calls": lambda a: calls(a[0], a[1]),
}


def run(argv):
    kind = argv[0]
    if kind in KINDS:
        KINDS[kind](argv[1:])
    elif kind in ("check", "write"):
        failed = False
        for path in argv[1:]:
            stale, count = blocks(path, kind == "write")
            for args in stale:
                print(f"{path}: the table of 'results_tables.py {args}' differs from its data"
                      + (" (rewritten)" if kind == "write" else ""))
            failed |= bool(stale) and kind == "check"
            print(f"{path}: {count} generated tables, {len(stale)} differing")
        sys.exit(1 if failed else 0)
    else:
        sys.exit(f"results_tables.py: unknown table '{kind}'")


if __name__ == "__main__":
    run(sys.argv[1:])
