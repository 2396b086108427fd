#!/usr/bin/env python3
"""Compares two pcl_icf_bench output folders case by case: for every NAME_cases.csv in the first,
the rows of the same file in the second, column by column (time_ms and the free-text detail
left out). Prints per file the columns that differ and how often, with a few examples. Used to
show that a change leaves every pose and decision as it was, or which ones it moves.

  scripts/compare_bench_cases.py BEFORE_DIR AFTER_DIR
"""
import collections
import csv
import glob
import os
import sys


def main(before, after):
    differing = 0
    for path in sorted(glob.glob(os.path.join(before, '*_cases.csv'))):
        other = os.path.join(after, os.path.basename(path))
        if not os.path.exists(other):
            print('missing', other)
            differing += 1
            continue
        rows_a = list(csv.DictReader(open(path)))
        rows_b = list(csv.DictReader(open(other)))
        if len(rows_a) != len(rows_b):
            print(os.path.basename(path), 'row counts differ:', len(rows_a), len(rows_b))
            differing += 1
            continue
        counts, examples = collections.Counter(), []
        for a, b in zip(rows_a, rows_b):
            for key in a:
                if key in ('time_ms', 'detail') or a[key] == b.get(key):
                    continue
                counts[key] += 1
                if len(examples) < 6:
                    examples.append((a['case'], a['method'], key, a[key][:60], b.get(key, '')[:60]))
        print(os.path.basename(path), len(rows_a), 'rows', dict(counts))
        for e in examples:
            print('   ', e)
        differing += sum(counts.values())
    return 0 if differing == 0 else 1


if __name__ == '__main__':
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
