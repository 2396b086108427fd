#!/usr/bin/python3
"""Runs every benchmark suite doc/BENCHMARKS.md shows, in one run, and renders that document from
the run's folder: the machine and date once at the top, per section the exact commands (run from
the repository root), the figures and the bar. Nothing in the document is written by hand.

  /usr/bin/python3 scripts/benchmarks.py                      # run everything, then render
  scripts/benchmarks.py --list                                # the sections, expected minutes
  scripts/benchmarks.py --only queries,python --quick         # a smoke test of two sections
  scripts/benchmarks.py --render-only out/benchmarks          # re-render, run nothing

Options: --out DIR (default out/benchmarks: every suite's raw output, CSVs, logs, JSON, and
run.json with the machine, UTC times and commit), --doc PATH (default doc/BENCHMARKS.md),
--shared PATH (default ../shared), --build PATH (default build/release), --only A,B (sections
without a result in DIR render as "not run in this run"), --quick (case counts capped: the
document then says it holds no figures). Needs Debian's python3 (numpy, for the helper scripts);
builds nothing. Exit 0 when every section ran, 1 when one failed, 2 on bad input."""
import argparse
import csv
import datetime
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PY = "/usr/bin/python3"
ACCEPT = 0.875  # the localizer's accept threshold on the confidence
# Synthetic suites: name -> (kind, cases, seed, extra generator arguments, cases with --quick).
DATASETS = {"present": ("present", 12, 2016, "", 1), "absent": ("absent", 12, 2015, "", 1),
            "clutter": ("clutter", 100, 2018, "", 3), "desk": ("desk", 100, 2020, "", 3),
            "views": ("views", 30, 2013, "", 2), "tabletop": ("tabletop", 25, 2014, "", 2),
            "freeform": ("views", 30, 2017, " --models {shared}/data/meshes/bunny.ply", 2)}
REAL = ["ycbv_video0000", "ycbv_video0001", "ycbv", "ycbv_absent"]
# The peers' comparison: (name, manifest, arguments). Every method on every case of the full
# suites takes about 65 min on 2 cores, so the big suites run their first cases of each group.
PEERS = [("synthetic_views", "views", "--thesis-cases 2 --limit 5"),
         ("synthetic_tabletop", "tabletop", "--thesis-cases 2 --limit 5"),
         ("synthetic_freeform", "freeform", "--thesis-cases 2 --limit 10"),
         ("ycbv", "ycbv", "--thesis-cases -1 --repeat 3"),
         ("ycbv_video0000_crops", "ycbv_video0000", "--thesis-cases 0 --limit 4")]
PEER_LABELS = dict(synthetic_views="views", synthetic_tabletop="table tops", synthetic_freeform=
                   "bunny views", ycbv="YCB-V frame 2 crops", ycbv_video0000_crops="YCB-V video 0000 crops")
NEEDED = ["tools/pcl_icf_bench", "tools/pcl_icf_tool", "tools/pcl_icf_make_dataset",
          "tools/pcl_icf_track_score", "bench/pcl_icf_query_bench", "test/segmentation_test", "python"]
GHV_RUNS = 7  # PCL's GHV selection is unseeded: its AR is the median of this many runs
CACHE_MESHES = ["ycb_002_master_chef_can", "ycb_003_cracker_box", "ycb_004_sugar_box",
                "ycb_006_mustard_bottle"]
BARS = dict(exact_qps=1.5e6, field_lps=50e6, brute_x=20, cluster_success=0.95, cluster_ms=50,
            segmentation_ms=150, scene3_ms=300, peer_x=3.0, peer_points=0.05, api_success=0.95,
            api_ms=50, python_share=0.05, real_misses={"ycbv0000-": 0, "ycbv0001-": 1, "ycbv-": 0},
            real_ms=1000, present_ms=150, synthetic_false=1, clutter_half=0.9, clutter_false=0.02,
            desk_half=0.9, desk_mid=0.6, desk_false=0.01, one_call_ratio=0.5, cache_ms=50,
            track_refine_ms=10, track_3_ms=33)


class Failed(Exception):
    pass


def rel(path):
    """A path as the commands show it: relative to the repository root unless far outside."""
    r = os.path.relpath(Path(path).resolve(), ROOT)
    return r if not r.startswith("../..") else str(Path(path).resolve())


class Run:
    """One invocation's settings and the suites it already ran (shared by sections)."""

    def __init__(self, a):
        self.out, self.shared, self.build = Path(a.out).resolve(), Path(a.shared), Path(a.build)
        self.quick, self.done = a.quick, {}

    def tool(self, name):
        return rel(self.build / "tools" / name)

    def micro(self, name):
        return rel(self.build / "bench" / name)

    def data(self, *parts):
        return rel(self.shared.joinpath("data", *parts))


class Record:
    """A section's folder, the commands it ran (shown in the document) and its log."""

    def __init__(self, run, name):
        self.run, self.name, self.dir = run, name, run.out / name
        shutil.rmtree(self.dir, ignore_errors=True)
        self.dir.mkdir(parents=True)
        self.commands, self.start = [], now()

    def sh(self, command, ok=(0,)):
        """Runs the command with bash from the repository root; it is shown as it ran."""
        self.commands.append(command)
        print(f"[{self.name}] {command}", flush=True)
        with open(self.dir / "log.txt", "a") as log:
            log.write(f"$ {command}\n")
            log.flush()
            rc = subprocess.run(["bash", "-c", command], cwd=ROOT, stdout=log, stderr=log).returncode
        if rc not in ok:
            raise Failed(f"`{command}` exited {rc} (log: {rel(self.dir / 'log.txt')})")

    def once(self, key, command, ok=(0,)):
        """A command several sections need (a generated suite): run once per invocation."""
        if key in self.run.done:
            self.commands += [] if command in self.commands else [command]
        else:
            self.sh(command, ok)
            self.run.done[key] = True

    def save(self, error=None):
        record = dict(commands=self.commands, start=self.start, end=now(), error=error,
                      quick=self.run.quick, commit=commit())
        (self.dir / "record.json").write_text(json.dumps(record, indent=1))


def now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M")


def output(command):
    return subprocess.run(command, shell=True, cwd=ROOT, capture_output=True, text=True).stdout


def commit():
    """HEAD's short hash, and the tracked files that differ from it, if any."""
    dirty = [l[3:] for l in output("git status --porcelain --untracked-files=no").splitlines() if l]
    return output("git rev-parse --short HEAD").strip() + (
        f" (edited: {', '.join(dirty)})" if dirty else "")


def machine():
    model = re.search(r"Model name:\s*(.+)", output("lscpu"))
    mem = re.search(r"MemTotal:\s*(\d+)", Path("/proc/meminfo").read_text())
    system = re.search(r'PRETTY_NAME="([^"]+)"', Path("/etc/os-release").read_text())
    return dict(cpu=model.group(1).strip() if model else "?", nproc=output("nproc").strip(),
                memory_gib=round(int(mem.group(1)) / 2**20) if mem else None,
                system=system.group(1) if system else "?")


# ---- suites several sections share ----

def dataset(rec, name):
    """Generates the synthetic suite NAME into OUT/data/NAME; returns its manifest."""
    run = rec.run
    kind, cases, seed, extra, quick_cases = DATASETS[name]
    folder = run.out / "data" / name
    manifest = f"{rel(folder)}/{name}.txt"
    command = (f"{run.tool('pcl_icf_make_dataset')} --out {rel(folder)} --manifest {manifest} "
               f"--kind {kind} --cases {quick_cases if run.quick else cases} --seed {seed}"
               + extra.format(shared=rel(run.shared)))
    if name not in run.done:
        shutil.rmtree(folder, ignore_errors=True)
    rec.once(name, command)
    return manifest


def real_manifests(rec):
    """The real manifests with ../../../shared rewritten to --shared: OUT/data/NAME.txt."""
    run, out = rec.run, rel(rec.run.out / "data")
    shared = rel(run.shared)
    target = shared if os.path.isabs(shared) else "$PWD/" + shared
    rec.once("real", f"mkdir -p {out}; for m in {' '.join(REAL)}; do sed "
                     f"\"s|\\.\\./\\.\\./\\.\\./shared|{target}|g\" data/manifests/$m.txt > {out}/$m.txt; "
                     f"done; cat {' '.join(f'{out}/{m}.txt' for m in REAL)} > {out}/real.txt")
    return {m: f"{out}/{m}.txt" for m in REAL + ["real"]}


def scene_bench(rec, out, manifest, options="", real=False):
    run = rec.run
    limit = " --limit 1" if run.quick and real else ""
    return (f"{run.tool('pcl_icf_bench')} --methods icf-scene --no-plots{options}{limit} "
            f"--out {rel(out)} {manifest}")


def clutter_run(rec):
    """Synthetic clutter, one call per model and all four models in one call (two sections)."""
    run = rec.run
    manifest = dataset(rec, "clutter")
    rec.once("clutter-run", scene_bench(rec, run.out / "clutter", manifest,
                                        " --tuning depth_systematic=0").replace(
        "--methods icf-scene", "--methods icf-scene,icf-objects"))


# ---- section runners ----

def run_bop(rec):
    run, root = rec.run, rec.run.data("bop-ycbv")
    targets = ""
    if run.quick:  # the first image's targets only
        rows = json.loads((run.shared / "data/bop-ycbv/test_targets_bop19.json").read_text())
        (rec.dir / "targets.json").write_text(json.dumps(rows[:2]))
        targets = f" --targets {rel(rec.dir / 'targets.json')}"
    bench = f"{run.tool('pcl_icf_bench')} --bop {root}{targets}"
    rec.sh(f"{bench} --out {rel(rec.dir / 'icf')}")
    rec.sh(f"for i in $(seq {1 if run.quick else GHV_RUNS}); do {bench} --selection ghv "
           f"--out {rel(rec.dir)}/ghv_$i; done")


def run_one_call(rec):
    run = rec.run
    frames = " --frames 1" if run.quick else ""
    rec.sh(f"{PY} scripts/find_all_objects.py --tool {run.tool('pcl_icf_tool')} --data "
           f"{run.data()}{frames} > {rel(rec.dir / 'find_all_objects.txt')}", ok=(0, 1))
    clutter_run(rec)


def run_model_cache(rec):
    run, d = rec.run, rel(rec.dir)
    meshes, runs = (CACHE_MESHES[:1], "0 1 2") if run.quick else (CACHE_MESHES, "0 1 2 3 4 5")
    video = run.data("ycbv-video0001")
    rec.sh(f"rm -rf {d}/xdg; export XDG_CACHE_HOME={d}/xdg; for m in {' '.join(meshes)}; do "
           f"for i in {runs}; do {run.tool('pcl_icf_tool')} {video}/scenes/ycbv0001_000001.pcd "
           f"{video}/models/$m.ply -q --force --json {d}/${{m}}_$i.json; done; done", ok=(0, 1))


def run_real_clutter(rec):
    run, d = rec.run, rec.dir
    sys0 = " --tuning depth_systematic=0"
    rec.sh(scene_bench(rec, d / "real", real_manifests(rec)["real"], real=True))
    for name in ("present", "absent"):
        rec.sh(scene_bench(rec, d / name, dataset(rec, name), sys0))
    rec.sh(scene_bench(rec, d / "absent_camera", dataset(rec, "absent")))
    clutter_run(rec)
    desk = dataset(rec, "desk")
    rec.sh(scene_bench(rec, d / "desk", desk, sys0))
    rec.sh(scene_bench(rec, d / "desk_curve", desk, sys0 + " --scene-min-confidence 0"))
    rec.sh(f"{PY} scripts/confidence_curve.py --by-range --plot {rel(d / 'desk_range_curve.png')} "
           f"{rel(d / 'desk_curve/desk_cases.csv')} > {rel(d / 'desk_range_curve.md')}")


def run_queries(rec):
    d, quick = rel(rec.dir), rec.run.quick
    rec.sh(f"{rec.run.micro('pcl_icf_query_bench')} --benchmark_min_time={0.01 if quick else 0.3} "
           f"--benchmark_out={d}/query_bench.json --benchmark_out_format=json > {d}/query_bench.txt")
    rec.sh(f"{rec.run.micro('pcl_icf_field_error')} > {d}/field_error.md")


def run_clusters(rec):
    trials = "3 0" if rec.run.quick else "50 3"
    rec.sh(f"{rec.run.micro('pcl_icf_icf_bench')} {trials} > {rel(rec.dir / 'icf_bench.md')}")


def run_tabletop(rec):
    run, d = rec.run, rel(rec.dir)
    reps = "1 --benchmark_min_time=0.01" if run.quick else "3"
    rec.sh(f"{run.micro('pcl_icf_segmentation_bench')} --benchmark_repetitions={reps} "
           f"--benchmark_report_aggregates_only=true --benchmark_out={d}/segmentation.json "
           f"--benchmark_out_format=json > {d}/segmentation.txt")
    rec.sh(f"{run.micro('pcl_icf_localizer_bench')} {1 if run.quick else 5} > {d}/localizer.md")
    rec.sh(f"{rel(run.build / 'test/segmentation_test')} --gtest_filter='*Mosd.ConvexitySplit*' "
           f"> {d}/convexity_split.txt")


def run_peers(rec):
    run = rec.run
    rec.sh(f"dpkg-query -W libpcl-dev libopen3d-dev libopencv-dev > {rel(rec.dir / 'versions.txt')}",
           ok=(0, 1))
    real = real_manifests(rec)
    for name, suite, options in PEERS:
        manifest = real[suite] if suite in real else dataset(rec, suite)
        if run.quick:
            options = "--thesis-cases 0 --limit 1"
        rec.sh(f"{run.tool('pcl_icf_bench')} --no-plots --out {rel(rec.dir)} --name {name} "
               f"{options} {manifest}")
    rec.sh(f"{run.tool('pcl_icf_bench')} --no-plots --out {rel(rec.dir)} --name freeform_speed "
           f"--methods icf-fast+sac,o3d-fgr+icp --repeat 3 {dataset(rec, 'freeform')}")


def run_registration_api(rec):
    run = rec.run
    rec.sh(f"{run.tool('pcl_icf_bench')} --no-plots --out {rel(rec.dir)} --name "
           f"registration_api_tabletop --methods icf-fast+sac --repeat {1 if run.quick else 3} "
           f"{dataset(rec, 'tabletop')}")


def run_python(rec):
    d = rel(rec.dir)
    env = f"PYTHONPATH={rel(rec.run.build / 'python')}"
    rec.sh(f"{env} {PY} python/benchmark_overhead.py {3 if rec.run.quick else 20} > {d}/overhead.txt")


def run_tracking(rec):
    run, d = rec.run, rel(rec.dir)
    seqs, frames, more = (1, 10, 1) if run.quick else (5, 40, 20)
    env = f"PYTHONPATH={rel(run.build / 'python')}"
    rec.sh(f"BIN={run.tool('')} OUT={d}/seed1515 scripts/bench_tracking.sh {seqs} {frames} 1515 "
           f"> {d}/seed1515.txt", ok=(0, 1))
    rec.sh(f"{run.tool('pcl_icf_make_dataset')} --kind sequence --cases {more} --frames {frames} "
           f"--seed 1616 --out {d}/seed1616")
    rec.sh(f"{env} {PY} scripts/compare_tracker_settings.py --setting 'default=dict()' --scorer "
           f"{run.tool('pcl_icf_track_score')} {d}/seed1515/sequence/seq_* {d}/seed1616/sequence/seq_* "
           f"> {d}/all_sequences.txt")
    tool = run.tool("pcl_icf_tool")
    tool = tool if os.path.isabs(tool) else "$OLDPWD/" + tool
    rec.sh(f"for s in {d}/seed1515/sequence/seq_*; do (cd $s && {tool} "
           f"--track frames.txt $(cat tracked_models.txt) ../../models/TallCylinder.ply -q "
           f"> poses_three.jsonl); done", ok=(0, 1))
    video = run.data("ycbv-video0000")
    rec.sh(f"{run.tool('pcl_icf_tool')} --track {video}/scenes {video}/models/ycb_009_gelatin_box.ply "
           f"{video}/models/ycb_061_foam_brick.ply -q > {d}/video0000.jsonl", ok=(0, 1))
    rec.sh(f"{env} {PY} scripts/track_real_frames.py {run.data('ycbv-video0001')} --threads 2 "
           f"> {d}/video0001.txt", ok=(0, 1))


# ---- one function per summary ----

def read_cases(path, method=None):
    with open(path, newline="") as f:
        return [r for r in csv.DictReader(f) if method is None or r["method"] == method]


def confidence(r):
    return float(r.get("confidence") or 0)


def scene_summary(rows):
    """Whole-scene cases at the accept threshold: found right, wrong, false poses, median time."""
    present = [r for r in rows if r["absent"] == "0"]
    absent = [r for r in rows if r["absent"] == "1"]
    kept = [r for r in rows if confidence(r) >= ACCEPT]
    return dict(present=len(present), absent=len(absent),
                right=sum(r["absent"] == "0" and r["success"] == "1" for r in kept),
                wrong=sum(r["absent"] == "0" and r["success"] != "1" for r in kept),
                false=sum(r["absent"] == "1" for r in kept),
                ms=statistics.median(float(r["time_ms"]) for r in rows) if rows else math.nan,
                missed=[r["case"] for r in present if not (r["success"] == "1" and confidence(r) >= ACCEPT)],
                false_cases=[r["case"] for r in absent if confidence(r) >= ACCEPT])


def visibility_summary(rows):
    """{band: (found right, cases)} by the group's visibility band (K-v30-50 -> v30-50)."""
    bands = {}
    for r in rows:
        if r["absent"] == "0":
            parts = r["group"].split("-")
            band = bands.setdefault(parts[-2] + "-" + parts[-1], [0, 0])
            band[0] += r["success"] == "1" and confidence(r) >= ACCEPT
            band[1] += 1
    return bands


def visibility_bands(rows):
    """(right, cases) at least half visible, in the band below and under it; that band's bound."""
    bands = visibility_summary(rows)
    add = lambda names: tuple(map(sum, zip(*[bands.get(n, (0, 0)) for n in names]))) or (0, 0)
    low = [b for b in bands if b.startswith("v0-")]
    mid = [b for b in bands if b not in low and b not in ("v50-75", "v75-100")]
    return add(["v50-75", "v75-100"]), add(mid), add(low), (mid or ["v?-50"])[0][1:].split("-")[0]


def range_band_summary(rows):
    """{range band: (right, wrong, present, false, absent)}; an absent twin joins its twin's band."""
    band_of = {r["case"]: r["group"][3:].rsplit("-v", 1)[0] for r in rows if r["group"].startswith("D-r")}
    bands = {}
    for r in rows:
        band = band_of.get(r["case"].replace("_absent", ""))
        if band:
            bands.setdefault(band, []).append(r)
    out = {}
    for band in sorted(bands, key=lambda b: float(b.split("-")[0])):
        s = scene_summary(bands[band])
        out[band] = (s["right"], s["wrong"], s["present"], s["false"], s["absent"])
    return out


def stage_medians(rows):
    """Median ms of the localizer's stages, from the bench's detail text."""
    stages = {}
    for r in rows:
        m = re.search(r"\[segmentation ([\d.]+) ms, hypotheses ([\d.]+), ranking ([\d.]+), "
                      r"judging ([\d.]+)\]", r["detail"])
        for name, value in zip(("segmentation", "hypotheses", "ranking", "judging"), m.groups() if m else ()):
            stages.setdefault(name, []).append(float(value))
    return {k: statistics.median(v) for k, v in stages.items()}


def cluster_summary(rows):
    """Cluster methods: success (1 cm, 5 degrees), mean errors, median time, hasConverged()."""
    p = [r for r in rows if r["absent"] == "0" and r["t_err_mm"] != ""]
    ok = [r for r in p if float(r["t_err_mm"]) <= 10 and float(r["r_err_deg"]) <= 5]
    times = sorted(float(r["time_ms"]) for r in rows)
    return dict(n=len(p), success=len(ok) / len(p) if p else math.nan,
                t=statistics.mean(float(r["t_err_mm"]) for r in p) if p else math.nan,
                r=statistics.mean(float(r["r_err_deg"]) for r in p) if p else math.nan,
                ms=statistics.median(times) if times else math.nan,
                p90=times[math.ceil(0.9 * len(times)) - 1] if times else math.nan,
                max=max(times, default=math.nan),
                converged=sum(r["converged"] == "1" for r in rows))


def md_table(path):
    """The rows (header first) of the markdown table(s) in the file at path."""
    return md_table_text(Path(path).read_text())



def model_preparation(md_path):
    """{model file: ICF preparation ms} from a bench report's last table."""
    text = Path(md_path).read_text().split("Model preparation")[-1]
    return {row[0]: float(row[1]) for row in md_table_text(text)[1:]}


def md_table_text(text):
    return [[c.strip() for c in l.strip().strip("|").split("|")]
            for l in text.splitlines() if l.startswith("|") and not l.startswith("|---")]


# ---- rendering helpers ----

# The README's table of current results: (suite, metric, figure, peer's figure, section), filled
# by the section renderers from the same figures as the document, in the document's order.
HEADLINES = []


def headline(section, suite, metric, figure, peer=""):
    HEADLINES.append((section, suite, metric, figure, peer))


def met(ok):
    return "met" if ok else "**not met**"


def pct(x):
    return "—" if x != x else f"{100 * x:.0f}%"


def ms(x):
    return "—" if x != x else f"{x:,.0f} ms"


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|---" + "|---:" * (len(header) - 1) + "|"]
    return lines + ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]


def commands(rec):
    return ["```sh"] + rec["commands"] + ["```"]


def rate(x):
    return f"{x / 1e6:.2f} M/s" if x >= 1e6 else f"{x / 1e3:.1f} k/s"


# ---- section renderers: (folder, its record) -> lines ----

def render_bop(d, rec):
    names = dict((int(i), n.replace("_", " ")) for i, n in re.findall(
        r"(\d+)\s+`\d{3}_(\w+)`", Path(rec["shared"], "data/bop-ycbv/README.md").read_text()))
    text = (d / "icf/bop_scores.md").read_text()
    rows = md_table_text(text)
    for row in rows[1:]:
        if row[0].isdigit():
            row[0] = f"{row[0]} {names.get(int(row[0]), '')}".strip()
    head = re.search(r"\((\w+), (\d+) images, (\d+) estimates", text)
    ghv = [md_table_text(p.read_text())[-1] for p in sorted(d.glob("ghv_*/bop_scores.md"))]
    ars = [float(r[5].strip("*")) for r in ghv]
    rules = [round(float(r[7]) * int(r[1])) for r in ghv]
    out = [f"`bop-ycbv` ({head.group(2)} real YCB-Video frames) through `localizeObjects`, "
           f"{head.group(3)} estimates; BOP 2019's errors, ADD(-S) and the suites' rule "
           f"(doc/USER_GUIDE.md, \"BOP\").", *commands(rec), *table(rows[0], rows[1:]), ""]
    total = rows[-1]
    headline("bop", "BOP `bop-ycbv` (14 real frames, 38 targets)", "BOP AR · ADD(-S)",
             f"{total[5].strip('*')} · {total[6]}",
             f"PCL's GHV as the selection: {statistics.median(ars):.3f}" if ars else "")
    if ars:
        runs = f"{len(ars)} run{'s' if len(ars) > 1 else ''}"
        out.append(f"Peer: PCL's Global Hypotheses Verification as the selection over the same "
                   f"hypotheses (`--selection ghv`, unseeded, {runs}): AR median "
                   f"**{statistics.median(ars):.3f}** ({min(ars):.3f}-{max(ars):.3f}), rule "
                   f"{statistics.median(rules):.0f}/{rows[-1][1]} ({min(rules)}-{max(rules)}).")
    return out


def render_one_call(d, rec):
    text = (d / "find_all_objects.txt").read_text()
    one = re.search(r"one call:\s+(\d+)/(\d+) right, (\d+) wrong, (\d+)/(\d+) false poses, median "
                    r"(\d+) ms", text)
    single = re.search(r"single calls: (\d+)/(\d+) right, (\d+) wrong, (\d+)/(\d+) false poses, "
                       r"median (\d+) ms per frame; one call / singles ([\d.]+)", text)
    rows = [[name, f"**{m[1]}/{m[2]}**", m[3], f"**{m[4]}/{m[5]}**", f"{int(m[6]):,} ms"]
            for name, m in (("one call per frame", one), ("one call per model", single)) if m]
    out = ["Every shared real frame asked for all its meshed objects and four absent distractors in "
           "one call (`pcl_icf_tool SCENE MODEL...`) and in one call per model; localization time per "
           "frame, models prepared in both. Synthetic clutter: the case's model and the suite's three "
           "others in one `localizeObjects` call, scored on the case's model.", *commands(rec),
           *table(["", "objects found (right)", "wrong poses", "false poses (absent distractors)",
                   "median per frame"], rows)]
    if one and single:
        headline("one_call", "every object of a real frame in one call (+4 absent)",
                 "found · false poses · time", f"{one[1]}/{one[2]} · {one[4]}/{one[5]} · "
                 f"{float(single[7]):.2f}x the single calls",
                 f"one call per model: {single[1]}/{single[2]} · {single[4]}/{single[5]}")
    if single:
        ratio = float(single[7])
        out += [f"| ratio (median of frames) | | | | **{ratio:.2f}** |", "",
                "Bar: the one call finds as many as the single calls "
                f"({met(int(one[1]) >= int(single[1]))}), "
                f"no false pose ({met(one[4] == '0')}), time ratio <= {BARS['one_call_ratio']} "
                f"({met(ratio <= BARS['one_call_ratio'])})."]
    clutter = Path(d).parent / "clutter/clutter_cases.csv"
    if clutter.exists():
        s = {m: scene_summary(read_cases(clutter, m)) for m in ("icf-objects", "icf-scene")}
        decided = {m: {r["case"]: (r["success"] == "1", confidence(r) >= ACCEPT)
                       for r in read_cases(clutter, m)} for m in s}
        differ = sum(decided["icf-objects"][c] != v for c, v in decided["icf-scene"].items())
        rows = [[label, f"**{x['right']}/{x['present']}**", x["wrong"],
                 f"**{x['false']}/{x['absent']}**", ms(x["ms"])]
                for label, x in (("one call, 4 models", s["icf-objects"]),
                                 ("one call per model (the case's)", s["icf-scene"]))]
        o, single = s["icf-objects"], s["icf-scene"]
        out += ["", *table([f"{o['present'] + o['absent']} clutter cases", "found (right)", "wrong poses",
                            "false poses (absent twins)", "median per case"], rows), "",
                f"Cases decided differently by the two: {differ}. Bar (found not lower than the "
                f"single calls, false poses <= 1%): "
                f"{met(o['right'] >= single['right'] and o['false'] <= 0.01 * o['absent'])}."]
    return out


def render_model_cache(d, rec):
    files = sorted((d / "xdg").rglob("*.icfmodel"), key=lambda p: p.stat().st_mtime)
    parts, worst = [], 0.0
    for k, mesh in enumerate(m for m in CACHE_MESHES if (d / f"{m}_0.json").exists()):
        docs = [json.loads(p.read_text()) for p in sorted(d.glob(f"{mesh}_*.json"))]
        cached = [x["timing_ms"]["build_model"] for x in docs if x["model_info"]["from_cache"]]
        built = [x["timing_ms"]["build_model"] for x in docs if not x["model_info"]["from_cache"]]
        size = f"{files[k].stat().st_size / 1e6:.1f} MB" if k < len(files) else "?"
        read = statistics.median(cached) if cached else math.inf
        worst = max(worst, read)
        parts.append(f"{mesh.split('_', 2)[2].replace('_', ' ')} **{read:.1f} ms** (built in "
                     f"{ms(statistics.median(built)) if built else '?'}, {size} file)")
    return ["`pcl_icf_tool`'s `build_model` time with each 16,384-triangle `ycbv-video0001` mesh: one "
            "run builds and caches the model, the next ones read it.", *commands(rec),
            f"Read from the cache (median of the runs that read it): {', '.join(parts)}. Bar: <= "
            f"{BARS['cache_ms']} ms ({met(worst <= BARS['cache_ms'])})."]


def real_rows(d):
    """The table rows of the real frames, the whole set's summary and each dataset's, by group
    prefix."""
    rows = read_cases(d / "real/real_cases.csv")
    out, parts = [], {}
    for label, prefix in (("`ycbv-video0000` (real, 0.55 m)", "ycbv0000-"),
                          ("`ycbv-video0001` (real, 1 m)", "ycbv0001-"), ("YCB-V frame", "ycbv-")):
        s = scene_summary([r for r in rows if r["group"].startswith(prefix)])
        parts[prefix] = s
        out.append([label, s["present"], f"**{s['right']}/{s['present']}**", s["wrong"], "", ""])
    s = scene_summary([r for r in rows if r["group"].startswith("absent-")])
    out.append(["`ycbv_absent` (real, target absent)", s["absent"], "", "",
                f"**{s['false']}/{s['absent']}**", ""])
    s, st = scene_summary(rows), stage_medians(rows)
    stages = ", ".join(f"{k} {v:.0f}" for k, v in st.items())
    out.append(["the real set above, together", len(rows), f"{s['right']}/{s['present']}", s["wrong"],
                f"{s['false']}/{s['absent']}", f"**{ms(s['ms'])}** ({stages})"])
    return out, s, parts


def synthetic_rows(d):
    """The table rows of the generated table tops, with and without the target."""
    present = read_cases(d / "present/present_cases.csv")
    p, hyp = scene_summary(present), stage_medians(present).get("hypotheses", math.nan)
    a = scene_summary(read_cases(d / "absent/absent_cases.csv"))
    ac = scene_summary(read_cases(d / "absent_camera/absent_cases.csv"))
    return [["synthetic table tops with a look-alike (`--kind present`)", p["present"],
             f"**{p['right']}/{p['present']}**", p["wrong"], "", f"{ms(p['ms'])} (hypotheses {hyp:.0f})"],
            ["synthetic target absent (`--kind absent`)", a["absent"], "", "",
             f"**{a['false']}/{a['absent']}**", ms(a["ms"])],
            ["the same, a real camera's error assumed (default `depth_systematic`)", ac["absent"], "", "",
             f"{ac['false']}/{ac['absent']}", ms(ac["ms"])]], p, a


def desk_row(label, cases):
    """A cluttered suite's row by visibility band, and its summary."""
    s, (half, mid, low, bound) = scene_summary(cases), visibility_bands(cases)
    s.update(half=half[0] / half[1] if half[1] else math.nan, mid=mid[0] / mid[1] if mid[1] else math.nan,
             false_share=s["false"] / s["absent"] if s["absent"] else math.nan)
    return [label, len(cases), f">=50% visible {half[0]}/{half[1]}, {bound}-50% **{mid[0]}/{mid[1]}**, "
            f"<{bound}% {low[0]}/{low[1]}", s["wrong"], f"**{s['false']}/{s['absent']}**", ms(s["ms"])], s


def bar(text, value, limit, at_least=True):
    """'text X (bar Y: met)' with shares as per cent."""
    return f"{text} {pct(value)} (bar {pct(limit)}: {met(value >= limit if at_least else value <= limit)})"


def render_real_clutter(d, rec):
    rows, real, parts = real_rows(d)
    misses = {prefix: x["present"] - x["right"] for prefix, x in parts.items()}
    desk_cases = read_cases(d / "desk/desk_cases.csv")
    synthetic, p, a = synthetic_rows(d)
    clutter_row, clutter = desk_row("synthetic clutter (`--kind clutter`)",
                                    read_cases(d.parent / "clutter/clutter_cases.csv", "icf-scene"))
    desk_row_, desk = desk_row("real-like desks (`--kind desk`)", desk_cases)
    prep = model_preparation(d / "real/real.md")
    limits = BARS["real_misses"]
    for label, prefix in (("whole real frames, `ycbv-video0000` (0.55 m)", "ycbv0000-"),
                          ("whole real frames, `ycbv-video0001` (1 m)", "ycbv0001-")):
        x = parts[prefix]
        headline("real_clutter", label, "found, no guess, whole scene",
                 f"{x['right']}/{x['present']}, {x['wrong']} wrong")
    headline("real_clutter", "real frames without the target (`ycbv_absent`)", "false poses",
             f"{real['false']}/{real['absent']}")
    headline("real_clutter", "real-like synthetic desks", "found (>= 50% visible · 25-50%) · false poses",
             f"{pct(desk['half'])} · {pct(desk['mid'])} · {pct(desk['false_share'])}")
    headline("real_clutter", "synthetic table tops with a look-alike", "found · median time",
             f"{p['right']}/{p['present']} · {ms(p['ms'])}")
    bands = [[b, f"{r}/{n}", f"{w}/{n}", f"{f}/{na}"] for b, (r, w, n, f, na) in
             range_band_summary(desk_cases).items()]
    return ["`localizeObject` on whole frames, no guess (doc/localizer.md); time per case (one object "
            "in one frame), segmentation included, models prepared once (not timed). The simulated "
            "camera makes no low-frequency depth error: `depth_systematic=0`.", *commands(rec),
            *table(["suite", "cases", "found", "wrong poses", "false poses (target absent)",
                    "median per case"], rows + synthetic + [clutter_row, desk_row_]), "",
            "Real frames, bars: misses at most "
            + ", ".join(f"{v} ({k.rstrip('-')})" for k, v in limits.items())
            + f" ({met(all(misses[k] <= v for k, v in limits.items()))}), {ms(real['ms'])} per object and "
            f"frame (bar {BARS['real_ms']} ms: {met(real['ms'] <= BARS['real_ms'])}), no false pose "
            f"({met(real['false'] == 0)}). Missed: {', '.join(real['missed']) or 'none'}. Model preparation "
            f"{min(prep.values()) / 1e3:.1f}-{max(prep.values()) / 1e3:.1f} s a YCB mesh. Identification: "
            f"table tops all found ({met(p['right'] == p['present'])}) in {ms(p['ms'])} per case (bar "
            f"{BARS['present_ms']} ms: {met(p['ms'] <= BARS['present_ms'])}); synthetic target absent <= "
            f"{BARS['synthetic_false']} false pose in 60 "
            f"({met(a['false'] * 60 <= BARS['synthetic_false'] * max(1, a['absent']))}).", "",
            bar("Synthetic clutter: at least half visible", clutter["half"], BARS["clutter_half"]) + ", "
            + bar("false poses", clutter["false_share"], BARS["clutter_false"], False) + ". "
            + bar("Real-like desks: at least half visible", desk["half"], BARS["desk_half"]) + ", "
            + bar("the band below", desk["mid"], BARS["desk_mid"]) + ", "
            + bar("false poses", desk["false_share"], BARS["desk_false"], False)
            + f": {', '.join(desk['false_cases']) or 'none'}. Per target range band, accept threshold "
            f"{ACCEPT}:",
            "", *table(["target range (m)", "found (right pose)", "wrong poses, target present",
                        "false poses, target absent"], bands), "",
            "![false poses against missed objects per range band as the threshold moves, on the desks run "
            "with --scene-min-confidence 0](img/desk_range_curve.png)"]


def render_queries(d, rec):
    found = {b["name"]: b for b in json.loads((d / "query_bench.json").read_text())["benchmarks"]}
    get = lambda name: found.get(name, {}).get("items_per_second", math.nan)
    meshes = [("box 14x9x5 cm", "box"), ("cylinder (YellowRoundSalt)", "cylinder"),
              ("Stanford bunny (`meshes/bunny.ply`)", "bunny"),
              ("dinosaur (`parasaurolophus_low_normals2.ply`, mm -> m)", "dino55k")]
    rows = []
    for label, key in meshes:
        exact = found.get(f"exactQueries/{key}_r1cm", {})
        cells = [get(f"exactQueries/{key}_r1cm"), get(f"exactQueries/{key}_unbounded"),
                 get(f"bruteQueries/{key}"), get(f"fieldLookups/{key}")]
        rows.append([label, f"{exact.get('faces', math.nan):,.0f}"]
                    + ["" if c != c else rate(c) for c in cells])
    exact, brute, field = get("exactQueries/bunny_r1cm"), get("bruteQueries/bunny"), get("fieldLookups/bunny")
    headline("queries", "point-to-face queries, Stanford bunny, 1 cm radius", "queries/s per thread",
             f"{rate(exact)} (field: {rate(field)} lookups)", f"brute force {rate(brute)}")
    errors = md_table(d / "field_error.md")
    within = all(float(r[6]) <= float(r[2]) for r in errors[1:])
    return ["Per thread, rates from CPU time; query points: surface samples displaced by up to 5 mm "
            "along a random direction. The micro-benchmarks read the shared data folder compiled into "
            "them.", *commands(rec),
            *table(["mesh", "faces", "exact, Embree, 1 cm radius", "exact, unbounded", "brute force",
                    "field lookups"], rows), "",
            f"Bars on the bunny: exact >= {rate(BARS['exact_qps'])} ({met(exact >= BARS['exact_qps'])}), "
            f"field >= {rate(BARS['field_lps'])} ({met(field >= BARS['field_lps'])}), both >= "
            f"{BARS['brute_x']}x brute force ({exact / brute:,.0f}x, {field / brute:,.0f}x: "
            f"{met(min(exact, field) >= BARS['brute_x'] * brute)}). The field's error against exact "
            f"distances, 200,000 points within 3 cm:", "", *table(errors[0], errors[1:]), "",
            f"Bar: the error within one cell ({met(within)})."]


def render_clusters(d, rec):
    rows = md_table(d / "icf_bench.md")
    fast = [r for r in rows[1:] if r[1].startswith("ICF fast")]
    ok = all(float(r[4].rstrip("%")) >= 100 * BARS["cluster_success"] for r in fast)
    quick = all(float(r[7]) <= BARS["cluster_ms"] for r in fast)
    times = [float(r[7]) for r in fast]
    spread = lambda xs, unit: f"{min(xs):.0f}{unit}" if min(xs) == max(xs) else \
        f"{min(xs):.0f}-{max(xs):.0f}{unit}"
    others = []
    for prefix in ("PCL ICP", "thesis"):
        rs = [r for r in rows[1:] if r[1].startswith(prefix)]
        if rs:
            others.append(f"{rs[0][1].split('(')[0].strip()} "
                          f"{spread([float(r[4].rstrip('%')) for r in rs], '%')}")
    headline("clusters", "synthetic Kinect views, thesis's 4 models, no guess",
             "success · median time per cluster",
             f"{spread([float(r[4].rstrip('%')) for r in fast], '%')} · {spread(times, ' ms')}",
             "; ".join(others))
    return ["Synthetic Kinect views of the thesis's four models at random poses 0.7-1.1 m away, no "
            "guess, seeds 5000 on; wall time of `align()` per cluster on both cores, the model prepared "
            "once (not timed).", *commands(rec), *table(rows[0], rows[1:]), "",
            f"Bars: >= {pct(BARS['cluster_success'])} within 5 mm / 3 degrees ({met(ok)}); median <= "
            f"{BARS['cluster_ms']} ms per cluster of 2-5k points ({min(times):.0f}-{max(times):.0f} ms: "
            f"{met(quick)})."]


SEGMENTATION_STAGES = [("FiniteIndices", "finite points"), ("VoxelDownsample", "voxel grid (1 cm)"),
                       ("FindTablePlane", "table plane (RANSAC, seeded)"),
                       ("RefineTablePlane", "plane refit on the full cloud"), ("TableHull", "table hull"),
                       ("AboveTableIndices", "above the table (prism)"),
                       ("ExtractClusters_Grid", "clusters (grid flood fill, = PCL's result)"),
                       ("ExtractClusters_PclOrganized|ExtractClusters_PclKdTree",
                        "clusters, PCL OrganizedNeighbor / kd-tree (to compare)"),
                       ("SegmentTabletop", "**whole segmentation**")]


def render_tabletop(d, rec):
    times = {}
    for b in json.loads((d / "segmentation.json").read_text())["benchmarks"]:
        if b.get("aggregate_name", "median") == "median" and not b.get("error_occurred"):
            times[b.get("run_name", b["name"]).replace("/real_time", "")] = b["real_time"]
    cell = lambda keys, scene: " / ".join(f"{times[f'{k}/{scene}']:.1f}" if f"{k}/{scene}" in times
                                          else "—" for k in keys.split("|")) + " ms"
    rows = [[label, cell(keys, "milk"), cell(keys, "mosd_test55")] for keys, label in SEGMENTATION_STAGES]
    whole = [times.get(f"SegmentTabletop/{s}", math.inf) for s in ("milk", "mosd_test55")]
    scenes = md_table(d / "localizer.md")
    synthetic = float(scenes[1][6]) if len(scenes) > 1 else math.inf
    big, scene = [], "?"  # (scene, segment, points, precision, recall, cluster precision, recall)
    for line in (d / "convexity_split.txt").read_text().splitlines():
        head = re.match(r"\[ mosd lccp\] (\w+):", line)
        scene = head.group(1) if head else scene
        cells = line.split()
        if len(cells) == 6 and cells[0].isdigit() and int(cells[1]) >= 500:
            big.append((scene, cells[0], *map(float, cells[1:])))
    merged = [s[5] for s in big if s[5] < 0.9]
    cut = [f"{s[0]} {s[1]}: {s[4]:.3f}" for s in big if s[4] < s[6] - 0.1]
    return ["Segmentation of real 640x480 Kinect scenes (PCL's milk scene, mOSD test55), median of the "
            "repetitions; whole scenes (median of the runs, the YCB frame a third of them); the convexity "
            "split on the stacked and touching mOSD scenes, per labelled segment.",
            *commands(rec), *table(["stage", "milk scene", "mOSD test55"], rows), "",
            *table(scenes[0], scenes[1:]), "",
            f"Bars: segmentation <= {BARS['segmentation_ms']} ms "
            f"({met(max(whole) <= BARS['segmentation_ms'])}); the synthetic 3-object scene <= "
            f"{BARS['scene3_ms']} ms whole ({met(synthetic <= BARS['scene3_ms'])}). "
            f"Convexity split, segments of at least 500 points: precision at least "
            f"{min((s[3] for s in big), default=math.nan):.3f} against {min(merged, default=math.nan):.2f}-"
            f"{max(merged, default=math.nan):.2f} for the Euclidean clusters that merge objects; recall "
            f"where the split cuts an object (recall down by more than 0.1): {', '.join(cut) or 'none'}."]


def render_peers(d, rec):
    columns, methods = [], []
    for name, suite, options in PEERS:
        path = d / f"{name}_cases.csv"
        rows = read_cases(path) if path.exists() else []
        for r in rows:
            if r["method"] not in methods:
                methods.append(r["method"])
        columns.append((name, {m: cluster_summary([r for r in rows if r["method"] == m]) for m in methods}))
    cell = lambda s, n: "—" if not s or not s["n"] else (
        f"{pct(s['success'])} · {s['t']:.1f} mm · {s['r']:.1f}° · {s['ms']:,.0f} ms"
        + (f" ({s['n']} cases)" if s["n"] != n else ""))
    header = ["method"] + [f"{PEER_LABELS[n]} ({c.get('icf-fast', {}).get('n', 0)})" for n, c in columns]
    rows = [[f"`{m}`"] + [cell(c.get(m), c.get("icf-fast", {}).get("n")) for _, c in columns]
            for m in methods]
    verdicts = []
    for name, c in columns:
        icf = c.get("icf-fast+sac")
        peers = [s for m, s in c.items() if not m.startswith("icf-") and s["n"]]
        if not icf or not peers:
            continue
        best = max(s["success"] for s in peers)
        near = [s for s in peers if s["success"] >= icf["success"] - BARS["peer_points"]]
        ratio = min(s["ms"] for s in (near or peers)) / icf["ms"]
        ok = icf["success"] >= best and (not near or ratio >= BARS["peer_x"])
        verdicts.append(f"{PEER_LABELS[name]} {met(ok)} ({pct(icf['success'])} vs {pct(best)}, "
                        f"{ratio:.1f}x{'' if near else ' the fastest'})")
    for name, c in columns:
        icf = c.get("icf-fast+sac")
        peers = [(m, x) for m, x in c.items() if not m.startswith("icf-") and x["n"]]
        if icf and icf["n"]:
            best = max(peers, key=lambda mx: (mx[1]["success"], -mx[1]["ms"]), default=None)
            headline("peers", f"clusters: {PEER_LABELS[name]} ({icf['n']})", "success · median time",
                     f"{pct(icf['success'])} · {ms(icf['ms'])}",
                     f"`{best[0]}` {pct(best[1]['success'])} · {ms(best[1]['ms'])}" if best else "")
    speed = d / "freeform_speed_cases.csv"
    if speed.exists():
        s = {m: cluster_summary(read_cases(speed, m)) for m in ("icf-fast+sac", "o3d-fgr+icp")}
        verdicts.append("bunny with `--repeat 3` (all its cases): `icf-fast+sac` "
                        f"{ms(s['icf-fast+sac']['ms'])}, "
                        f"`o3d-fgr+icp` {ms(s['o3d-fgr+icp']['ms'])}: "
                        f"{s['o3d-fgr+icp']['ms'] / s['icf-fast+sac']['ms']:.2f}x")
    versions = ", ".join(" ".join(l.split("\t")) for l in (d / "versions.txt").read_text().splitlines())
    return ["Every method on the same cluster points of each case (what each row runs: "
            "doc/experiments/2026-11-27-peers-pcl-open3d-opencv.md); to keep it near 15 minutes, the "
            "first cases of each group (`--limit`, `--thesis-cases`: the commands). Success (1 cm, "
            f"5 degrees) · mean translation / rotation error · median time per cluster; {versions}.",
            *commands(rec),
            *table(header, rows), "",
            f"Bar (ICF's success at least every peer's, {BARS['peer_x']:.0f}x faster than the fastest "
            "peer within 5 points of it): " + "; ".join(verdicts) + "."]


def render_registration_api(d, rec):
    rows = read_cases(d / "registration_api_tabletop_cases.csv")
    groups = sorted({r["group"] for r in rows})
    s = cluster_summary(rows)
    lines = [["all", s["n"], f"**{pct(s['success'])}**", s["converged"],
              f"**{s['ms']:.0f}** (90th percentile {s['p90']:.0f}, max {s['max']:.0f})"]]
    for g in groups:
        x = cluster_summary([r for r in rows if r["group"] == g])
        lines.append([g, x["n"], pct(x["success"]), x["converged"], f"{x['ms']:.0f}"])
    prep = model_preparation(d / "registration_api_tabletop.md")
    return ["`icf-fast+sac`: a `pcl::IterativeClosestFace<pcl::PointXYZ>` per cluster through "
            "`Registration::align`, no guess, on the synthetic table tops (oracle clusters).", *commands(rec),
            *table(["group", "cases", "success (1 cm, 5°)", "`hasConverged()`",
                    "median ms per cluster"], lines), "",
            f"Bar (>= {pct(BARS['api_success'])} success, median <= {BARS['api_ms']} ms per cluster, model "
            f"prepared once): {met(s['success'] >= BARS['api_success'] and s['ms'] <= BARS['api_ms'])}. "
            "Model preparation: " + ", ".join(f"{Path(k).stem} {v:.0f} ms" for k, v in prep.items()) + "."]


def render_python(d, rec):
    m = re.search(r"runs (\d+): Python call median ([\d.]+) ms, C\+\+ localizeObject median ([\d.]+) "
                  r"ms, overhead median ([\d.-]+) ms \(max ([\d.-]+) ms\) = ([\d.-]+)%",
                  (d / "overhead.txt").read_text())
    share = float(m[6]) / 100
    headline("python", "Python `localize`", "overhead over the C++ call", f"{m[6]}%")
    header = ["calls", "Python call (median)", "C++ `localizeObject` (median)",
              "overhead (median, max)", "share"]
    return ["The call's wall time minus `Localization::total_ms`, `data/demo/tabletop_box5.pcd` with "
            "`box5.ply`, after a warm-up.", *commands(rec),
            *table(header, [[m[1], f"{m[2]} ms", f"{m[3]} ms", f"{m[4]} ms ({m[5]})", f"**{m[6]}%**"]]),
            "", f"Bar (<= {pct(BARS['python_share'])} of the C++ time): "
            f"{met(share <= BARS['python_share'])}."]


def score_rows(text):
    """The track scorer's "all" row (split into cells) and its bars line."""
    row = next((l for l in text.splitlines() if l.startswith("| **all**")), "")
    bars = next((l for l in text.splitlines() if l.startswith("bars:")), "bars: ?")
    return [c.strip().strip("*") for c in row.strip().strip("|").split("|")], bars


def frame_times(path, every=lambda objects: True, skip_first=False):
    """The ms of the frames of a --track JSON-lines file whose objects pass every()."""
    lines = [json.loads(l) for l in Path(path).read_text().splitlines() if l.strip()]
    return [x["ms"] for k, x in enumerate(lines) if every(x["objects"]) and not (skip_first and k == 0)]


def render_tracking(d, rec):
    text, every_text = (d / "seed1515.txt").read_text(), (d / "all_sequences.txt").read_text()
    (cells, bars), (every, every_bars) = score_rows(text), score_rows(every_text)
    whole = re.search(r"whole frame: median ([\d.]+) ms over (\d+) frames", text)
    notes = "".join(f" All sequences, {l}." for l in every_text.splitlines()
                    if l.startswith(("missed", "posed beyond")))
    three = []
    for p in sorted(d.glob("seed1515/sequence/seq_*/poses_three.jsonl")):
        three += frame_times(p, lambda o: all(x["state"] == "tracking" for x in o))
    video0 = statistics.median(frame_times(d / "video0000.jsonl", skip_first=True))
    real = re.search(r"after the first: (\d+)/(\d+) object-frames posed right, median (\d+) ms",
                     (d / "video0001.txt").read_text())
    refine, t3 = float(cells[7]), statistics.median(three)
    headline("tracking", "tracking generated sequences (seeds 1515 on)",
             "within 1 cm / 5 deg while half visible · whole frame", f"{cells[2]} · {whole[1]} ms")
    headline("tracking", "tracking real `ycbv-video0001`", "object-frames right · per object and frame",
             f"{real[1]}/{real[2]} · {real[3]} ms")
    rows = [["generated, seeds 1515 on (`bench_tracking.sh`)"] + cells[2:8],
            [f"all {len(list(d.glob('seed*/sequence/seq_*')))}, seeds 1515 and 1616 on"] + every[2:8]]
    header = ["sequences", "within 1 cm / 5 deg (>= 50% visible)", "hidden: accurate",
              "poses while absent", "loss after (frames)", "re-found after", "refine ms (median)"]
    return ["Generated sequences (doc/DATASETS.md; the occluder tracked too in the fourth command), "
            "real ycbv-video0000 and ycbv-video0001 (`pcl_icf.Tracker`, the suites' rule).",
            *commands(rec), *table(header, rows), "",
            f"Whole frame (2 objects) median {whole[1]} ms over {whole[2]} frames; three tracked objects "
            f"**{t3:.1f} ms** median over {len(three)} frames with all three tracked (max "
            f"{max(three):.1f}); ycbv-video0000 frames after the first, two objects: {video0:.1f} ms; "
            f"ycbv-video0001: {real[1]}/{real[2]} object-frames right, **{real[3]} ms per object and "
            f"frame**.{notes}", "",
            f"Bars, the scorer's: {bars[6:]}" + ("" if every_bars == bars else f" (all: {every_bars[6:]})")
            + f"; refinement <= {BARS['track_refine_ms']} ms per object "
            f"({met(refine <= BARS['track_refine_ms'])}); 3 objects <= {BARS['track_3_ms']} ms a frame "
            f"({met(t3 <= BARS['track_3_ms'])})."]


# name, title, expected minutes on 2 cores (in the full run; with --quick), runner, renderer. The
# clutter run (7 min) is one_call's; real_clutter alone runs it too (15 min).
SECTIONS = [
    ("bop", "BOP scores of the shared frames", 6, 0.2, run_bop, render_bop),
    ("one_call", "Every object in one call", 12, 2, run_one_call, render_one_call),
    ("model_cache", "Prepared models read from the cache", 2, 0.3, run_model_cache, render_model_cache),
    ("real_clutter", "Real clutter: whole scenes, real and synthetic", 8, 2, run_real_clutter,
     render_real_clutter),
    ("queries", "Exact queries and the closest-point field", 1.5, 0.3, run_queries, render_queries),
    ("clusters", "IterativeClosestFace on single clusters", 3, 0.2, run_clusters, render_clusters),
    ("tabletop", "Table-top scenes", 1.5, 0.3, run_tabletop, render_tabletop),
    ("peers", "ICF against PCL, Open3D and OpenCV", 16, 4, run_peers, render_peers),
    ("registration_api", "pcl::IterativeClosestFace through the PCL Registration API", 1, 0.2,
     run_registration_api, render_registration_api),
    ("python", "Python bindings: overhead of `pcl_icf.localize`", 0.5, 0.1, run_python, render_python),
    ("tracking", "Tracking", 6, 1, run_tracking, render_tracking),
]


def wrap(lines, width=100):
    """Prose wrapped at width; tables, headings, pictures and commands as they are."""
    out, code = [], False
    for line in lines:
        code ^= line.startswith("```")
        prose = not (code or line.startswith(("|", "#", "!", "```")))
        out += textwrap.wrap(line, width, break_on_hyphens=False) if prose and line else [line]
    return out


README_BEGIN = "<!-- results: written by scripts/benchmarks.py from the run of doc/BENCHMARKS.md -->"
README_END = "<!-- /results -->"


def write_readme_table(readme, titles):
    """The README's table of current results between its markers, from HEADLINES."""
    text = readme.read_text()
    if README_BEGIN not in text or README_END not in text:
        print(f"warning: {rel(readme)} has no results markers; its table is not written", file=sys.stderr)
        return
    rows = [[suite, metric, figure, peer, f"\"{titles[section]}\""]
            for section, suite, metric, figure, peer in HEADLINES]
    block = [README_BEGIN, *table(["suite", "metric", "pcl_icf", "best peer",
                                   "section of doc/BENCHMARKS.md"], rows), README_END]
    head, rest = text.split(README_BEGIN, 1)
    readme.write_text(head + "\n".join(block) + rest.split(README_END, 1)[1])
    print(f"wrote {rel(readme)}'s results table ({len(rows)} rows)")


def render(out, doc, readme=None):
    """doc/BENCHMARKS.md from the folder out, and the results table of \a readme when given."""
    HEADLINES.clear()
    meta = json.loads((out / "run.json").read_text()) if (out / "run.json").exists() else {}
    records = {}
    for name, *_ in SECTIONS:
        path = out / name / "record.json"
        records[name] = json.loads(path.read_text()) if path.exists() else None
    done = [r for r in records.values() if r]
    m = meta.get("machine", {})
    start, end = (min(r["start"] for r in done), max(r["end"] for r in done)) if done else ("?", "?")
    span = f"{start}-{end[11:] if end[:10] == start[:10] else end} UTC"
    commits = ", ".join(sorted({r["commit"] for r in done})) or "?"
    lines = ["# Benchmarks", "",
             f"One run of `/usr/bin/python3 scripts/benchmarks.py`, {span}, on {m.get('cpu', '?')}, "
             f"{m.get('nproc', '?')} cores (`nproc`), {m.get('memory_gib', '?')} GiB, "
             f"{m.get('system', '?')}, "
             f"commit {commits}; raw output in `{rel(out)}`. Times vary by "
             "tens of per cent between runs: compare figures within a table. Right: the model's box centre "
             "within 1 cm and ADD-S under 10% of the diameter (cluster suites: 1 cm, 5 degrees). Whole "
             f"scenes count a pose at confidence >= {ACCEPT} (the accept threshold): found if right, wrong "
             "if not, false if the target is absent."]
    if any(r["quick"] for r in done):
        lines += ["", "**Quick run (`--quick`), not the figures**: case counts capped for a smoke test."]
    for name, title, *_, renderer in SECTIONS:
        lines += ["", f"## {title}"]
        r = records[name]
        if r is None:
            lines.append("Not run in this run.")
        elif r["error"]:
            lines += [f"Failed in this run: {r['error']}", *commands(r)]
        else:
            r["shared"] = meta.get("shared", str(ROOT.parent / "shared"))
            try:
                lines += renderer(out / name, r)
            except (OSError, ValueError, TypeError, KeyError, IndexError, AttributeError,
                    statistics.StatisticsError) as e:
                lines += [f"Not rendered: its output in `{rel(out / name)}` is incomplete ({e}).",
                          *commands(r)]
    lines += ["", "## History", "How each figure came about, newest first: the dated notes listed in",
              "[experiments/README.md](experiments/README.md)."]
    curve = out / "real_clutter/desk_range_curve.png"
    if records["real_clutter"] and curve.exists():
        (doc.parent / "img").mkdir(parents=True, exist_ok=True)
        shutil.copyfile(curve, doc.parent / "img/desk_range_curve.png")
    lines = wrap(lines)
    if readme:
        write_readme_table(readme, {name: title for name, title, *_ in SECTIONS})
    doc.parent.mkdir(parents=True, exist_ok=True)
    doc.write_text("\n".join(lines) + "\n")
    if len(lines) > 300:
        print(f"warning: {rel(doc)} has {len(lines)} lines (limit 300)", file=sys.stderr)
    print(f"wrote {rel(doc)} ({len(lines)} lines)")


def fail(message):
    print(f"benchmarks.py: {message}", file=sys.stderr)
    sys.exit(2)


def check_inputs(a, names):
    unknown = [n for n in names if n not in [s[0] for s in SECTIONS]]
    if unknown:
        fail(f"unknown section {', '.join(unknown)}; --list shows them")
    if a.render_only:
        return
    missing = [p for p in NEEDED if not (Path(a.build) / p).exists()]
    if missing:
        fail(f"no usable build at {a.build} ({', '.join(missing)} missing): build the release preset "
             "first or give --build")
    if not Path(PY).is_file():
        fail(f"{PY} missing (Debian's python3 with numpy runs the helper scripts)")
    if not (Path(a.shared) / "data/ycbv-video0000").is_dir():
        fail(f"no shared data at {a.shared} (data/ycbv-video0000 missing): give --shared")


def readme(a):
    """The README whose table the render writes: the repository's, with the default document."""
    return ROOT / "README.md" if Path(a.doc).resolve() == (ROOT / "doc/BENCHMARKS.md").resolve() else None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("--out", default=str(ROOT / "out/benchmarks"))
    parser.add_argument("--render-only", metavar="DIR")
    parser.add_argument("--doc", default=str(ROOT / "doc/BENCHMARKS.md"))
    parser.add_argument("--only", default="")
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--shared", default=str(ROOT.parent / "shared"))
    parser.add_argument("--build", default=str(ROOT / "build/release"))
    parser.add_argument("--quick", action="store_true")
    a = parser.parse_args()
    if a.list:
        for name, title, full, quick, *_ in SECTIONS:
            slow = {"peers": " (reduced: every case ~65 min)", "real_clutter": " (15 alone)"}.get(name, "")
            print(f"{name:17s} {full:5.1f} min ({quick:.1f} with --quick)  {title}{slow}")
        print(f"{'all':17s} {sum(s[2] for s in SECTIONS):5.1f} min")
        return 0
    names = [n for n in a.only.split(",") if n] or [s[0] for s in SECTIONS]
    check_inputs(a, names)
    if a.render_only:
        if not Path(a.render_only).is_dir():
            fail(f"no folder {a.render_only}")
        render(Path(a.render_only).resolve(), Path(a.doc), readme(a))
        return 0
    run = Run(a)
    run.out.mkdir(parents=True, exist_ok=True)
    meta = dict(machine=machine(), start=now(), commit=commit(), quick=a.quick, sections=names,
                shared=str(Path(a.shared).resolve()), build=str(Path(a.build).resolve()))
    failed = []
    for name, title, _, _, runner, _ in SECTIONS:
        if name in names:
            rec = Record(run, name)
            try:
                runner(rec)
                rec.save()
            except Exception as e:  # a failed command, or its output missing: the next section
                print(f"[{name}] failed: {e}", file=sys.stderr)
                failed.append(name)
                rec.save(str(e))
    meta["end"] = now()
    (run.out / "run.json").write_text(json.dumps(meta, indent=1))
    render(run.out, Path(a.doc), readme(a))
    if failed:
        print(f"failed: {', '.join(failed)}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
