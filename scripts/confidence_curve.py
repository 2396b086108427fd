#!/usr/bin/env python3
# pcl_icf — Iterative Closest Face registration for PCL.
# SPDX-License-Identifier: BSD-3-Clause
"""The curve of false poses against missed objects as the accept threshold on the confidence
moves (doc/BENCHMARKS.md "Identification").

Input: NAME_cases.csv files written by
    pcl_icf_bench --methods icf-scene --scene-min-confidence 0 ...
(every case reports its best hypothesis with its confidence). A case is
  present-right  the target is there and the pose is a success (1 cm, ADD-S rule of the bench),
  present-wrong  the target is there and the pose is wrong,
  absent         the target is not there (truth=none).
At threshold t a pose is reported when confidence >= t. A false pose is a reported absent or
present-wrong case; a missed object is a present case without a reported right pose.

Writes a table (markdown) of the curve to stdout and, with --plot FILE.png, a gnuplot picture.
With --residual-sweep (rows measured with the residual term off, max_residual infinity), the
table at the accept threshold 0.875 as the residual factor's fit_residual F moves (max_residual
2F): each row's confidence times max(0, 1 - (residual - F) / F) beyond F.
With --by-range (the desk suite, pcl_icf_make_dataset --kind desk, whose groups name the
target's range band, D-r0.9-1.2-v50-75), the table at the accept threshold per range band
(an absent twin D_NNN_absent in its present twin's band) and, with --plot, one curve per band.
Python's standard library only (Debian's python3), gnuplot for the picture.
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile


def read_cases(paths):
    cases = []
    for path in paths:
        suite = os.path.basename(path).replace("_cases.csv", "")
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if row["method"] != "icf-scene":
                    continue
                conf = row.get("confidence", "")
                if conf == "":
                    conf = "0"
                absent = row["absent"] == "1"
                label = "absent" if absent else ("right" if row["success"] == "1" else "wrong")
                among = row.get("success_among_alternatives", "") == "1"
                cases.append({"suite": suite, "case": row["case"], "label": label,
                              "group": row["group"],
                              "confidence": float(conf), "terms": row.get("verification", ""),
                              "among_alternatives": among})
    return cases


def curve(cases, thresholds):
    present = sum(1 for c in cases if c["label"] != "absent")
    absent = sum(1 for c in cases if c["label"] == "absent")
    rows = []
    for t in thresholds:
        reported = [c for c in cases if c["confidence"] >= t]
        false_absent = sum(1 for c in reported if c["label"] == "absent")
        false_wrong = sum(1 for c in reported if c["label"] == "wrong")
        found = sum(1 for c in reported if c["label"] == "right")
        among = sum(1 for c in reported if c["label"] != "absent" and c["among_alternatives"])
        rows.append((t, false_absent, absent, false_wrong, found, present, among))
    return rows


def range_bands(cases):
    """{band: cases} from the desk suite's groups; absent twins join their present twin's."""
    band_of = {}
    for c in cases:
        if c["group"].startswith("D-r"):
            band_of[c["case"]] = c["group"][3:].rsplit("-v", 1)[0]
    bands = {}
    for c in cases:
        band = band_of.get(c["case"].replace("_absent", ""))
        if band:
            bands.setdefault(band, []).append(c)
    return dict(sorted(bands.items(), key=lambda kv: float(kv[0].split("-")[0])))


def by_range(cases, plot, threshold=0.875):
    bands = range_bands(cases)
    if not bands:
        sys.exit("confidence_curve: --by-range needs the desk suite's groups (D-r...)")
    print(f"| target range (m), threshold {threshold} | found (right pose) | wrong poses, "
          f"target present | false poses, target absent |")
    print("|---|---:|---:|---:|")
    for band, members in bands.items():
        (t, fa, na, fw, found, npres, _), = curve(members, [threshold])
        print(f"| {band} | {found}/{npres} | {fw}/{npres} | {fa}/{na} |")
    if not plot:
        return
    files, plots = [], []
    for band, members in bands.items():
        fine = sorted({0.0, 1.0} | {c["confidence"] for c in members})
        dat = tempfile.NamedTemporaryFile("w", suffix=".dat", delete=False)
        for t, fa, na, fw, found, npres, _ in curve(members, fine):
            dat.write(f"{(fa + fw) / max(1, na + npres)} {(npres - found) / max(1, npres)} {t}\n")
        dat.close()
        files.append(dat.name)
        colour = len(files)
        plots.append(f"'{dat.name}' using 1:2 with steps lw 2 lc {colour} title '{band} m'")
        plots.append(f"'-' using 1:2 with points pt 7 ps 1.4 lc {colour} notitle")
    inline = []
    for band, members in bands.items():
        t, fa, na, fw, found, npres, _ = curve(members, [threshold])[0]
        inline.append(f"{(fa + fw) / max(1, na + npres)} {(npres - found) / max(1, npres)}\ne")
    script = f"""
set terminal pngcairo size 720,520
set output '{plot}'
set xlabel 'false poses (absent target or wrong pose) per case'
set ylabel 'missed objects per present target'
set title 'Confidence threshold sweep per target range (dots: threshold {threshold})'
set grid
set key top right
plot {", ".join(plots)}
""" + "\n".join(inline) + "\n"
    subprocess.run(["gnuplot"], input=script, text=True, check=True)
    for name in files:
        os.unlink(name)


def residual_of(terms):
    for token in terms.split():
        if token.startswith("residual="):
            return float(token.split("=", 1)[1])
    return 0.0


def residual_sweep(cases, fits, threshold=0.875):
    print("| fit_residual (max_residual 2x) | false poses, target absent | wrong poses, target "
          "present | found (right pose) |")
    print("|---:|---:|---:|---:|")
    present = sum(1 for c in cases if c["label"] != "absent")
    absent = len(cases) - present
    for fit in fits:
        kept = {"absent": 0, "wrong": 0, "right": 0}
        for c in cases:
            r = residual_of(c["terms"])
            factor = 1.0 if r <= fit else max(0.0, 1.0 - (r - fit) / fit)
            if c["confidence"] * factor >= threshold:
                kept[c["label"]] += 1
        print(f'| {fit:.2f} | {kept["absent"]}/{absent} | {kept["wrong"]}/{present} | '
              f'{kept["right"]}/{present} |')


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", help="NAME_cases.csv files of icf-scene runs")
    ap.add_argument("--plot", help="write the curve as a PNG picture (gnuplot)")
    ap.add_argument("--list", action="store_true", help="print every case with its terms")
    ap.add_argument("--residual-sweep", action="store_true",
                    help="the table at 0.875 as fit_residual moves (rows measured with it off)")
    ap.add_argument("--by-range", action="store_true",
                    help="per target range band (the desk suite), one curve per band")
    args = ap.parse_args()
    cases = read_cases(args.csv)
    if not cases:
        sys.exit("confidence_curve: no icf-scene rows in " + ", ".join(args.csv))
    if args.by_range:
        by_range(cases, args.plot)
        return
    if args.residual_sweep:
        residual_sweep(cases, [1.0, 1.25, 1.5, 1.6, 1.75, 2.0, 2.25, 2.5, 3.0, float("inf")])
        return
    if args.list:
        for c in sorted(cases, key=lambda c: -c["confidence"]):
            print(f'{c["confidence"]:.3f} {c["label"]:7s} {c["case"]:40s} {c["terms"]}')
    thresholds = [i / 20 for i in range(21)]
    print("| threshold | false poses, target absent | wrong poses, target present | "
          "found (right pose) | right among the alternatives | missed |")
    print("|---:|---:|---:|---:|---:|---:|")
    for t, fa, na, fw, found, npres, among in curve(cases, thresholds):
        print(f"| {t:.2f} | {fa}/{na} | {fw}/{npres} | {found}/{npres} | {among}/{npres} | "
              f"{npres - found}/{npres} |")
    if args.plot:
        fine = sorted({0.0, 1.0} | {c["confidence"] for c in cases})
        with tempfile.NamedTemporaryFile("w", suffix=".dat", delete=False) as dat:
            for t, fa, na, fw, found, npres, _ in curve(cases, fine):
                false_rate = (fa + fw) / max(1, na + npres)
                miss_rate = (npres - found) / max(1, npres)
                dat.write(f"{false_rate} {miss_rate} {t}\n")
        script = f"""
set terminal pngcairo size 720,520
set output '{args.plot}'
set xlabel 'false poses (absent target or wrong pose) per case'
set ylabel 'missed objects per present target'
set title 'Confidence threshold sweep ({len(cases)} cases)'
set grid
set key off
plot '{dat.name}' using 1:2 with steps lw 2, '' using 1:2:(sprintf('%.2f',$3)) every 8 with labels offset 1,0.5 font ',8'
"""
        subprocess.run(["gnuplot"], input=script, text=True, check=True)
        os.unlink(dat.name)


if __name__ == "__main__":
    main()
