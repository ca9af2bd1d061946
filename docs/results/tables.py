#!/usr/bin/env python3
"""The Markdown tables of docs/results/README.md and plan.md, from the sweep CSVs.
usage: tables.py sweep SWEEP_CSV | tables.py plan PLAN_CSV [BUDGET_DB [REPEAT_CSV...]] | tables.py seeds SEEDS_CSV SWEEP_CSV
       | tables.py variations DISTANCE FABRIC_KIND CSV... | tables.py change CONFIGURATION BASELINE SWEEP_CSV
       | tables.py methods METHODS_CSV (bench/sweep_methods.json: every method against svbrdf's defaults)
       | tables.py colours COLOURS_CSV (bench/sweep_colours.json: colourways of one fabric, front- and back-lit)
       | tables.py volume VOLUME_CSV (bench/sweep_volume.json: knits as yarn volumes and as tubes, per distance)
       | tables.py choose METHODS_CSV (the README's table: each method at its defaults)
Medians leave non-finite figures out, as the chart does; a "blow-up" is a row whose
image held NaN (PSNR or flicker not finite) or radiance so large that PSNR < 0."""
import csv, math, re, statistics, sys

def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))

def num(text):
    try:
        return float(text)
    except ValueError:
        return math.nan

def finite(values):
    return [v for v in values if math.isfinite(v)]

def med(values, fmt):
    values = finite(values)
    return fmt % statistics.median(values) if values else "–"

STANDARD = ("flat0.near", "flat60.mid", "flat80.far", "sphere.mid")

def standard(scene):
    return scene.split(".", 1)[1] in STANDARD

def sweep(path):
    table = rows(path)
    order = []
    for r in table:
        if r["configuration"] not in order:
            order.append(r["configuration"])
    print("| configuration | scenes | PSNR dB | 1 − SSIM | frame ms | GPU ms | precompute s | precompute CPU s | asset KiB | flicker | blow-ups (of) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for c in order:
        mine = [r for r in table if r["configuration"] == c]
        std = [r for r in mine if standard(r["scene"])]
        svb = mine[0]["method"] == "svbrdf"
        blow = sum(1 for r in mine if not math.isfinite(num(r["psnr_db"])) or num(r["psnr_db"]) < 0 or math.isnan(num(r["flicker"])))
        col = lambda k: [num(r[k]) for r in std]
        print(f"| {c} | {len(std)} | {med(col('psnr_db'), '%.2f')} | {med(col('perceptual_error'), '%.3f')} | "
              f"{med(col('frame_ms'), '%.0f')} | {med(col('gpu_ms'), '%.0f') if svb else '–'} | "
              f"{med(col('precompute_seconds'), '%.1f') if svb else '–'} | "
              f"{med(col('precompute_cpu_seconds'), '%.1f') if svb else '–'} | "
              f"{med([v / 1024 for v in col('asset_bytes')], '%.0f') if svb else '–'} | "
              f"{med(col('flicker'), '%.4f')} | {blow} ({len(mine)}) |")
    print()
    groups = [("near (64 px tiles, 0°)", ("flat0.near",)), ("mid (16 px at 60°, sphere)", ("flat60.mid", "sphere.mid")),
              ("far (2 px at 80°)", ("flat80.far",))]
    configs = ["default", "reference-4", "reference-16", "reference-64", "level-none"]
    print("| distance | scenes | default svbrdf | reference-4 | reference-16 | reference-64 | svbrdf level-none |")
    print("|---|---|---|---|---|---|---|")
    for label, views in groups:
        cells = []
        n = 0
        for c in configs:
            sel = [r for r in table if r["configuration"] == c and r["scene"].split(".", 1)[1] in views]
            n = max(n, len(sel))
            col = lambda k: [num(r[k]) for r in sel]
            cells.append(f"{med(col('psnr_db'), '%.2f')} / {med(col('perceptual_error'), '%.3f')} / "
                         f"{med(col('flicker'), '%.3f')} / {med(col('frame_ms'), '%.0f')}")
        print(f"| {label} | {n} | " + " | ".join(cells) + " |")

SETTINGS = ("method", "method_settings", "spatial_resolution", "view_directions", "light_directions", "lobes", "lookup_table",
            "supersampling", "sampling_plane", "level_mode", "texel_filter", "msaa_samples", "lod_bias", "shading_rate")

def seed_means(tables):
    """(scene, settings) → mean PSNR over the distinct seeds in `tables`, as
    loom-lab plan --distill takes repeats (lab/sweep_distill.h)."""
    by_seed = {}
    for table in tables:
        for r in table:
            if r["method"] != "reference":
                by_seed.setdefault((r["scene"],) + tuple(r[k] for k in SETTINGS), {})[r["seed"]] = num(r["psnr_db"])
    return {key: (statistics.mean(v.values()), len(v)) for key, v in by_seed.items()}

def plan(path, budget=0.5, repeat_paths=()):
    """Plan against defaults per scene; with repeat CSVs (the same settings under
    other seeds), also the change of the seed means."""
    table = rows(path)
    means = seed_means([table] + [rows(p) for p in repeat_paths])
    mean_of = lambda r: means[(r["scene"],) + tuple(r[k] for k in SETTINGS)]
    by = {}
    for r in table:
        by.setdefault(r["scene"], {})[r["configuration"]] = r
    scenes = [s for s in by if "default" in by[s] and "plan" in by[s]]
    rec = []
    for s in scenes:
        d, p = by[s]["default"], by[s]["plan"]
        change = num(p["psnr_db"]) - num(d["psnr_db"])
        (dm, dn), (pm, pn) = mean_of(d), mean_of(p)
        rec.append(dict(scene=s, fabric=d["fabric"], d=d, p=p, change=change, mean_change=pm - dm, seeds=(dn, pn),
                        within=math.isfinite(change) and change >= -budget - 1e-9,
                        mean_within=math.isfinite(pm - dm) and pm - dm >= -budget - 1e-9,
                        t=num(p["precompute_cpu_seconds"]) / num(d["precompute_cpu_seconds"]),
                        b=num(p["asset_bytes"]) / num(d["asset_bytes"])))
    n = len(rec)
    ch = finite([r["change"] for r in rec])
    print(f"| plan within the {budget} dB budget (PSNR ≥ default − {budget} dB) | **{sum(r['within'] for r in rec)} of {n}** |")
    if repeat_paths:
        mch = finite([r["mean_change"] for r in rec])
        several = sum(min(r["seeds"]) > 1 for r in rec)
        print(f"| the same, PSNR the mean over the seeds measured ({several} scenes with more than one seed of both) | "
              f"**{sum(r['mean_within'] for r in rec)} of {n}** (median change {statistics.median(mch):+.2f} dB, worst {min(mch):+.2f}) |")
    print(f"| plan's asset smaller | **{sum(r['b'] < 1 for r in rec)} of {n}** (median ×{statistics.median([r['b'] for r in rec]):.2f}, worst ×{max(r['b'] for r in rec):.2f}) |")
    print(f"| plan's precompute CPU time smaller | {sum(r['t'] < 1 for r in rec)} of {n} (median ×{statistics.median([r['t'] for r in rec]):.2f}, worst ×{max(r['t'] for r in rec):.2f}) |")
    print(f"| median PSNR change | {statistics.median(ch):+.2f} dB (mean {statistics.mean(ch):+.2f}, worst {min(ch):+.2f}, best {max(ch):+.2f}) |")
    print()
    print("| fabric | within budget | median PSNR change | worst PSNR change | median CPU-time ratio | median bytes ratio |")
    print("|---|---|---|---|---|---|")
    fabrics = []
    for r in rec:
        if r["fabric"] not in fabrics:
            fabrics.append(r["fabric"])
    for f in fabrics:
        mine = [r for r in rec if r["fabric"] == f]
        print(f"| {f} | {sum(r['within'] for r in mine)} of {len(mine)} | {statistics.median([r['change'] for r in mine]):+.2f} dB | "
              f"{min(r['change'] for r in mine):+.2f} dB | ×{statistics.median([r['t'] for r in mine]):.3f} | ×{statistics.median([r['b'] for r in mine]):.3f} |")
    print()
    print("| scene | tile px | plan: method, texels, views, lobes, LUT, ss | precompute CPU s default → plan | bytes KiB default → plan | PSNR dB default → plan | change | within 0.5 dB | change of seed means (seeds) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rec:
        d, p = r["d"], r["p"]
        print(f"| {r['scene']} | {d['footprint_pixels'] and '%.0f' % num(d['footprint_pixels'])} | "
              f"{p['method']}, {p['spatial_resolution']}, {p['view_directions']}, "
              + (f"{p['lobes']}, {'on' if p['lookup_table'] == '1' else 'off'}" if p['method'] == 'svbrdf' else "–, –")
              + f", {p['supersampling']} | "
              f"{num(d['precompute_cpu_seconds']):.1f} → {num(p['precompute_cpu_seconds']):.1f} (×{r['t']:.2f}) | "
              f"{num(d['asset_bytes']) / 1024:.0f} → {num(p['asset_bytes']) / 1024:.0f} (×{r['b']:.2f}) | "
              f"{num(d['psnr_db']):.2f} → {num(p['psnr_db']):.2f} | {r['change']:+.2f} | {'yes' if r['within'] else '**no**'} | "
              f"{r['mean_change']:+.2f} ({r['seeds'][0]}, {r['seeds'][1]}) |")

SEEDS = ("seed2", "seed3")
VARIATIONS = ("res8-ss8", "res16-ss4", "res16", "dirs49", "dirs36", "lobes1", "lut-off", "dirs16")

def changes(table, configs, distance):
    """PSNR change against the table's defaults of `configs`' rows at `distance`."""
    base = {r["scene"]: num(r["psnr_db"]) for r in table if r["configuration"] == "default"}
    return [num(r["psnr_db"]) - base[r["scene"]] for r in table
            if r["configuration"] in configs and r["distance"] == distance and r["scene"] in base
            and math.isfinite(num(r["psnr_db"])) and math.isfinite(base[r["scene"]])]

def seeds(seeds_path, sweep_path):
    """How far PSNR moves against the defaults, per distance: under another seed
    (bench/sweep_seeds.json: nothing but the rays changes) and under each of the
    planner's variations (the standard sweep)."""
    print("| against the defaults | distance | scenes | mean abs. PSNR change dB | largest abs. change dB | changes beyond 0.5 dB |")
    print("|---|---|---|---|---|---|")
    seeded, swept = rows(seeds_path), rows(sweep_path)
    for label, table, configs in [("another seed (seed2, seed3)", seeded, SEEDS)] + [(v, swept, (v,)) for v in VARIATIONS]:
        for d in ("near", "mid", "far"):
            a = [abs(x) for x in changes(table, configs, d)]
            if a:
                print(f"| {label} | {d} | {len(a) // len(configs)} | {statistics.mean(a):.2f} | {max(a):.2f} | {sum(x > 0.5 for x in a)} of {len(a)} |")

def variations(distance, kind, paths):
    """Per scene at `distance` of fabric kind `kind` (all kinds: "any"), the
    defaults' seed mean and each variation's change of seed means, and per
    variation the worst: what the planner budgets, as loom-lab plan --distill
    takes it. A configuration named NAME-seedN is NAME under another seed; seedN
    alone is the defaults."""
    base = lambda name: re.sub(r"-?seed\d+$", "", name) or "default"
    psnr = {}
    for path in paths:
        for r in rows(path):
            if r["method"] == "svbrdf" and r["distance"] == distance and kind in ("any", r["fabric_kind"]):
                psnr.setdefault(r["scene"], {}).setdefault(base(r["configuration"]), {})[r["seed"]] = num(r["psnr_db"])
    shown = [v for v in VARIATIONS if any(v in by for by in psnr.values())]
    print("| scene | defaults dB: mean (seeds) | " + " | ".join(f"`{v}`" for v in shown) + " |")
    print("|---|---|" + "---|" * len(shown))
    worst = {v: math.inf for v in shown}
    for scene in sorted(psnr):
        by = psnr[scene]
        d = statistics.mean(by["default"].values())
        cells = []
        for v in shown:
            if v in by:
                change = statistics.mean(by[v].values()) - d
                worst[v] = min(worst[v], change)
                cells.append(f"{change:+.2f} ({len(by[v])})")
            else:
                cells.append("–")
        print(f"| {scene} | {d:.2f} ({len(by['default'])}) | " + " | ".join(cells) + " |")
    print("| **worst** | | " + " | ".join(f"**{worst[v]:+.2f}**" for v in shown) + " |")

def change(configuration, baseline, path):
    """PSNR of `configuration` against `baseline` on every scene both ran on: mean,
    median, how many scenes moved by more than 0.1 dB either way, and per distance
    the mean and the extremes (the figures quoted for level modes and texel filters)."""
    table = rows(path)
    base = {r["scene"]: num(r["psnr_db"]) for r in table if r["configuration"] == baseline}
    by_distance = {}
    for r in table:
        if r["configuration"] == configuration and r["scene"] in base:
            d = num(r["psnr_db"]) - base[r["scene"]]
            if math.isfinite(d):
                by_distance.setdefault(r["distance"], []).append((d, r["scene"]))
    every = [x for v in by_distance.values() for x in v]
    values = [d for d, _ in every]
    print(f"| {configuration} against {baseline} | scenes | mean dB | median dB | worst | best |")
    print("|---|---|---|---|---|---|")
    for label, v in [("all", every)] + [(d, by_distance[d]) for d in ("near", "mid", "far") if d in by_distance]:
        worst, best = min(v), max(v)
        print(f"| {label} | {len(v)} | {statistics.mean(d for d, _ in v):+.2f} | {statistics.median(d for d, _ in v):+.2f} | "
              f"{worst[0]:+.2f} ({worst[1]}) | {best[0]:+.2f} ({best[1]}) |")
    print(f"\nbetter by more than 0.1 dB on {sum(d > 0.1 for d in values)} scenes, worse on {sum(d < -0.1 for d in values)}")

# A scene's group: its variant (opposite, closeup) or its distance.
def group(scene):
    parts = scene.split(".")
    return parts[3] if len(parts) > 3 else parts[2]

def methods(path):
    table = rows(path)
    order, by = [], {}
    for r in table:
        if r["configuration"] not in order:
            order.append(r["configuration"])
        by[(r["configuration"], r["scene"])] = r
    first = ["default", "tabulated", "factored"]  # each method at its defaults, then the variations
    appearance = list(order)
    order.sort(key=lambda c: (first.index(c) if c in first else len(first), appearance.index(c)))
    scenes = sorted({r["scene"] for r in table if r["configuration"] == "default"})
    groups = ["near", "mid", "far", "opposite", "closeup"]
    print("| configuration | scenes | PSNR dB median (mean) | SSIM median | Δ PSNR vs svbrdf: median, worst, best | scenes > 0.5 dB worse | " +
          " | ".join("median %s" % g for g in groups) + " | asset MB median | frame ms median |")
    print("|---|---|---|---|---|---|" + "---|" * len(groups) + "---|---|")
    for c in order:
        mine = [s for s in scenes if (c, s) in by]
        psnr = [num(by[(c, s)]["psnr_db"]) for s in mine]
        ssim = [1 - num(by[(c, s)]["perceptual_error"]) for s in mine]
        delta = finite([num(by[(c, s)]["psnr_db"]) - num(by[("default", s)]["psnr_db"]) for s in mine])
        worse = sum(1 for d in delta if d < -0.5)
        per_group = [med([num(by[(c, s)]["psnr_db"]) for s in mine if group(s) == g], "%.2f") for g in groups]
        print("| %s | %d | %s (%.2f) | %s | %+.2f, %+.2f, %+.2f | %d | %s | %s | %s |" % (
            c, len(mine), med(psnr, "%.2f"), statistics.mean(finite(psnr)), med(ssim, "%.3f"),
            statistics.median(delta), min(delta), max(delta), worse, " | ".join(per_group),
            med([num(by[(c, s)]["asset_bytes"]) / 1e6 for s in mine], "%.2f"),
            med([num(by[(c, s)]["frame_ms"]) for s in mine], "%.0f")))

# Per configuration of bench/sweep_colours.json: PSNR front- and back-lit, per colourway,
# and the precompute seconds of each colourway's asset: a configuration with colour
# components loads the first colourway's asset for the others, so it reports the same
# seconds (its timing file) for all three.
def colours(path):
    table = rows(path)
    order = []
    for r in table:
        if r["configuration"] not in order:
            order.append(r["configuration"])
    fabrics = []
    for r in table:
        if r["fabric"] not in fabrics:
            fabrics.append(r["fabric"])
    print("| configuration | scenes | PSNR dB median: all | front-lit | back-lit | " +
          " | ".join(fabrics) + " | precompute s per colourway | asset MB | frame ms median |")
    print("|---|---|---|---|---|" + "---|" * len(fabrics) + "---|---|---|")
    for c in order:
        mine = [r for r in table if r["configuration"] == c]
        psnr = lambda keep: med([num(r["psnr_db"]) for r in mine if keep(r)], "%.2f")
        seconds = []
        for f in fabrics:
            values = sorted({num(r["precompute_seconds"]) for r in mine if r["fabric"] == f})
            seconds.append("/".join("%.0f" % v for v in values))
        print("| %s | %d | %s | %s | %s | %s | %s | %s | %s |" % (
            c, len(mine), psnr(lambda r: True), psnr(lambda r: "backlit" not in r["scene"]),
            psnr(lambda r: "backlit" in r["scene"]),
            " | ".join(psnr(lambda r, f=f: r["fabric"] == f) for f in fabrics), ", ".join(seconds),
            med([num(r["asset_bytes"]) / 1e6 for r in mine], "%.2f"), med([num(r["frame_ms"]) for r in mine], "%.0f")))

def volume(path):
    table = rows(path)
    keys = []
    for r in table:
        key = (r["configuration"], r["fabric"])
        if key not in keys:
            keys.append(key)
    distances = ["near", "mid", "far"]
    print("| configuration | fabric | PSNR dB: " + " | ".join(distances) + " | 1 − SSIM: " + " | ".join(distances) +
          " | precompute s | asset MB | frame ms median |")
    print("|---|---|" + "---|" * (2 * len(distances)) + "---|---|---|")
    for c, f in keys:
        mine = [r for r in table if r["configuration"] == c and r["fabric"] == f]
        at = lambda d, column, fmt: med([num(r[column]) for r in mine if r["distance"] == d], fmt)
        print("| %s | %s | %s | %s | %s | %s | %s |" % (
            c, f, " | ".join(at(d, "psnr_db", "%.2f") for d in distances),
            " | ".join(at(d, "perceptual_error", "%.3f") for d in distances),
            med([num(r["precompute_seconds"]) for r in mine], "%.0f"),
            med([num(r["asset_bytes"]) / 1e6 for r in mine], "%.2f"), med([num(r["frame_ms"]) for r in mine], "%.0f")))

# The README's "which method" table: each method at its defaults (methods.csv's
# configurations default, tabulated, factored, neural), medians over the sweep's scenes.
def choose(path):
    table = rows(path)
    print("| method | PSNR dB | SSIM | frame ms | precompute s (CPU) | asset MB |")
    print("|---|---|---|---|---|---|")
    for configuration, name in (("default", "svbrdf"), ("factored", "factored"), ("neural", "neural"),
                                ("tabulated", "tabulated")):
        mine = [r for r in table if r["configuration"] == configuration]
        column = lambda c, fmt, scale=1: med([num(r[c]) * scale for r in mine], fmt)
        print("| %s | %s | %s | %s | %s | %s |" % (
            name, column("psnr_db", "%.1f"), med([1 - num(r["perceptual_error"]) for r in mine], "%.2f"),
            column("frame_ms", "%.0f"), column("precompute_cpu_seconds", "%.0f"), column("asset_bytes", "%.1f", 1e-6)))

if __name__ == "__main__":
    if sys.argv[1] == "choose":
        choose(sys.argv[2])
    elif sys.argv[1] == "volume":
        volume(sys.argv[2])
    elif sys.argv[1] == "methods":
        methods(sys.argv[2])
    elif sys.argv[1] == "colours":
        colours(sys.argv[2])
    elif sys.argv[1] == "sweep":
        sweep(sys.argv[2])
    elif sys.argv[1] == "seeds":
        seeds(sys.argv[2], sys.argv[3])
    elif sys.argv[1] == "change":
        change(sys.argv[2], sys.argv[3], sys.argv[4])
    elif sys.argv[1] == "variations":
        variations(sys.argv[2], sys.argv[3], sys.argv[4:])
    else:
        plan(sys.argv[2], float(sys.argv[3]) if len(sys.argv) > 3 else 0.5, sys.argv[4:])
