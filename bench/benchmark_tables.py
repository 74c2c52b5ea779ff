#!/usr/bin/python3
"""The tables of bench/run_benchmarks.sh (Markdown, for BENCHMARKS.md) and its combined
report.html (the tables, then each dataset's page from `fine2coarse evaluate --report`).

    /usr/bin/python3 bench/benchmark_tables.py ROWS_TSV WORK_DIR
"""
import html
import json
import os
import re
import statistics
import sys
from collections import OrderedDict, defaultdict


def load(path):
    try:
        return json.load(open(path))
    except (OSError, ValueError):
        return None


def main():
    rows_path, work = sys.argv[1:3]
    runs = OrderedDict()  # (kind, label) -> {variant: record}
    failed = []
    for line in open(rows_path):
        kind, label, variant, keep = line.rstrip("\n").split("\t")
        slot = runs.setdefault((kind, label), OrderedDict())
        if variant == "open3d-failed" or keep == "failed":
            failed.append(f"{label}, {variant}: {keep}")
            if variant == "open3d-failed":
                slot["open3d"] = {"failed": keep}
            continue
        rec = {"eval": load(f"{keep}/eval.json")}
        if variant == "open3d":
            rec["peer"] = load(f"{keep}/peer.json")
        else:
            rec["run"] = load(f"{keep}/run.json")
            rec["eval_t0"] = load(f"{keep}/eval_t0.json")
        slot[variant] = rec

    out = []
    p = out.append
    ate = lambda r: r["eval"]["ate_m"]["rmse"] if r and r.get("eval") else float("nan")
    ate0 = lambda r: r["eval_t0"]["ate_m"]["rmse"] if r and r.get("eval_t0") else float("nan")
    corr = lambda e: e["correspondences"]["distance_m"]["rmse"] if e and "correspondences" in e else float("nan")
    refine_ms = lambda r: ((r["run"]["stages"].get("refine") or {}).get("ms_per_frame", float("nan"))
                           if r and r.get("run") else float("nan"))
    mib = lambda b: b / 2**20
    f4 = lambda v: "-" if v != v else f"{v:.4f}"
    f3 = lambda v: "-" if v != v else f"{v:.3f}"

    real = [(label, v) for (kind, label), v in runs.items() if kind == "real"]
    sims = [(label, v) for (kind, label), v in runs.items() if kind == "sim"]

    if real:
        p("### Real sequences (ATE RMSE against the ground truth, m; time end to end: odometry, refinement, mesh)\n")
        p("| sequence | frames | T0 | fine2coarse | Open3D | fine2coarse time | Open3D time | Open3D time / ours "
          "| peak memory, ours / Open3D (MiB) |")
        p("|---|---|---|---|---|---|---|---|---|")
        for label, v in real:
            d = v.get("default")
            if not d or not d.get("run"):
                p(f"| {label} | | failed | | | | | | |")
                continue
            run = d["run"]
            n, wall = run["frames"], run["total_wall_s"]
            peer = v.get("open3d")
            if peer and "peer" in peer:
                pj = peer["peer"]
                o_ate, o_time = f4(ate(peer)), f"{pj['seconds']:.1f} s ({pj['seconds'] / pj['frames']:.2f} s/frame)"
                ratio, o_mem = f"{pj['seconds'] / wall:.0f}x", f"{mib(pj['peak_memory_bytes']):.0f}"
            elif peer:
                o_ate, o_time, ratio, o_mem = "failed", "", "", ""
            else:
                o_ate, o_time, ratio, o_mem = "not run", "", "", ""
            p(f"| {label} | {n} | {f4(ate0(d))} | **{f4(ate(d))}** | {o_ate} | {wall:.1f} s ({n / wall:.1f} frames/s) "
              f"| {o_time} | {ratio} | {mib(run['peak_memory_bytes']):.0f} / {o_mem or '-'} |")
        p("")
        p("### Ablations on the real sequences (ATE RMSE, m; refinement ms per frame, mean over the sequences)\n")
        labels = [label for label, _ in real]
        p("| variant | " + " | ".join(labels) + " | refinement ms/frame |")
        p("|---|" + "---|" * (len(labels) + 1))
        variants = [k for k in real[0][1].keys() if k != "open3d"]
        for name in variants:
            cells = [f4(ate(v.get(name))) for _, v in real]
            ms = [refine_ms(v.get(name)) for _, v in real]
            ms = [m for m in ms if m == m]
            ms_cell = f"{statistics.mean(ms):.1f}" if ms else "-"
            p(f"| {name} | " + " | ".join(cells) + f" | {ms_cell} |")
        p("")

    if sims:
        by_scene = defaultdict(list)
        for label, v in sims:
            by_scene[label.rsplit("-", 1)[0]].append(v)
        mean = lambda xs: statistics.mean(xs) if xs else float("nan")
        p("### Simulated walks (means over the seeds; ratio = T0 / fine2coarse)\n")
        p("| scene | walks | T0 ATE | fine2coarse ATE | ratio | T0 corr. RMSE | fine2coarse corr. RMSE | ratio "
          "| end to end frames/s | Open3D ATE | Open3D corr. RMSE |")
        p("|---|---|---|---|---|---|---|---|---|---|---|")
        for scene, vs in by_scene.items():
            ds = [v["default"] for v in vs if v.get("default") and v["default"].get("run")]
            a0, a1 = mean([ate0(d) for d in ds]), mean([ate(d) for d in ds])
            c0, c1 = mean([corr(d["eval_t0"]) for d in ds]), mean([corr(d["eval"]) for d in ds])
            fps = mean([d["run"]["frames"] / d["run"]["total_wall_s"] for d in ds])
            peers = [v["open3d"] for v in vs if v.get("open3d") and "peer" in v["open3d"]]
            o_a = f3(mean([ate(x) for x in peers])) if peers else "not run"
            o_c = f3(mean([corr(x["eval"]) for x in peers])) if peers else ""
            p(f"| {scene} | {len(ds)} | {f3(a0)} | **{f3(a1)}** | {a0 / a1:.1f}x | {f3(c0)} | **{f3(c1)}** | "
              f"{c0 / c1:.1f}x | {fps:.1f} | {o_a} | {o_c} |")
        p("")
        # Each scan on its own: the refinement must beat T0 on every one, not on the mean.
        p("Each scan (ATE and ground-truth correspondence RMSE, m):\n")
        p("| scan | T0 ATE | fine2coarse ATE | T0 corr. RMSE | fine2coarse corr. RMSE |")
        p("|---|---|---|---|---|")
        worse = []
        for label, v in sims:
            d = v.get("default")
            if not d or not d.get("run"):
                p(f"| {label} | failed | | | |")
                continue
            if not ate(d) < ate0(d):
                worse.append(label)
            p(f"| {label} | {f4(ate0(d))} | {f4(ate(d))} | {f4(corr(d['eval_t0']))} | {f4(corr(d['eval']))} |")
        p("")
        p(f"Refined ATE below T0's on {len(sims) - len(worse)} of {len(sims)} scans"
          + (f" (not on {', '.join(worse)})." if worse else ".") + "\n")
        p("### Ablations on the simulated walks (means over the seeds)\n")
        scenes = list(by_scene.keys())
        p("| variant | " + " | ".join(f"{s} ATE | {s} corr. RMSE" for s in scenes) + " | refinement ms/frame |")
        p("|---|" + "---|" * (2 * len(scenes) + 1))
        variants = [k for k in sims[0][1].keys() if k != "open3d"]
        for name in variants:
            cells, ms = [], []
            for s in scenes:
                rs = [v.get(name) for v in by_scene[s] if v.get(name) and v[name].get("eval")]
                cells += [f3(mean([ate(r) for r in rs])), f3(mean([corr(r["eval"]) for r in rs]))]
                ms += [refine_ms(r) for r in rs]
            p(f"| {name} | " + " | ".join(cells) + f" | {mean([m for m in ms if m == m]):.1f} |")
        p("")
        p("### Correspondence error against frame distance (the paper's Fig. 9; median per gap bin, m, mean over the "
          "seeds)\n")
        gaps = OrderedDict()
        for s in scenes:
            for v in by_scene[s]:
                d = v.get("default")
                if not d or not d.get("eval"):
                    continue
                for which, e in (("T0", d["eval_t0"]), ("fine2coarse", d["eval"])):
                    for b in (e.get("correspondences") or {}).get("by_frame_gap", []):
                        gaps.setdefault(b["gap_from"], defaultdict(list))[(s, which)].append(b["median_m"])
        cols = [(s, w) for s in scenes for w in ("T0", "fine2coarse")]
        p("| frame gap | " + " | ".join(f"{s} {w}" for s, w in cols) + " |")
        p("|---|" + "---|" * len(cols))
        for g in sorted(gaps):
            p(f"| {g if g == 1 else f'{g}-{2 * g - 1}'} | " + " | ".join(f3(mean(gaps[g][c])) for c in cols) + " |")
        p("")
    if failed:
        p("Failed runs: " + "; ".join(failed) + "\n")

    md = "\n".join(out)
    tmp = os.path.join(work, "tables.md.tmp")
    open(tmp, "w").write(md)
    os.replace(tmp, os.path.join(work, "tables.md"))
    print(md)

    # The combined page: the tables, then each dataset's own page (its <body>), in one file.
    body = []
    table = []
    for line in out + [""]:
        if line.startswith("|"):
            table.append(line)
            continue
        if table:
            cells = lambda l: [c.strip() for c in l.strip("|").split("|")]
            t = "<table><tr>" + "".join(f"<th>{html.escape(c)}</th>" for c in cells(table[0])) + "</tr>\n"
            for l in table[2:]:
                t += "<tr>" + "".join("<td>" + re.sub(r"\*\*(.*?)\*\*", r"<b>\1</b>", html.escape(c)) + "</td>"
                                      for c in cells(l)) + "</tr>\n"
            body.append(t + "</table>")
            table = []
        if line.startswith("### "):
            body.append(f"<h2>{html.escape(line[4:])}</h2>")
        elif line:
            body.append(f"<p>{html.escape(line)}</p>")
    pages = []
    for (kind, label) in runs:
        path = os.path.join(work, "pages", label + ".html")
        if not os.path.exists(path):
            continue
        page = open(path).read()
        inner = page[page.index("<body>") + len("<body>"):page.rindex("</body>")]
        inner = re.sub(r"<h1>.*?</h1>", f"<h1 id=\"{html.escape(label)}\">{html.escape(label)}</h1>", inner, count=1)
        pages.append(f"<hr>\n{inner}")
        style = re.search(r"<style>.*?</style>", page, re.S)
    index = " | ".join(f"<a href=\"#{html.escape(l)}\">{html.escape(l)}</a>" for (_, l) in runs
                       if os.path.exists(os.path.join(work, "pages", l + ".html")))
    doc = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>fine2coarse benchmarks</title>\n"
           + (style.group(0) if pages else "") + "</head><body>\n<h1>fine2coarse benchmarks</h1>\n"
           + "\n".join(body) + f"\n<p>Datasets: {index}</p>\n" + "\n".join(pages) + "</body></html>\n")
    tmp = os.path.join(work, "report.html.tmp")
    open(tmp, "w").write(doc)
    os.replace(tmp, os.path.join(work, "report.html"))
    print(f"wrote {os.path.join(work, 'tables.md')} and {os.path.join(work, 'report.html')} "
          f"({len(doc) / 2**20:.1f} MiB)", file=sys.stderr)


if __name__ == "__main__":
    main()
